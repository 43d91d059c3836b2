// Collada text through the checks made before Assimp sees a file (io::checkColladaText:
// node graphs with <instance_node> cycles, deep nesting or exploding instances; arrays,
// accessors and index lists): fast, so the node-graph walk is fuzzed far more often than
// through mesh_assimp, where each input also goes through Assimp.
#include <plantnbv/io/mesh_io.h>

#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  plantnbv::fuzz::run([&] { plantnbv::io::checkColladaText("fuzz/scene.dae", text); });
  return 0;
}
