#pragma once
/// \file synthetic_plant.h
/// \brief A plant-shaped test mesh (stem, petioles, leaflets, fruits) with part labels,
/// for tests and benchmarks until the procedural tomato generator of module plant/
/// exists.

#include <cstdint>

#include <plantnbv/common/triangle_mesh.h>

namespace plantnbv {
namespace test {

struct SyntheticPlantConfig {
  double stem_height_m = 0.6;
  double stem_radius_m = 0.005;
  int leaves = 8;
  int leaflets_per_leaf = 5;
  int fruits = 3;
  /// Subdivision of every part: higher gives more triangles (default about 25k).
  int detail = 24;
  std::uint64_t seed = 0; ///< varies leaf lengths and droop
};

/// \brief The mesh, base at the origin, stem along +Z, labels and node names set.
TriangleMesh makeSyntheticPlant(const SyntheticPlantConfig& config = {});

} // namespace test
} // namespace plantnbv
