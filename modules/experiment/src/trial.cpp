#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/common/stopwatch.h>
#include <plantnbv/experiment/plant_scene.h>
#include <plantnbv/experiment/region_ray_mask.h>
#include <plantnbv/experiment/trial.h>
#include <plantnbv/planning/view_planner.h>
#include <plantnbv/sensor/simulated_depth_sensor.h>
#include <plantnbv/sensor/simulated_detector.h>
#include <plantnbv/session/detection_fusion.h>
#include <plantnbv/session/leaf_node_prior.h>
#include <plantnbv/session/memory_estimate.h>

namespace plantnbv {

namespace {

constexpr const char* kPlannerNames[] = {"nbv", "predefined", "random"};

// Independent streams of the trial's seed for its random parts.
enum SeedStream : std::uint64_t {
  kPlannerStream = 1,
  kNoiseStream = 2,
  kTruthStream = 3,
  kRoiStream = 4
};

/// The class of an ROI's boxes: the first box's name without its "_<number>" end
/// ("leaf_node_2": "leaf_node"), or "roi" for a box without a name.
std::string roiClassName(const Roi& roi)
{
  std::string name = roi.empty() ? "" : roi.boxes().front().name;
  const std::size_t end = name.find_last_not_of("0123456789");
  if (end != std::string::npos && end + 1 < name.size() && name[end] == '_')
    name.erase(end);
  return name.empty() ? "roi" : name;
}

/// Everything the map after v0 depends on besides the scene and the update region,
/// exactly (doubles in hex): the first frame (camera at `v0`, depth rounding) and the
/// map's parameters.
std::string initialViewKey(const TrialConfig& c, const Viewpoint& v0)
{
  std::ostringstream k;
  const CameraIntrinsics& cam = c.camera;
  k << std::hexfloat << cam.width << ' ' << cam.height << ' ' << cam.fx << ' ' << cam.fy
    << ' ' << cam.cx << ' ' << cam.cy << ' ' << cam.min_range_m << ' ' << cam.max_range_m;
  k << " v0";
  for (double x : {v0.position.x(), v0.position.y(), v0.position.z(), v0.orientation.w(),
                   v0.orientation.x(), v0.orientation.y(), v0.orientation.z()})
    k << ' ' << x;
  const OccupancyMap::Config& m = c.map;
  k << " map " << m.resolution_m << ' ' << m.prob_hit << ' ' << m.prob_miss << ' '
    << m.clamp_min << ' ' << m.clamp_max << ' ' << m.occupancy_threshold << ' '
    << m.max_range_m << " depth_scale " << c.depth_scale;
  return k.str();
}

ViewPlanner::Ptr makePlanner(const TrialConfig& c, const Roi& exploration)
{
  switch (c.planner) {
  case PlannerKind::nbv: {
    auto planner = std::make_shared<AttentionNbvPlanner>();
    planner->setStopGain(c.stop_gain_bits);
    planner->setExploration(c.explore_share, exploration);
    planner->setExplorationViews(c.roi_source.explorationViews());
    planner->setViewSpacing(c.view_spacing_m);
    return planner;
  }
  case PlannerKind::predefined: {
    auto planner = std::make_shared<PredefinedPlanner>();
    planner->setPattern(c.pattern);
    return planner;
  }
  case PlannerKind::random:
    return std::make_shared<RandomPlanner>();
  }
  throw InvalidArgumentError("unknown planner kind");
}

} // namespace

const char* plannerKindName(PlannerKind kind)
{
  return kPlannerNames[static_cast<int>(kind)];
}

PlannerKind plannerKindFromName(const std::string& name)
{
  for (int i = 0; i < 3; ++i)
    if (name == kPlannerNames[i])
      return static_cast<PlannerKind>(i);
  throw InvalidArgumentError("unknown planner '" + name +
                             "' (expected nbv, predefined or random)");
}

void TrialConfig::validate() const
{
  camera.validate();
  noise.validate();
  scene.validate();
  map.validate();
  gain.validate();
  try {
    roi_source.validate();
  } catch (const InvalidArgumentError& e) {
    throw InvalidArgumentError(std::string("trial config: ") + e.what());
  }
  auto bad = [](const std::string& field, const std::string& value,
                const std::string& expected) {
    throw InvalidArgumentError("trial config: " + field + " = " + value + ", expected " +
                               expected);
  };
  if (pattern < 1 || pattern > 4)
    bad("pattern", std::to_string(pattern), "1, 2, 3 or 4");
  if (grid_rows < 1 || grid_cols < 1)
    bad("grid", std::to_string(grid_rows) + " x " + std::to_string(grid_cols),
        "at least 1 x 1");
  if (samples_per_cell < 1)
    bad("samples_per_cell", std::to_string(samples_per_cell), ">= 1");
  if (planner == PlannerKind::predefined && (grid_rows != 3 || grid_cols != 3))
    bad("grid", std::to_string(grid_rows) + " x " + std::to_string(grid_cols),
        "3 x 3 for the predefined planner (its patterns are defined on 9 cells)");
  if (!(stop_gain_bits >= 0.0) || !std::isfinite(stop_gain_bits))
    bad("stop_gain_bits", std::to_string(stop_gain_bits), "a finite value >= 0");
  if (!(explore_share >= 0.0 && explore_share <= 1.0))
    bad("explore_share", std::to_string(explore_share), "in [0, 1] (0: never explore)");
  if (!(std::isfinite(view_spacing_m) && view_spacing_m >= 0.0))
    bad("view_spacing", std::to_string(view_spacing_m), "finite and >= 0 (metres)");
  if (views < 1 || views > 1000)
    bad("views", std::to_string(views), "1 to 1000");
  if (threads < 0)
    bad("threads", std::to_string(threads), ">= 0");
  if (!(std::isfinite(time_limit_s) && time_limit_s >= 0.0))
    bad("time_limit_s", std::to_string(time_limit_s), "a finite value >= 0 (0: none)");
  if (!initial_view.position.allFinite() ||
      !initial_view.orientation.coeffs().allFinite() ||
      !(initial_view.orientation.norm() > 0.5 && initial_view.orientation.norm() < 2.0))
    bad("initial_view", "a non-finite position or orientation",
        "finite numbers and a unit quaternion");
  if (!(depth_scale >= 0.0) || !std::isfinite(depth_scale))
    bad("depth_scale", std::to_string(depth_scale),
        "a finite value >= 0 (units per metre; 0: the sensor's float depth)");
  if (!(memory_cap_bytes > 0.0))
    bad("memory_cap_bytes", std::to_string(memory_cap_bytes), "> 0");
  std::ostringstream what;
  what << std::setprecision(3) << "trial config: map resolution " << map.resolution_m
       << " m, range " << map.max_range_m << " m, camera " << camera.width << " x "
       << camera.height << " and " << gain.rays_x << " x " << gain.rays_y << " gain rays";
  requireWithinMemoryCap(estimatedMemoryBytes(), memory_cap_bytes, what.str(),
                         " (memory_cap_gib raises it)");
  CylindricalSector s = sector;
  s.axis_base = paperPlantBase(); // replaced by the plant's base; the rest must hold
  s.validate();
}

double TrialConfig::estimatedMemoryBytes() const
{
  return estimatedViewMemoryBytes(map, camera) + estimatedGainMemoryBytes(gain);
}

std::uint64_t groundTruthSeed(std::uint64_t trial_seed)
{
  return deriveSeed(trial_seed, kTruthStream);
}

std::uint64_t roiSourceSeed(std::uint64_t trial_seed)
{
  return deriveSeed(trial_seed, kRoiStream);
}

ActiveVisionSession::Config sessionConfigOf(const TrialConfig& c)
{
  ActiveVisionSession::Config session;
  session.map = c.map;
  session.sector = c.sector;
  session.grid_rows = c.grid_rows;
  session.grid_cols = c.grid_cols;
  session.samples_per_cell = c.samples_per_cell;
  session.gain = c.gain;
  session.seed = c.seed;
  session.threads = c.threads;
  return session;
}

std::vector<double> TrialResult::f1Curve(std::size_t level) const
{
  std::vector<double> curve;
  for (const TrialStep& step : steps)
    curve.push_back(level < step.scores.size()
                        ? step.scores[level].f1
                        : std::numeric_limits<double>::quiet_NaN());
  return curve;
}

Trial::Trial(const TrialConfig& config) : map_(std::make_shared<OccupancyMap>())
{
  setConfig(config);
}

Trial::~Trial() = default;

void Trial::setConfig(const TrialConfig& config)
{
  config.validate();
  config_ = config;
}

void Trial::setPlant(std::shared_ptr<const Plant> plant)
{
  plant_ = std::move(plant);
}

const ReconstructionEvaluator& Trial::getEvaluator() const
{
  if (!evaluator_)
    throw InvalidArgumentError("Trial: no evaluator before run()");
  return *evaluator_;
}

void Trial::run(TrialResult& result)
{
  if (!plant_)
    throw InvalidArgumentError("Trial: no plant set");
  const bool with_region = !keep_full_map_ && !callback_ && !frame_callback_;
  if (!runOnce(result, with_region))
    runOnce(result, false); // a hit outside the region: the full map after all
}

std::shared_ptr<const UpdateRegion>
Trial::surfaceRegion(const TriangleMesh& background) const
{
  const TrialConfig& c = config_;
  // A voxel becomes occupied only where a ray ends, on the scene's triangles up to
  // rounding, when the sensor has no noise and the plant is a mesh.
  if (c.noise.enabled || plant_->mesh.empty())
    return nullptr;
  const double res = c.map.resolution_m;
  // Rays reach max_range_m from a camera on the sector or at v0; outside these bounds
  // every voxel counts as read.
  const double reach = c.map.max_range_m + res;
  const Eigen::Vector3d v0 =
      c.initial_view.position + (plant_->base_position - paperPlantBase());
  const Eigen::Vector3d sector_lo =
      sector_.axis_base +
      Eigen::Vector3d(-sector_.radius_m, -sector_.radius_m, sector_.bottom_m);
  const Eigen::Vector3d sector_hi =
      sector_.axis_base + Eigen::Vector3d(sector_.radius_m, sector_.radius_m,
                                          sector_.bottom_m + sector_.height_m);
  const Box bounds = Box::fromMinMax(sector_lo.cwiseMin(v0).array() - reach,
                                     sector_hi.cwiseMax(v0).array() + reach);
  // A region's bits take one bit a brick: past 2^24 bricks (2 MiB; a sector of metres or
  // a fine map) the full map costs less than building the region for every trial.
  if (UpdateRegion::bricksOver(res, bounds) > (std::size_t{1} << 24))
    return nullptr;
  auto region = std::make_shared<UpdateRegion>(res, bounds);
  // A point lies on a triangle up to the sensor's rounding (and, with depth_scale, half
  // a depth unit along the ray); a voxel's margin covers both.
  const double surface_margin = res + (c.depth_scale > 0.0 ? 1.0 / c.depth_scale : 0.0);
  region->addMesh(plant_->mesh, surface_margin);
  region->addMesh(background, surface_margin);
  return region;
}

std::shared_ptr<const UpdateRegion> Trial::readRegion(const UpdateRegion& surface) const
{
  const TrialConfig& c = config_;
  // The planner reads its ROIs' voxels and the occupied ones only when it has fixed
  // ROIs and no visibility weighting (gain_snapshot.h).
  const bool explores = c.planner == PlannerKind::nbv &&
                        (c.explore_share > 0.0 || c.roi_source.explorationViews() > 0);
  if (attended_.empty() || (explores && exploration_.empty()) ||
      c.roi_source.followsFrames() || c.gain.visibility_weighted)
    return nullptr;
  auto region = std::make_shared<UpdateRegion>(surface);
  const double res = c.map.resolution_m;
  for (const Box& box : attended_.boxes())
    region->addBox(box, 2.0 * res);
  if (explores)
    for (const Box& box : exploration_.boxes())
      region->addBox(box, 2.0 * res);
  return region;
}

bool Trial::runOnce(TrialResult& result, bool with_region)
{
  const TrialConfig& c = config_;
  Stopwatch total_clock;
  result = TrialResult{};
  for (const EvaluationLevel& level : levels_)
    result.level_names.push_back(level.name);

  // Everything that depends only on the plant and its pose: scene, ground truth, sector.
  Stopwatch setup_clock;
  SimulatedDepthSensor sensor(c.camera);
  sensor.setNumberOfThreads(static_cast<unsigned int>(c.threads));
  if (c.noise.enabled) {
    NoiseConfig noise = c.noise;
    noise.seed = deriveSeed(c.seed, kNoiseStream);
    sensor.setNoise(noise);
  }
  sensor.setScene(scene_ ? scene_
                         : makePlantScene(*plant_, c.scene,
                                          static_cast<unsigned int>(c.threads),
                                          neighbours_));
  evaluator_ = std::make_shared<ReconstructionEvaluator>();
  ReconstructionEvaluator& evaluator = *evaluator_;
  evaluator.setResolution(c.map.resolution_m);
  evaluator.setSeed(groundTruthSeed(c.seed));
  evaluator.setNumberOfThreads(c.threads);
  evaluator.setGroundTruth(*plant_);
  evaluator.setLevels(levels_);
  // Scored on the plant only: the floor's, the supports' and the neighbours' voxels are
  // left out.
  TriangleMesh background;
  for (const TriangleMesh& part : plantSceneBackground(*plant_, c.scene, neighbours_))
    background.append(part);
  evaluator.setBackground(background);
  sector_ = c.sector;
  sector_.axis_base = plant_->base_position;
  ActiveVisionSession::Config session_config = sessionConfigOf(c);
  session_config.sector = sector_;
  session_config.seed = deriveSeed(c.seed, kPlannerStream);
  ActiveVisionSession session(session_config);
  session.setCamera(c.camera); // the candidates' frusta are the camera's
  session.setPlanner(makePlanner(c, exploration_));
  attended_ = c.roi_source.apply(attention_, roiSourceSeed(c.seed));
  session.setRoi(attended_);
  // The detections source: a detector of the config's quality finds the attention
  // ROI's boxes in each frame, and their fusion is what the next plan attends to.
  const bool detecting = c.roi_source.detects();
  SimulatedDetector detector;
  DetectionFusion fusion;
  std::vector<Detection> detections;
  if (detecting) {
    if (attention_.empty())
      throw InvalidArgumentError("roi_source detections: the trial has no attention ROI "
                                 "for the simulated detector to find");
    SimulatedDetector::Config detector_config;
    detector_config.class_name = roiClassName(attention_);
    detector_config.recall = c.roi_source.detector_recall;
    detector_config.false_positives = c.roi_source.detector_false_positives;
    detector_config.box_jitter_px = c.roi_source.detector_box_jitter_px;
    detector_config.mask_dilation_px = c.roi_source.detector_mask_dilation_px;
    detector_config.masks = c.roi_source.detector_masks;
    detector_config.seed = roiSourceSeed(c.seed);
    detector.setConfig(detector_config);
    DetectionFusion::Config fusion_config;
    fusion_config.class_name = detector_config.class_name;
    fusion.setConfig(fusion_config);
  }
  // The prior: leaf nodes along the stem, the detected ones added to them.
  const LeafNodePrior prior(c.roi_source.priorConfig());
  map_ = session.getMap();
  // v0's map from initial_views_ where the frame is not needed otherwise (the same
  // scene, frame, map parameters and region give the same map).
  const bool share_v0 =
      initial_views_ && scene_ && !c.noise.enabled && !frame_callback_ && !detecting;
  // Frames that a plan reads go exactly into the voxels it reads and those a frame can
  // make occupied; the last frame, read by the scores only (the occupied voxels), into
  // the latter.
  const std::shared_ptr<const UpdateRegion> surface =
      with_region ? surfaceRegion(background) : nullptr;
  map_->setUpdateRegion(surface ? readRegion(*surface) : nullptr);
  result.setup_ms = setup_clock.ms();
  auto checkTimeLimit = [&](const char* after) {
    if (c.time_limit_s > 0.0 && total_clock.ms() > 1000.0 * c.time_limit_s) {
      std::ostringstream s;
      s << std::setprecision(3) << "trial time limit of " << c.time_limit_s
        << " s passed after " << after << " (" << total_clock.ms() / 1000.0 << " s)";
      throw TimeLimitError(s.str());
    }
  };
  checkTimeLimit("setup");

  Viewpoint view(c.initial_view.position + (plant_->base_position - paperPlantBase()),
                 c.initial_view.orientation);
  CloudXYZL frame;
  DepthImage depth;
  const bool rounded_depth = c.depth_scale > 0.0;
  CloudXYZ occupied;
  for (int index = 0; index < c.views; ++index) {
    TrialStep step;
    step.index = index;
    step.gain = std::numeric_limits<double>::quiet_NaN();
    if (index > 0) {
      Stopwatch plan_clock;
      session.setCurrentView(view);
      NextBestView best;
      session.nextBestView(best);
      const NextViewResult& next = best.result;
      step.plan_ms = plan_clock.ms();
      if (next.stop) {
        result.stopped_early = true;
        break;
      }
      view = next.view;
      step.gain = next.gain;
      step.unknown_seen = next.candidates[next.chosen].gain.unknown_seen;
      step.candidates = next.candidates.size();
    }
    step.view = view;

    if (surface && index + 1 == c.views)
      map_->setUpdateRegion(surface);
    const Pose T_W_O = opticalFrame(view); // a frames folder reads it back bit for bit
    std::string v0_key;
    std::unique_ptr<OccupancyMap> shared_v0;
    Stopwatch share_clock;
    if (index == 0 && share_v0) {
      v0_key = initialViewKey(c, view);
      shared_v0 = initial_views_->find(scene_, v0_key, map_->getUpdateRegion().get());
    }
    if (shared_v0) { // v0 as another trial integrated it (all its hits in the region)
      session.setMapWithFrame(std::move(shared_v0), T_W_O.position);
      map_ = session.getMap();
      step.insert_ms = share_clock.ms();
    } else {
      Stopwatch capture_clock;
      // Only the rays that can reach the region, where nothing but the map reads the
      // frame.
      if (map_->getUpdateRegion() && !frame_callback_ && !detecting)
        sensor.setRayMask(std::make_shared<const RayMask>(regionRayMask(
            *map_->getUpdateRegion(), c.camera, T_W_O, c.map.max_range_m)));
      sensor.setFrameIndex(static_cast<std::uint64_t>(index));
      sensor.capture(view, frame,
                     rounded_depth || frame_callback_ || detecting ? &depth : nullptr);
      step.capture_ms = capture_clock.ms();

      Stopwatch insert_clock;
      if (rounded_depth) {
        roundDepthToUnits(depth, c.depth_scale);
        session.integrate(depth, c.camera, T_W_O);
      } else {
        session.integrate(frame, T_W_O.position);
      }
      if (!v0_key.empty() && map_->getLastInsertStats().hits_outside_region == 0)
        initial_views_->add(scene_, v0_key, *map_);
      step.insert_ms = insert_clock.ms();
    }
    if (map_->getUpdateRegion() && map_->getLastInsertStats().hits_outside_region > 0)
      return false;
    if (detecting) { // the depth as integrated: a frames folder replays to this ROI
      detector.detect(frame, attention_, static_cast<std::uint64_t>(index), detections);
      fusion.addFrame(detections, depth, c.camera, T_W_O);
    }
    if (frame_callback_) {
      TrialFrame record;
      record.index = index;
      record.T_W_O = T_W_O;
      record.depth = &depth;
      record.detections = detecting ? &detections : nullptr;
      frame_callback_(record);
    }

    Stopwatch eval_clock;
    map_->getOccupiedVoxelCentres(occupied);
    step.occupied_voxels = occupied.size();
    evaluator.compute(occupied, step.scores, step.organs);
    step.eval_ms = eval_clock.ms();
    if (c.roi_source.followsFrames()) { // what the next view attends to
      attended_ = detecting ? fusion.getRoi() : Roi();
      if (c.roi_source.predicts())
        attended_ =
            prior.predictAround(attended_, occupied, sector_.axis_base, sector_.height_m);
      session.setRoi(attended_);
    }

    result.steps.push_back(step);
    if (callback_)
      callback_(result.steps.back());
    if (index + 1 < c.views)
      checkTimeLimit(
          ("view " + std::to_string(index + 1) + " of " + std::to_string(c.views))
              .c_str());
  }
  result.total_ms = total_clock.ms();
  return true;
}

} // namespace plantnbv
