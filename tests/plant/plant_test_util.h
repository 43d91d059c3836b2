#pragma once
// Shared by the plant tests: a stable mesh hash and the default plants, generated once
// per test process.

#include <cstdint>
#include <cstring>
#include <memory>

#include <plantnbv/plant/tomato_plant_generator.h>

namespace plantnbv {
namespace test {

/// FNV-1a over the bytes of every vertex, triangle and label, in order.
inline std::uint64_t meshHash(const TriangleMesh& mesh)
{
  std::uint64_t h = 0xcbf29ce484222325ULL;
  auto add = [&h](const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i)
      h = (h ^ p[i]) * 0x100000001b3ULL;
  };
  for (const auto& v : mesh.vertices)
    add(v.data(), 3 * sizeof(float));
  for (const auto& t : mesh.triangles)
    add(t.data(), 3 * sizeof(std::uint32_t));
  for (const auto& l : mesh.labels)
    add(&l, sizeof(l));
  return h;
}

/// Default plant `index` (0-9), generated on first use.
inline const Plant& defaultPlant(int index, bool simplified = false)
{
  static std::unique_ptr<Plant> cache[2][kDefaultPlantCount];
  auto& slot = cache[simplified ? 1 : 0][index];
  if (!slot)
    slot = std::make_unique<Plant>(
        TomatoPlantGenerator(defaultPlantConfig(index, simplified)).generate());
  return *slot;
}

} // namespace test
} // namespace plantnbv
