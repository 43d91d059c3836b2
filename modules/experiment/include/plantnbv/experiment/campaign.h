#pragma once
/// \file campaign.h
/// \brief A campaign: many trials over plants, yaws, planners and study variants (the
/// paper's section 3 study and its sensitivity analyses), expanded into a list of trial
/// specifications with stable ids and seeds.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <plantnbv/experiment/trial.h>

namespace plantnbv {

/// \brief A plant of a campaign: generated from a seed, or a model file (paths are
/// kept as given; the app loads them).
struct CampaignPlant {
  std::string name;                     ///< in trial ids: "plant03" or the model's name
  std::optional<std::uint64_t> seed;    ///< a generated tomato plant
  std::optional<double> stage;          ///< its growth stage (default: the generator's)
  bool simplified = false;              ///< half of the leaflets removed
  std::string model;                    ///< or a mesh / cloud file
  std::vector<std::string> model_parts; ///< further mesh files of the model
  std::string labels;                   ///< part label rules of a mesh model
  double scale = 0.0;                   ///< a model's metres per file unit; 0: the file's
  std::string up_axis = "file";         ///< a model's up axis: file, y or z (mesh_io.h)
  std::string rois;                     ///< ROI file of a model
  /// A model kept in its file's coordinates (no base, no yaw: the campaign's yaws_deg
  /// must be [0]), so that boxes drawn in that frame (rois, attention files) match it.
  bool keep_frame = false;
  /// The sector radius for this plant (metres); unset: the trial config's (0.4 m).
  std::optional<double> sector_radius_m;
};

/// \brief A planner of a study: NBV with an attention ROI, pre-defined with its
/// patterns (one trial per pattern, averaged as one planner in the report), or random.
struct CampaignPlanner {
  std::string name;                    ///< e.g. "nbv-leaf-nodes"; in trial ids
  PlannerKind kind = PlannerKind::nbv; ///< nbv, predefined or random
  std::string attention; ///< nbv: whole-plant, main-stem, leaf-nodes, fruit or a ROI file
  std::vector<int> patterns; ///< predefined: 1-4 each
  /// nbv: where its ROI comes from; unset: the trial section's (oracle by default).
  std::optional<RoiSource> roi_source;
};

/// \brief A study: planners run on every plant and yaw, over the variants its lists
/// give (each list left empty takes the campaign's value: one variant).
struct CampaignStudy {
  std::string name; ///< "main", "occlusion", ...; first part of trial ids
  std::vector<CampaignPlanner> planners; ///< each runs on every plant, yaw and variant
  std::vector<bool> simplified;          ///< plants with half of their leaflets removed
  std::vector<int> candidates; ///< candidates per step (multiples of the grid cells)
  std::vector<double> resolutions_m; ///< map resolution = rho
  /// Greenhouse rows: the distance of a neighbour on each side (metres; 0: the plant
  /// alone; scenario::rowNeighbours).
  std::vector<double> row_spacings_m;
};

/// \brief A whole campaign (plain values; apps read it from YAML).
struct CampaignDefinition {
  std::string name;                  ///< names the campaign in reports
  std::uint64_t seed = 0;            ///< trial seeds derive from it and the trial id
  std::vector<CampaignPlant> plants; ///< every study runs on each
  std::vector<double> yaws_deg{0.0}; ///< turns of each plant about its stem
  int views = 10;                    ///< view budget, v0 included
  int candidates = 27;         ///< candidates per step, unless a study lists its own
  double resolution_m = 0.003; ///< map resolution = rho (metres), unless a study lists
  int repetitions = 1;         ///< trials per plant, yaw and variant, with other seeds
  std::vector<std::string> levels;    ///< evaluation levels; empty: all the plant has
  std::vector<CampaignStudy> studies; ///< the studies, in order
  /// What the campaign file says, hashed (contentFingerprint of its canonical text:
  /// comments, key order and quoting do not change it); set by the file's reader, empty
  /// for a definition built in code. Part of every trial's fingerprint.
  std::string content_fingerprint;

  /// \throws InvalidArgumentError naming the field by its path (e.g.
  /// "studies[1].planners[0].patterns[2]") and the bad value.
  void validate() const;
};

/// \brief One trial of a campaign.
struct TrialSpec {
  /// Stable and readable: study/planner[-pK]/[variant/]plant/yawDDD/repR, e.g.
  /// "main/nbv-leaf-nodes/plant03/yaw090/rep0", "main/predefined-p2/plant03/yaw090/rep0",
  /// "candidates/nbv-leaf-nodes/c45/plant03/yaw090/rep0",
  /// "row/random/row25cm/plant03/yaw090/rep0" ("alone" for a row spacing of 0).
  std::string id;
  std::string study;   ///< CampaignStudy::name
  std::string variant; ///< e.g. "c45", "res5mm", "simplified"; empty for one variant
  std::string planner; ///< the planner's name (patterns of one predefined share it)
  PlannerKind kind = PlannerKind::nbv; ///< nbv, predefined or random
  std::string attention;               ///< nbv only
  std::optional<RoiSource> roi_source; ///< nbv only; unset: the trial section's
  int pattern = 0;                     ///< predefined only, 1-4
  std::size_t plant_index = 0;         ///< into CampaignDefinition::plants
  std::string plant;                   ///< its name
  bool simplified = false;             ///< half of the plant's leaflets removed
  double yaw_deg = 0.0;                ///< the plant's turn about its stem, degrees
  int repetition = 0;                  ///< 0, 1, ... (CampaignDefinition::repetitions)
  int candidates = 27;                 ///< candidates per step
  double resolution_m = 0.003;         ///< map resolution = rho (metres)
  double row_spacing_m = 0.0;          ///< neighbours this far on each side; 0: none
  int views = 10;                      ///< view budget, v0 included
  std::uint64_t seed = 0;              ///< deriveSeed(campaign seed, hash of the id)
  /// What determines the trial's result, hashed: the campaign's content_fingerprint,
  /// the id and the seed. Its result file carries it; a file whose fingerprint differs
  /// is another campaign's and is not taken as this trial's result.
  std::string fingerprint;
};

/// \brief FNV-1a, 64 bits, of a trial id (stable across platforms and runs).
std::uint64_t trialIdHash(const std::string& id);

/// \brief FNV-1a, 64 bits, of `text` as 16 lower-case hex digits (stable across
/// platforms and runs; it tells results apart, it is no protection against forgery).
std::string contentFingerprint(const std::string& text);

/// \brief The most trials a campaign may expand to (the paper's study has 2,760; each
/// trial is one result file): a few lines of YAML (repetitions: 2000000000) must not
/// exhaust memory.
constexpr std::size_t kMaxCampaignTrials = 100'000;

/// \brief All trials of the campaign, study by study, in a fixed order. Ids are unique
/// and seeds depend only on the campaign seed and the id.
/// \throws InvalidArgumentError if the definition is invalid or expands to more than
/// kMaxCampaignTrials trials.
std::vector<TrialSpec> expandCampaign(const CampaignDefinition& definition);

} // namespace plantnbv
