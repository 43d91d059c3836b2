#pragma once
/// \file campaign_file.h
/// \brief A campaign file (YAML, docs/campaigns.md): its definition, the trial config its
/// trials share, and how one of its trials runs.

#include <filesystem>
#include <string>

#include <plantnbv/experiment/campaign.h>
#include <plantnbv/experiment/result_store.h>
#include <plantnbv/experiment/trial.h>

namespace plantnbv {
namespace scenario {

/// \brief A campaign file: the definition, the trial config its trials share and the
/// directory its relative paths (models, ROI files) are relative to.
struct CampaignFile {
  std::string path;               ///< the file, as given
  std::string text;               ///< as read (the result store keeps it)
  CampaignDefinition definition;  ///< plants, yaws, studies, planners
  TrialConfig base;               ///< the `trial:` section over the built-in defaults
  std::filesystem::path base_dir; ///< relative paths in the file are relative to this
};

/// \brief Reads and checks a campaign file (keys in data/campaigns/paper.yaml and
/// docs/campaigns.md); every trial's config is validated. The definition's
/// content_fingerprint hashes the file's canonical text and the resolved trial config
/// (trialConfigText of `base`), so that the same file run under other built-in defaults
/// is another campaign, whose results are not taken for this one's.
/// \throws IoError if it cannot be read; FormatError naming the file and the key path for
/// an unknown key, a wrong type or an impossible value; InvalidArgumentError naming the
/// trial for a trial config that does not validate.
CampaignFile loadCampaignFile(const std::string& path);

/// \brief The same from the file's text; `path` names it in messages and is where
/// relative paths start from. `defaults`: the trial config the `trial:` section
/// overrides (the built-in one unless given). \throws as loadCampaignFile, but no
/// IoError.
CampaignFile parseCampaignFile(const std::string& text, const std::string& path,
                               const TrialConfig& defaults = TrialConfig());

/// \brief The config of trial `t` of `f` (without a model's sector height, which needs
/// the plant: fitSectorToPlant). One thread: campaigns run one trial per worker.
TrialConfig campaignTrialConfig(const CampaignFile& f, const TrialSpec& t);

/// \brief Runs trial `t` of `f`: its own plant, scene and map, on one thread.
/// \throws the errors of the plant's files and of the trial.
void runCampaignTrial(const CampaignFile& f, const TrialSpec& t, TrialResult& result);

/// \brief A campaign directory's counts against the campaign.yaml it holds (`campaign
/// status`, Python's campaign_status); `file`, if not null, receives that file.
/// \throws FileNotFoundError when DIR holds no campaign.yaml; as loadCampaignFile.
StoreStatus campaignDirectoryStatus(const std::filesystem::path& dir,
                                    CampaignFile* file = nullptr);

} // namespace scenario
} // namespace plantnbv
