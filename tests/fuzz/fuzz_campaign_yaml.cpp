// Campaign files (YAML, with a trial config section): scenario::parseCampaignFile, the
// parser behind `plantnbv campaign run FILE`.
#include <plantnbv/scenario/campaign_file.h>

#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const std::string text(reinterpret_cast<const char*>(data), size);
  plantnbv::fuzz::run([&] {
    plantnbv::scenario::parseCampaignFile(text, "fuzz/campaign.yaml");
  });
  return 0;
}
