#pragma once
/// \file campaign_file.h
/// \brief A campaign file (YAML, docs/campaigns.md): its definition, the trial config its
/// trials share, and how one of its trials runs.

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <plantnbv/experiment/campaign.h>
#include <plantnbv/experiment/campaign_report.h>
#include <plantnbv/experiment/campaign_runner.h>
#include <plantnbv/experiment/result_store.h>
#include <plantnbv/experiment/trial.h>
#include <plantnbv/scenario/placed_plant.h>

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

/// \brief What the trials of one plant, pose and row of a campaign file share, made once
/// for them all: the placed plant, its neighbours and the sensor's scene (its BVH, the
/// largest part of a trial's setup). One cache serves one campaign file. Thread-safe:
/// workers that ask for the same entry together wait for one build. It keeps the entries
/// asked for last, up to its capacity.
class CampaignSceneCache {
public:
  /// \brief One plant, pose and row.
  struct Entry {
    PlacedPlant placed;          ///< the plant as its trials get it
    NeighbourPlants neighbours;  ///< its row (none without row spacing)
    SensorScene::ConstPtr scene; ///< makePlantScene of both, committed
    /// The maps after v0 of its trials (Trial::setInitialViewCache): trials that
    /// differ only in their planner or candidates start from one v0.
    InitialViewCache::Ptr initial_views;
  };

  /// \param[in] capacity entries kept (>= 1).
  explicit CampaignSceneCache(std::size_t capacity);
  ~CampaignSceneCache();

  /// \brief The entry of trial `t` of `f` (its config: campaignTrialConfig), made on the
  /// first call for its plant, variant, yaw, row and scene. \throws what making it
  /// throws, to the trials that wait for that build; a failed entry is not kept, and
  /// the next trial that asks makes it again.
  std::shared_ptr<const Entry> get(const CampaignFile& f, const TrialSpec& t,
                                   const TrialConfig& config);

  /// \brief Entries made so far (each at most once while kept).
  std::size_t builds() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// \brief Runs trial `t` of `f`: its own map, on one thread; its plant, neighbours and
/// scene from `cache` when given (the same results), else made for it alone (the scene
/// then outside the trial's setup_ms, as with the cache).
/// \throws the errors of the plant's files and of the trial.
void runCampaignTrial(const CampaignFile& f, const TrialSpec& t, TrialResult& result,
                      CampaignSceneCache* cache = nullptr);

/// \brief What a LocalRunner of `f`'s trials calls: runCampaignTrial with a
/// CampaignSceneCache of two entries, shared by the trials of one plant and pose (give
/// the runner the specs in groupTrialsByScene's order). Two keep the plant the workers
/// are on and the next one; a scene a running trial holds lives on outside the cache, so
/// the cache adds at most two scenes to what the trials hold. `f` must outlive it.
LocalRunner::TrialFunction campaignTrialFunction(const CampaignFile& f);

/// \brief `specs` reordered so that the trials of one plant, variant, yaw and row follow
/// one another (otherwise in their order): what a CampaignSceneCache makes for them is
/// made once. The results do not depend on the order.
void groupTrialsByScene(std::vector<TrialSpec>& specs);

/// \brief A campaign directory's counts against the campaign.yaml it holds (`campaign
/// status`, Python's campaign_status); `file`, if not null, receives that file.
/// \throws FileNotFoundError when DIR holds no campaign.yaml; as loadCampaignFile.
StoreStatus campaignDirectoryStatus(const std::filesystem::path& dir,
                                    CampaignFile* file = nullptr);

/// \brief Where a campaign directory's done trials spend their time (campaignTiming of
/// its campaign's done trials: `campaign status --timing`, Python's campaign_timing).
/// \throws as campaignDirectoryStatus; FormatError naming a done trial's file that
/// ResultStore::loadFile refuses.
std::vector<TimingRow> campaignDirectoryTiming(const std::filesystem::path& dir);

} // namespace scenario
} // namespace plantnbv
