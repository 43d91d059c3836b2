// VRML97 meshes: io::loadMesh with our VRML reader (DEF/USE, transforms, primitives).
#include <plantnbv/io/mesh_io.h>

#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  plantnbv::fuzz::useSmallLimits();
  const std::string path = plantnbv::fuzz::writeInput(data, size, ".wrl");
  plantnbv::fuzz::run([&] { plantnbv::io::loadMesh(path); });
  return 0;
}
