#pragma once
/// \file trial.h
/// \brief One reconstruction trial (the paper's Algorithm 1 with evaluation): capture at
/// v0, then plan -> capture -> insert up to the view budget, scoring the map against
/// ground truth after every view.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/camera/depth_image.h>
#include <plantnbv/camera/detection.h>
#include <plantnbv/common/box.h>
#include <plantnbv/common/error.h>
#include <plantnbv/common/memory_cap.h>
#include <plantnbv/common/pose.h>
#include <plantnbv/experiment/initial_view_cache.h>
#include <plantnbv/experiment/plant_scene.h>
#include <plantnbv/experiment/reconstruction_evaluator.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/planning/cylindrical_sector_sampler.h>
#include <plantnbv/planning/information_gain.h>
#include <plantnbv/plant/plant.h>
#include <plantnbv/sensor/noise_model.h>
#include <plantnbv/session/active_vision_session.h>
#include <plantnbv/session/roi_source.h>

namespace plantnbv {

/// \brief The planners of the paper (section 3.2).
enum class PlannerKind {
  nbv,        ///< AttentionNbvPlanner: arg max of the gain inside the attention ROI
  predefined, ///< PredefinedPlanner: the 9 grid-cell centres in one of 4 patterns
  random,     ///< RandomPlanner: one of the freshly sampled candidates
};
/// \brief "nbv", "predefined" or "random" (the names configs and trial ids use).
const char* plannerKindName(PlannerKind kind);
/// \throws InvalidArgumentError naming the string and the accepted names.
PlannerKind plannerKindFromName(const std::string& name);

/// \brief The paper's base of the plant (Table 1); TrialConfig::initial_view is given
/// for a plant standing there.
inline Eigen::Vector3d paperPlantBase()
{
  return {1.0, 0.0, 0.8};
}

/// \brief Everything a trial needs besides the plant and the ROIs. Defaults: the paper's
/// Table 1 (data/paper.yaml), the L515 at 640 x 480, noise off.
struct TrialConfig {
  /// The simulated camera's image size, pinhole model and range limits.
  CameraIntrinsics camera = CameraIntrinsics::l515(L515Mode::vga_640x480);
  /// Off by default (the paper's sensor was noise-free); its seed is derived from `seed`.
  NoiseConfig noise;
  /// Depth units per metre of the camera's depth images, as a 16-bit PNG stores them
  /// (1000: millimetres). 0 (default, the paper's sensor): the map takes the sensor's
  /// points as they are. > 0: every frame's depth is rounded to these units and the map
  /// takes the frame as a robot's would come (ActiveVisionSession::integrate of the
  /// depth image), so that the frames a trial writes replay to its map bit for bit.
  double depth_scale = 0.0;
  PlantSceneConfig scene;   ///< floor and support by default
  OccupancyMap::Config map; ///< resolution (= rho), sensor model, max range

  PlannerKind planner = PlannerKind::nbv; ///< which planner chooses the views
  int pattern = 1;                        ///< predefined planner's pattern, 1-4
  /// What the planner attends to, from the attention ROI it is given (the plant's true
  /// boxes in a trial): oracle (the paper's), noisy (seeded from `seed`), or detections:
  /// a SimulatedDetector of the given quality finds the attention ROI's boxes in every
  /// frame (class: the boxes' name without its number, "leaf_node"), and
  /// DetectionFusion's boxes are the ROI of the next plan (empty before the first find:
  /// every voxel counts); prior: LeafNodePrior's boxes along the stem the map shows;
  /// detections+prior: both, the prior anchored on the detections.
  RoiSource roi_source;
  /// The cylindrical sector; its axis_base is replaced by the plant's base, so that the
  /// sector moves with the plant.
  CylindricalSector sector;
  int grid_rows = 3;        ///< sector grid rows (along z), >= 1
  int grid_cols = 3;        ///< sector grid columns (along the arc), >= 1
  int samples_per_cell = 3; ///< 1, 3, 5 give the paper's 9, 27, 45 candidates
  /// Ray grid and range of the gain; its fields of view are replaced by the camera's.
  GainConfig gain;
  /// AttentionNbvPlanner: stop when the best gain is below this (bits); 0 never stops.
  double stop_gain_bits = 0.0;
  /// AttentionNbvPlanner: explore the Trial's exploration region once the best gain in
  /// the ROI falls below this share of its largest (AttentionNbvPlanner::setExploration);
  /// in [0, 1], 0 (default, the paper's) never explores.
  double explore_share = 0.0;
  /// AttentionNbvPlanner: a candidate closer than this to an earlier view is chosen only
  /// when every candidate is (AttentionNbvPlanner::setViewSpacing); metres, 0 (the
  /// paper's): none.
  double view_spacing_m = kDefaultViewSpacingM;

