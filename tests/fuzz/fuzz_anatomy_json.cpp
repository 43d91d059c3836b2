// Plant anatomy JSON (anatomy.json): anatomyFromJson.
#include <plantnbv/plant/anatomy_json.h>

#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  plantnbv::fuzz::run([&] {
    plantnbv::Plant plant;
    plantnbv::anatomyFromJson(text, plant);
  });
  return 0;
}
