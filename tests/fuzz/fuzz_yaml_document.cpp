// Any YAML document through the checks every reader of ours relies on (io::YamlReader::
// parse: alias cycles, nesting, alias expansion, repeated keys), then the two walks
// that follow aliases: the canonical text (campaign fingerprints) and describe (error
// messages).
#include <plantnbv/io/yaml_reader.h>

#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  plantnbv::fuzz::run([&] {
    const plantnbv::io::YamlReader reader("fuzz/document.yaml");
    const YAML::Node root = reader.parse(text);
    plantnbv::io::YamlReader::canonical(root);
    plantnbv::io::YamlReader::describe(root);
  });
  return 0;
}
