#pragma once
/// \file trial_setup.h
/// \brief How a trial is set up from a placed plant, the same for `reconstruct`, the
/// campaigns and Python: its evaluation levels, the planner's attention ROI, the sector
/// that follows a loaded model, the candidate count.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <plantnbv/common/roi_kind.h>
#include <plantnbv/experiment/reconstruction_evaluator.h>
#include <plantnbv/experiment/trial.h>
#include <plantnbv/scenario/placed_plant.h>

namespace plantnbv {
namespace scenario {

/// \brief The level name of a model's own ROI file (each box scored on its own).
constexpr const char* kModelRoisLevel = "model_rois";

/// \brief What an NBV planner attends to: a kind of the plant's ROIs, or an ROI file.
struct Attention {
  std::optional<RoiKind> kind; ///< set: the plant's ROI of this kind
  std::string file;            ///< otherwise: an ROI file (YAML boxes, world frame)

  /// \brief A kind by any accepted name (roi_kind.h), or a file (a name with an
  /// extension). \throws InvalidArgumentError "unknown ROI 'x' (expected ...)" for
  /// anything else.
  static Attention parse(const std::string& name);
  /// \brief The kind's name, or the file.
  std::string name() const;
};

/// \brief The planner name campaigns give an NBV planner: "nbv-leaf-nodes" for a kind
/// (the paper's planner names), "nbv-<file stem>" for an ROI file; with a noisy ROI
/// source, its sigma in millimetres and a scale other than 1 follow:
/// "nbv-leaf-nodes-noisy10mm", "nbv-leaf-nodes-noisy0mm-x1.5"; with detections, a recall
/// other than 1 and false positives: "nbv-leaf-nodes-detections-recall0.8-fp2"; with the
/// prior, an internode other than the default: "nbv-leaf-nodes-prior-internode50mm",
/// "nbv-leaf-nodes-detections-prior-recall0.5".
std::string nbvPlannerName(const Attention& attention, const RoiSource& source = {});

/// \brief The attention ROI on the placed plant. \throws InvalidArgumentError if the
/// plant has no ROI of that kind; the io errors of an ROI file.
Roi attentionRoi(const PlacedPlant& placed, const Attention& attention);

/// \brief The levels the plant has ROIs for, in kRoiKinds order, then model_rois.
std::vector<EvaluationLevel> evaluationLevels(const PlacedPlant& placed);

/// \brief A canonical level name (a RoiKind's, or model_rois) for any accepted spelling.
/// \throws InvalidArgumentError for an unknown level.
std::string canonicalLevelName(const std::string& name);

/// \brief Sets config.samples_per_cell so that the sector gives `candidates` per step.
/// \throws InvalidArgumentError unless `candidates` is a positive multiple of the
/// sector's grid cells; `what` names the value in the message ("--candidates").
void setCandidateCount(int candidates, const std::string& what, TrialConfig& config);

/// \brief The rule for loaded models, which may be taller than the paper's plants (0.7 m
/// sector for plants of at most 0.7 m): unless `sector_height_m` is given, a model's
/// sector is as high as the model stands above its base (at least 0.05 m); a generated
/// plant keeps the config's sector.
void fitSectorToPlant(const PlacedPlant& placed, std::optional<double> sector_height_m,
                      TrialConfig& config);

/// \brief What `--roi-source`, `--roi-sigma`, `--roi-scale`, `--detector-recall`,
/// `--detector-false-positives`, `--detector-box-jitter`, `--detector-mask-dilation`,
/// `--detector-masks`, `--prior-internode` and `--detections-explore-views`
/// (reconstruct; plan those of the noisy, prior and detections sources) and Python's
/// keywords of the same names set over a config's RoiSource.
struct RoiSourceOverrides {
  std::optional<std::string> source;              ///< oracle, noisy, detections
  std::optional<double> sigma_m;                  ///< RoiSource::sigma_m
  std::optional<double> scale;                    ///< RoiSource::scale
  std::optional<double> detector_recall;          ///< RoiSource::detector_recall
  std::optional<double> detector_false_positives; ///< per frame
  std::optional<double> detector_box_jitter_px;   ///< RoiSource::detector_box_jitter_px
  std::optional<int> detector_mask_dilation_px;   ///< RoiSource::..._mask_dilation_px
  std::optional<bool> detector_masks;             ///< RoiSource::detector_masks
  std::optional<double> prior_internode_m;        ///< RoiSource::prior_internode_m
  std::optional<int> detections_explore_views;    ///< RoiSource::detections_explore_views

