// ROI files (YAML boxes): io::loadRoi.
#include <plantnbv/io/roi_io.h>

#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  plantnbv::fuzz::useSmallLimits();
  const std::string path = plantnbv::fuzz::writeInput(data, size, ".yaml");
  plantnbv::fuzz::run([&] { plantnbv::io::loadRoi(path); });
  return 0;
}