  /// v0 (Table 1) for a plant whose base is at paperPlantBase(); it is translated with
  /// the plant's base, so that every planner starts from the same view of the plant.
  Viewpoint initial_view =
      Pose::fromXyzQuat(0.646, 0.353, 1.383, 0.0, 0.0, -0.383, 0.924);
  int views = 10;         ///< the view budget, v0 included
  std::uint64_t seed = 0; ///< the trial's seed (planner draws, noise, ground truth)
  int threads = 0;        ///< 0: OpenMP's default; results do not depend on it
  /// Wall-clock limit of one run() in seconds; 0: none. Checked after setup and after
  /// every view, so a trial overruns it by at most one view's time.
  double time_limit_s = 0.0;
  /// validate() refuses a config whose estimatedMemoryBytes() exceed this.
  double memory_cap_bytes = kDefaultMemoryCapBytes;

  /// \brief An upper estimate of the memory a trial needs, in bytes: one view into the
  /// map (estimatedViewMemoryBytes: views overlap, so a whole trial's map stays near it)
  /// and the gain's rays (estimatedGainMemoryBytes).
  double estimatedMemoryBytes() const;

  /// \throws InvalidArgumentError naming the first bad field and its value (NaN and
  /// infinities included), or the memory estimate when it is over memory_cap_bytes.
  void validate() const;
};

/// \brief The seed of a trial's ground-truth sampling (MeshSampler) for the trial seed
/// `trial_seed`: `plantnbv sample --seed` or `eval --seed` with it draws the trial's
/// surface samples (docs/trials.md, "Ground truth").
std::uint64_t groundTruthSeed(std::uint64_t trial_seed);

/// \brief The seed of a trial's ROI source (RoiSource::apply) for the trial seed
/// `trial_seed`; `plantnbv plan --seed S` draws a noisy ROI from roiSourceSeed(S).
std::uint64_t roiSourceSeed(std::uint64_t trial_seed);

/// \brief The session part of a trial config: map, sector, grid, gain, seed, threads
/// (the sector's axis as in the config; a Trial puts it at the plant's base).
ActiveVisionSession::Config sessionConfigOf(const TrialConfig& config);

/// \brief Thrown by Trial::run when TrialConfig::time_limit_s has passed.
class TimeLimitError : public Error {
public:
  using Error::Error;
};

/// \brief What happened at one view.
struct TrialStep {
  int index = 0;     ///< 0 = v0
  Viewpoint view;    ///< the camera body pose of this view (world frame)
  double gain = 0.0; ///< the chosen view's gain (bits); NaN for v0
  /// Of the voxels the chosen view's gain counted in the ROI, the unknown ones (0 for
  /// v0): a gain made of known voxels re-observes what the map has seen.
  std::size_t unknown_seen = 0;
  std::size_t candidates = 0;      ///< the candidates the view was chosen from; 0 for v0
  double plan_ms = 0.0;            ///< 0 for v0
  double capture_ms = 0.0;         ///< rendering the depth frame
  double insert_ms = 0.0;          ///< integrating it into the map
  double eval_ms = 0.0;            ///< scoring the map against ground truth
  std::size_t occupied_voxels = 0; ///< in the whole map after this view
  std::vector<LevelScore> scores;  ///< per evaluation level, in the Trial's order
  std::vector<OrganRecall> organs; ///< recall per organ of the whole plant
};

/// \brief A frame as the trial integrated it (TrialConfig::depth_scale > 0: rounded).
struct TrialFrame {
  int index = 0; ///< the view's index, 0 = v0
  Pose T_W_O;    ///< the camera's optical frame, exactly as integrated
  const DepthImage* depth = nullptr; ///< valid during the callback
  /// The simulated detector's detections of the frame (roi_source detections), else
  /// null; valid during the callback.
  const std::vector<Detection>* detections = nullptr;
};

/// \brief The outcome of Trial::run.
struct TrialResult {
  std::vector<std::string> level_names; ///< the evaluation levels, in order
  std::vector<TrialStep> steps;         ///< one per view, v0 first
  bool stopped_early = false; ///< the NBV planner's gain fell below stop_gain_bits
  double setup_ms = 0.0;      ///< scene (BVH; not when given: setScene), ground truth
  double total_ms = 0.0;      ///< setup and all steps