  /// \brief Sets what is given over `roi` and validates it. Messages name the overrides
  /// as `option_prefix` + "roi-source" etc. (or the config keys without a prefix).
  /// \throws InvalidArgumentError as roiSourceKindFromName and RoiSource::validate.
  void applyTo(RoiSource& roi, const std::string& option_prefix) const;
};

/// \brief What `plantnbv reconstruct` and Python's run_trial set over a trial config
/// file; what is unset keeps the file's value, or the built-in default.
struct TrialOverrides {
  std::string config_file; ///< a trial config (loadTrialConfig); empty: the defaults
  std::optional<std::string> planner;     ///< nbv, predefined, random
  std::optional<int> pattern;             ///< the predefined planner's pattern, 1-4
  std::optional<int> views;               ///< view budget, v0 included
  std::optional<int> candidates;          ///< per step, a multiple of the grid cells
  std::optional<double> resolution_m;     ///< map resolution = rho, metres
  std::optional<double> sector_height_m;  ///< else fitSectorToPlant's rule
  std::optional<double> sector_radius_m;  ///< else the config's (0.4 m)
  std::optional<std::uint64_t> seed;      ///< the trial's seed
  std::optional<int> threads;             ///< 0: OpenMP's default
  std::optional<double> depth_scale;      ///< TrialConfig::depth_scale
  std::optional<CameraIntrinsics> camera; ///< the simulated sensor's
  std::optional<bool> noise;              ///< the sensor's depth noise on or off
  std::optional<bool> background;         ///< floor and support in the scene, or not
  RoiSourceOverrides roi;                 ///< where the attention ROI comes from
};

/// \brief The trial config of `placed`: the file, the overrides, the sector fitted to
/// the plant, validated. Messages name an override as `option_prefix` + its name
/// ("--" for the command line: "--candidates", "--roi-sigma").
/// \throws InvalidArgumentError for a pattern with a planner other than predefined (it
/// would be ignored); as loadTrialConfig, setCandidateCount, RoiSource::validate and
/// TrialConfig::validate.
TrialConfig makeTrialConfig(const TrialOverrides& overrides, const PlacedPlant& placed,
                            const std::string& option_prefix = "");

/// \brief What a user should hear before a trial runs, one line each: a map resolution
/// that gives fewer than 2 voxels across the smallest side of a level's boxes (its
/// scores say little), and an NBV attention ROI none of whose boxes meets the plant's
/// bounding box (the planner would attend to empty space). Empty when neither holds.
std::vector<std::string> trialWarnings(const PlacedPlant& placed,
                                       const TrialConfig& config, const Roi& attention,
                                       const std::vector<EvaluationLevel>& levels);

/// \brief The neighbours of `placed` in a greenhouse row, `spacing_m` from it on each
/// side across the direction the config's sector faces (rowNeighbours), for
/// Trial::setNeighbours; none for a spacing of 0.
/// \throws InvalidArgumentError as rowNeighbours (a negative spacing among them).
NeighbourPlants rowNeighbourPlants(const PlacedPlant& placed, double spacing_m,
                                   const TrialConfig& config);

/// \brief Gives `trial` the plant, the attention ROI, the levels and, as its exploration
/// region, the plant's whole-plant ROI.
void setUpTrial(const PlacedPlant& placed, const Roi& attention,
                const std::vector<EvaluationLevel>& levels, Trial& trial);

} // namespace scenario
} // namespace plantnbv
