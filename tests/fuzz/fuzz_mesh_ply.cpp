// PLY meshes: io::loadMesh with our PLY reader (face labels, lists, ASCII and binary).
#include <plantnbv/io/mesh_io.h>

#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  plantnbv::fuzz::useSmallLimits();
  const std::string path = plantnbv::fuzz::writeInput(data, size, ".ply");
  plantnbv::fuzz::run([&] { plantnbv::io::loadMesh(path); });
  return 0;
}
