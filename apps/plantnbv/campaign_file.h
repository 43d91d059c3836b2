#pragma once
// A campaign file (YAML): its definition, the trial config its trials share, and how one
// of its trials runs. Shared by the campaign commands and the campaign-file fuzz target.

#include <filesystem>
#include <string>

#include <plantnbv/experiment/campaign.h>
#include <plantnbv/experiment/trial.h>

namespace plantnbv {
namespace app {

/// A campaign file: the definition, the trial config shared by its trials and the
/// directory its relative paths are relative to.
struct CampaignFile {
  std::string path;
  std::string text;
  CampaignDefinition definition;
  TrialConfig base; ///< the `trial:` section over the built-in defaults
  std::filesystem::path base_dir;
};

/// Reads and checks a campaign file (keys in data/campaigns/paper.yaml and
/// docs/campaigns.md). `name_for_messages` names the file in errors.
/// \throws IoError if it cannot be read; FormatError naming the key path for an unknown
/// key, a wrong type or an impossible value; InvalidArgumentError naming the trial for a
/// trial config that does not validate.
CampaignFile loadCampaignFile(const std::string& path,
                              const std::string& name_for_messages);

/// The same, from the file's text; `path` is only where relative paths start from.
/// \throws as loadCampaignFile, but no IoError (nothing is read).
CampaignFile parseCampaignFile(const std::string& text, const std::string& path,
                               const std::string& name_for_messages);

/// The config of one trial of `f` (without a model's sector height, which needs the
/// plant).
TrialConfig campaignTrialConfig(const CampaignFile& f, const TrialSpec& t);

/// Runs trial `t` of `f`: its own plant, scene and map, on one thread.
void runCampaignTrial(const CampaignFile& f, const TrialSpec& t, TrialResult& result);

} // namespace app
} // namespace plantnbv