  /// \brief F1 after each view for level `level` (index into level_names).
  std::vector<double> f1Curve(std::size_t level) const;
};

/// \brief One trial on one posed plant.
///
/// \code
/// Trial trial(config);
/// trial.setPlant(plant);                           // posed in the world frame
/// trial.setAttentionRoi(leafNodeRoi(plant));       // what the NBV planner attends to
/// trial.setEvaluationLevels(levels);
/// TrialResult result;
/// trial.run(result);
/// \endcode
/// The planner sees only the map, the attention ROI and the candidates; the plant is
/// used for the sensor's scene and for ground truth (docs/architecture.md).
/// Deterministic: the same config, plant and seed give the same steps (apart from the
/// timings) on any number of threads.
class Trial {
public:
  /// \brief A trial with `config` and an empty map. \throws InvalidArgumentError if the
  /// config is invalid.
  explicit Trial(const TrialConfig& config = {});
  ~Trial();

  /// \throws InvalidArgumentError if the config is invalid.
  void setConfig(const TrialConfig& config);
  /// \brief The configuration of the next run().
  const TrialConfig& getConfig() const { return config_; }
  /// \brief The plant, posed in the world frame: the sensor's scene and the ground
  /// truth (not copied; it must not change during run()).
  void setPlant(std::shared_ptr<const Plant> plant);
  /// \brief Plants beside it (a greenhouse row; plant_scene.h): in the scene, occluding
  /// and mapped, but not scored (their voxels are left out as background). Default none.
  void setNeighbours(NeighbourPlants neighbours) { neighbours_ = std::move(neighbours); }
  /// \brief The sensor's scene, built beforehand: what makePlantScene(plant,
  /// config.scene, config.threads, neighbours) gives for this trial's plant and
  /// neighbours, so that the trials of one plant, pose and row share one BVH (a
  /// campaign's scenario::CampaignSceneCache). run() cannot check that it shows its
  /// plant. Null (default): run() builds it.
  void setScene(SensorScene::ConstPtr scene) { scene_ = std::move(scene); }
  /// \brief Where run() finds the map after v0 of an earlier trial that started alike
  /// (the same scene from setScene, camera, v0, map parameters, depth rounding and
  /// update region) and takes a copy instead of capturing and integrating v0, and where
  /// it leaves its own: the same steps and scores (v0's capture_ms is then 0, its
  /// insert_ms the copy). Used only with a scene from setScene and without noise,
  /// frame callback or detections. Null (default): none.
  void setInitialViewCache(InitialViewCache::Ptr cache)
  {
    initial_views_ = std::move(cache);
  }
  /// \brief The attention ROI of the NBV planner (also used to report the gain of the
  /// baselines' views), before TrialConfig::roi_source. Empty: every voxel counts (plain
  /// volumetric NBV).
  void setAttentionRoi(const Roi& roi) { attention_ = roi; }
  /// \brief Where the NBV planner explores once its ROI has little left to give
  /// (TrialConfig::explore_share; scenario::setUpTrial gives the plant's whole-plant
  /// ROI). Empty (default): every voxel.
  void setExplorationRoi(const Roi& roi) { exploration_ = roi; }
  /// \brief The ROI the planner attended to in the last run(): the attention ROI after
  /// TrialConfig::roi_source (empty before run()).
  const Roi& getAttendedRoi() const { return attended_; }
  /// \brief The levels each view is scored at (e.g. whole plant, main stem, leaf nodes).
  void setEvaluationLevels(const std::vector<EvaluationLevel>& levels)
  {
    levels_ = levels;
  }
  /// \brief Called after every view, e.g. to print progress.
  void setStepCallback(std::function<void(const TrialStep&)> callback)
  {
    callback_ = std::move(callback);
  }

