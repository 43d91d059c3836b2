// OBJ, STL and Collada meshes: io::loadMesh through Assimp, with our Collada unit and
// up-axis handling and our checks before Assimp. The first byte picks the format and
// the up-axis option; the rest is the file.
#include <plantnbv/io/mesh_io.h>

#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  if (size < 1)
    return 0;
  plantnbv::fuzz::useSmallLimits();
  static const char* const kExtensions[] = {".obj", ".stl", ".dae"};
  using Up = plantnbv::io::MeshLoadOptions::UpAxis;
  plantnbv::io::MeshLoadOptions options;
  options.up_axis = data[0] & 0x10 ? Up::y : data[0] & 0x20 ? Up::z : Up::from_file;
  const std::string path =
      plantnbv::fuzz::writeInput(data + 1, size - 1, kExtensions[(data[0] & 0x0f) % 3]);
  plantnbv::fuzz::run([&] { plantnbv::io::loadMesh(path, options); });
  return 0;
}