  /// \brief Called with every frame after it is integrated, e.g. to write a frames
  /// folder (io::FramesFolderWriter); with depth_scale > 0 the folder replays to the
  /// trial's map bit for bit.
  void setFrameCallback(std::function<void(const TrialFrame&)> callback)
  {
    frame_callback_ = std::move(callback);
  }

  /// \brief Whether run() must leave the full map (default true): every voxel as a full
  /// insertion of the frames makes it. false, for callers that only want the steps and
  /// scores (a campaign): where the planner reads only fixed ROIs and the occupied
  /// voxels (an attention ROI, not from detections; no visibility weighting; a mesh
  /// plant; no noise; no callbacks), run() inserts exactly only the ROIs' voxels and the
  /// voxels near the scene's surface, the only ones a frame can make occupied
  /// (OccupancyMap::setUpdateRegion), and skips the rest of the free space; the last
  /// frame, which no plan reads, only the voxels near the surface (also for the planners
  /// that read more: a mesh plant, no noise, no callbacks). The steps and scores are the
  /// same; should a hit fall outside that region, run() starts again with the full map.
  void setKeepFullMap(bool keep) { keep_full_map_ = keep; }
  /// \brief See setKeepFullMap.
  bool getKeepFullMap() const { return keep_full_map_; }

  /// \brief Runs the trial from an empty map. \throws InvalidArgumentError if no plant
  /// was set; TimeLimitError after TrialConfig::time_limit_s; the modules' errors
  /// otherwise.
  void run(TrialResult& result);

  /// \brief The map after run() (empty before); see setKeepFullMap.
  const OccupancyMap& getMap() const { return *map_; }
  /// \brief The evaluator of the last run(): its ground truth, levels and background,
  /// e.g. to classify the map's voxels by outcome. \throws InvalidArgumentError before
  /// run().
  const ReconstructionEvaluator& getEvaluator() const;
  /// \brief The plant's sector (axis at the plant's base) used by the last run().
  const CylindricalSector& getSector() const { return sector_; }

private:
  TrialConfig config_;
  std::shared_ptr<const Plant> plant_;
  NeighbourPlants neighbours_;
  SensorScene::ConstPtr scene_;
  InitialViewCache::Ptr initial_views_;
  Roi attention_;
  Roi exploration_;
  Roi attended_;
  std::vector<EvaluationLevel> levels_;
  std::function<void(const TrialStep&)> callback_;
  std::function<void(const TrialFrame&)> frame_callback_;
  std::shared_ptr<OccupancyMap> map_;
  bool keep_full_map_ = true;

  /// One run, with update regions where surfaceRegion gives one (`with_region`); false
  /// when a hit fell outside them (the result is then incomplete).
  bool runOnce(TrialResult& result, bool with_region);
  /// The bricks where a frame can make a voxel occupied, near the scene's triangles
  /// (after sector_ is set), or null where hits are not known to fall there.
  std::shared_ptr<const UpdateRegion> surfaceRegion(const TriangleMesh& background) const;
  /// `surface` and the bricks of the ROIs the planner reads (after attended_ is set):
  /// every voxel a plan reads, or null where a plan may read any voxel.
  std::shared_ptr<const UpdateRegion> readRegion(const UpdateRegion& surface) const;
  std::shared_ptr<ReconstructionEvaluator> evaluator_;
  CylindricalSector sector_;
};

} // namespace plantnbv
