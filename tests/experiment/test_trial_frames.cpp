// A trial's frames and the loop it shares with a robot: frames written by a trial
// replay to its map bit for bit, the refactor onto ActiveVisionSession left the
// paper's trials unchanged, the NBV view beats the random planner's expected view, and
// the sensor's depth images follow the pixel convention of camera_intrinsics.h.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <tuple>
#include <unistd.h>
#include <vector>

#include <gtest/gtest.h>
#include <octomap/OcTree.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/camera/depth_image.h>
#include <plantnbv/camera/optical_frame.h>
#include <plantnbv/common/random.h>
#include <plantnbv/experiment/plant_scene.h>
#include <plantnbv/experiment/reconstruction_evaluator.h>
#include <plantnbv/experiment/trial.h>
#include <plantnbv/io/frames_folder.h>
#include <plantnbv/planning/view_planner.h>
#include <plantnbv/plant/plant_rois.h>
#include <plantnbv/plant/tomato_plant_generator.h>
#include <plantnbv/sensor/simulated_depth_sensor.h>
#include <plantnbv/session/active_vision_session.h>

#include "octree_leaves.h"
#include "temp_dir.h"

using namespace plantnbv;

namespace {

// Trial::run's seed streams (trial.cpp).
constexpr std::uint64_t kPlannerStream = 1;
constexpr std::uint64_t kTruthStream = 3;

/// A fast trial: the L515 at 320 x 240, a coarse gain ray grid, few views.
TrialConfig smallConfig(int views)
{
  TrialConfig c;
  c.camera = CameraIntrinsics::l515(L515Mode::qvga_320x240);
  c.views = views;
  c.gain.rays_x = 32;
  c.gain.rays_y = 24;
  c.seed = 5;
  return c;
}

std::shared_ptr<Plant> plantAt(int seed, double yaw_deg)
{
  auto plant =
      std::make_shared<Plant>(TomatoPlantGenerator(defaultPlantConfig(seed)).generate());
  posePlant(*plant, paperPlantBase(), yaw_deg * M_PI / 180.0);
  return plant;
}

std::vector<EvaluationLevel> levelsOf(const Plant& plant)
{
  return {{"whole_plant", wholePlantRoi(plant)},
          {"leaf_nodes", leafNodeRoi(plant), true}};
}

/// Bit-wise equality of two depth images (NaN == NaN).
bool sameDepth(const DepthImage& a, const DepthImage& b)
{
  if (a.width != b.width || a.height != b.height || a.depth_m.size() != b.depth_m.size())
    return false;
  for (std::size_t i = 0; i < a.depth_m.size(); ++i) {
    const float x = a.depth_m[i], y = b.depth_m[i];
    if (!(x == y || (std::isnan(x) && std::isnan(y))))
      return false;
  }
  return true;
}

/// Everything of two trials but their timings, bit for bit.
void expectSameSteps(const TrialResult& a, const TrialResult& b)
{
  ASSERT_EQ(a.steps.size(), b.steps.size());
  for (std::size_t i = 0; i < a.steps.size(); ++i) {
    const TrialStep& s = a.steps[i];
    const TrialStep& t = b.steps[i];
    EXPECT_EQ(s.index, t.index) << i;
    EXPECT_EQ(s.view.position, t.view.position) << i;
    EXPECT_EQ(s.view.orientation.coeffs(), t.view.orientation.coeffs()) << i;
    EXPECT_TRUE(s.gain == t.gain || (std::isnan(s.gain) && std::isnan(t.gain))) << i;
    EXPECT_EQ(s.candidates, t.candidates) << i;
    EXPECT_EQ(s.occupied_voxels, t.occupied_voxels) << i;
    ASSERT_EQ(s.scores.size(), t.scores.size()) << i;
    for (std::size_t l = 0; l < s.scores.size(); ++l) {
      EXPECT_EQ(s.scores[l].precision, t.scores[l].precision) << i << " " << l;
      EXPECT_EQ(s.scores[l].recall, t.scores[l].recall) << i << " " << l;
      EXPECT_EQ(s.scores[l].f1, t.scores[l].f1) << i << " " << l;
      EXPECT_TRUE(s.scores[l].chamfer == t.scores[l].chamfer ||
                  (std::isnan(s.scores[l].chamfer) && std::isnan(t.scores[l].chamfer)))
          << i << " " << l;
      EXPECT_EQ(s.scores[l].reconstruction_points, t.scores[l].reconstruction_points);
    }
  }
}

/// The evaluator of Trial::run for `plant`.
void setUpEvaluator(ReconstructionEvaluator& evaluator, const TrialConfig& c,
                    const Plant& plant, const std::vector<EvaluationLevel>& levels)
{
  evaluator.setResolution(c.map.resolution_m);
  evaluator.setSeed(deriveSeed(c.seed, kTruthStream));
  evaluator.setNumberOfThreads(c.threads);
  evaluator.setGroundTruth(plant);
  evaluator.setLevels(levels);
  TriangleMesh background;
  for (const TriangleMesh& part : plantSceneBackground(plant, c.scene))
    background.append(part);
  evaluator.setBackground(background);
}

/// The NBV trial as Trial::run computed it before it ran on ActiveVisionSession: the
/// sensor's clouds into OccupancyMap::insert, and AttentionNbvPlanner set up by hand.
TrialResult referenceTrial(const TrialConfig& c, const Plant& plant, const Roi& attention,
                           const std::vector<EvaluationLevel>& levels)
{
  TrialResult result;
  for (const EvaluationLevel& level : levels)
    result.level_names.push_back(level.name);
  SimulatedDepthSensor sensor(c.camera);
  sensor.setNumberOfThreads(static_cast<unsigned int>(c.threads));
  sensor.setScene(makePlantScene(plant, c.scene, static_cast<unsigned int>(c.threads)));
  ReconstructionEvaluator evaluator;
  setUpEvaluator(evaluator, c, plant, levels);

  CylindricalSector sector = c.sector;
  sector.axis_base = plant.base_position;
  auto sampler = std::make_shared<CylindricalSectorSampler>(sector);
  sampler->setGrid(c.grid_rows, c.grid_cols);
  sampler->setSamplesPerCell(c.samples_per_cell);
  auto map = std::make_shared<OccupancyMap>(c.map);
  map->setNumberOfThreads(c.threads);
  AttentionNbvPlanner planner;
  planner.setStopGain(c.stop_gain_bits);
  planner.setViewSpacing(c.view_spacing_m);
  planner.setInputMap(map);
  planner.setCandidateSampler(sampler);
  planner.setRoi(attention);
  GainConfig gain = c.gain;
  gain.horizontal_fov_rad = c.camera.horizontalFov();
  gain.vertical_fov_rad = c.camera.verticalFov();
  planner.setGainConfig(gain);
  planner.setSeed(deriveSeed(c.seed, kPlannerStream));
  planner.setNumberOfThreads(c.threads);

  Viewpoint view(c.initial_view.position + (plant.base_position - paperPlantBase()),
                 c.initial_view.orientation);
  CloudXYZL frame;
  CloudXYZ occupied;
  for (int index = 0; index < c.views; ++index) {
    TrialStep step;
    step.index = index;
    step.gain = std::numeric_limits<double>::quiet_NaN();
    if (index > 0) {
      planner.setCurrentView(view);
      NextViewResult next;
      planner.compute(next);
      if (next.stop)
        break;
      view = next.view;
      step.gain = next.gain;
      step.candidates = next.candidates.size();
    }
    step.view = view;
    sensor.setFrameIndex(static_cast<std::uint64_t>(index));
    sensor.capture(view, frame);
    map->insert(frame, view.position);
    planner.addVisitedPosition(view.position);
    map->getOccupiedVoxelCentres(occupied);
    step.occupied_voxels = occupied.size();
    evaluator.compute(occupied, step.scores);
    result.steps.push_back(step);
  }
  return result;
}

/// Runs a trial with depth_scale 1000 that writes its frames to `folder`, replays the
/// folder into a session and compares maps, poses and depth images bit for bit.
void expectFramesReplayToTheTrialsMap(const TrialConfig& config,
                                      const std::string& folder)
{
  const auto plant = plantAt(1, 20.0);
  io::CameraInfo info;
  info.intrinsics = config.camera;
  info.depth_scale = config.depth_scale;
  io::FramesFolderWriter writer(folder, info);
  std::vector<Pose> poses;
  std::vector<DepthImage> depths;
  Trial trial(config);
  trial.setPlant(plant);
  trial.setAttentionRoi(wholePlantRoi(*plant));
  trial.setEvaluationLevels(levelsOf(*plant));
  trial.setFrameCallback([&](const TrialFrame& frame) {
    EXPECT_EQ(frame.index, int(poses.size()));
    ASSERT_NE(frame.depth, nullptr);
    poses.push_back(frame.T_W_O);
    depths.push_back(*frame.depth);
    writer.append(*frame.depth, frame.T_W_O, std::numeric_limits<double>::quiet_NaN());
  });
  TrialResult result;
  trial.run(result);
  ASSERT_EQ(result.steps.size(), std::size_t(config.views));
  ASSERT_EQ(poses.size(), result.steps.size());
  EXPECT_EQ(writer.frameCount(), result.steps.size());

  const io::FramesFolder frames(folder);
  ASSERT_EQ(frames.frames().size(), poses.size());
  const CameraIntrinsics& K = frames.camera().intrinsics;
  EXPECT_EQ(K.width, config.camera.width);
  EXPECT_EQ(K.height, config.camera.height);
  EXPECT_EQ(K.fx, config.camera.fx);
  EXPECT_EQ(K.fy, config.camera.fy);
  EXPECT_EQ(K.cx, config.camera.cx);
  EXPECT_EQ(K.cy, config.camera.cy);
  EXPECT_EQ(frames.camera().depth_scale, config.depth_scale);

  ActiveVisionSession session(sessionConfigOf(config));
  DepthImage depth;
  for (std::size_t i = 0; i < frames.frames().size(); ++i) {
    const Pose& T_W_O = frames.frames()[i].T_W_O;
    // The pose the trial integrated is the step's optical frame, and it reads back.
    EXPECT_EQ(poses[i].position, opticalFrame(result.steps[i].view).position) << i;
    EXPECT_EQ(poses[i].orientation.coeffs(),
              opticalFrame(result.steps[i].view).orientation.coeffs())
        << i;
    EXPECT_EQ(T_W_O.position, poses[i].position) << i;
    EXPECT_EQ(T_W_O.orientation.coeffs(), poses[i].orientation.coeffs()) << i;
    frames.loadDepth(i, depth);
    EXPECT_TRUE(sameDepth(depth, depths[i])) << i;
    session.integrate(depth, K, T_W_O);
  }
  const std::vector<test::OcTreeLeaf> replayed = test::octreeLeaves(*session.getMap());
  const std::vector<test::OcTreeLeaf> trials = test::octreeLeaves(trial.getMap());
  EXPECT_GT(trial.getMap().countVoxels().occupied, 1000u);
  ASSERT_EQ(replayed.size(), trials.size());
  EXPECT_TRUE(replayed == trials);
  EXPECT_EQ(session.getMap()->countVoxels().occupied,
            result.steps.back().occupied_voxels);
}

} // namespace

TEST(TrialFrames, FramesReplayToTheTrialsMapBitForBit)
{
  TrialConfig config = smallConfig(3);
  config.depth_scale = 1000.0;
  test::TempDir dir;
  expectFramesReplayToTheTrialsMap(config, dir.file("frames"));
}

TEST(TrialFrames, NoisyFramesReplayToTheTrialsMapBitForBit)
{
  TrialConfig config = smallConfig(3);
  config.depth_scale = 1000.0;
  config.noise.enabled = true;
  test::TempDir dir;
  expectFramesReplayToTheTrialsMap(config, dir.file("frames"));
}

TEST(TrialFrames, FloatDepthTrialIsThePlannerLoopOnTheSensorsClouds)
{
  // depth_scale 0 (the paper's): Trial on ActiveVisionSession gives exactly the steps
  // of the loop it replaced.
  const auto plant = plantAt(2, 45.0);
  const TrialConfig config = smallConfig(4);
  ASSERT_EQ(config.depth_scale, 0.0);
  const Roi attention = leafNodeRoi(*plant);
  Trial trial(config);
  trial.setPlant(plant);
  trial.setAttentionRoi(attention);
  trial.setEvaluationLevels(levelsOf(*plant));
  TrialResult result;
  trial.run(result);
  const TrialResult reference =
      referenceTrial(config, *plant, attention, levelsOf(*plant));
  ASSERT_EQ(result.steps.size(), 4u);
  for (std::size_t i = 1; i < result.steps.size(); ++i)
    EXPECT_EQ(result.steps[i].candidates, 27u);
  expectSameSteps(result, reference);

  // Millimetre depth changes the map slightly: v0's occupied voxels within 2 %.
  TrialConfig rounded = config;
  rounded.depth_scale = 1000.0;
  rounded.views = 1;
  Trial rounded_trial(rounded);
  rounded_trial.setPlant(plant);
  rounded_trial.setAttentionRoi(attention);
  rounded_trial.setEvaluationLevels(levelsOf(*plant));
  TrialResult rounded_result;
  rounded_trial.run(rounded_result);
  ASSERT_EQ(rounded_result.steps.size(), 1u);
  const double a = double(result.steps[0].occupied_voxels);
  const double b = double(rounded_result.steps[0].occupied_voxels);
  std::printf("v0 occupied voxels: float depth %.0f, millimetre depth %.0f\n", a, b);
  EXPECT_NE(test::octreeLeaves(rounded_trial.getMap()).size(), 0u);
  EXPECT_LT(std::abs(a - b), 0.02 * a);
}

TEST(TrialFrames, NbvViewBeatsTheMeanCandidate)
{
  // The random planner's expected F1 after v0 + one view is the mean over the
  // candidates it draws from; the NBV planner's choice must beat it.
  for (int plant_seed : {1, 2}) {
    SCOPED_TRACE("plant " + std::to_string(plant_seed));
    const auto plant = plantAt(plant_seed, 0.0);
    TrialConfig c = smallConfig(2);
    c.gain = GainConfig(); // the paper's ray grid
    const CameraIntrinsics K = c.camera;
    const Roi roi = wholePlantRoi(*plant);

    SimulatedDepthSensor sensor(K);
    sensor.setScene(makePlantScene(*plant, c.scene));
    ReconstructionEvaluator evaluator;
    setUpEvaluator(evaluator, c, *plant, {{"whole_plant", roi}});

    ActiveVisionSession::Config session_config = sessionConfigOf(c);
    session_config.sector.axis_base = plant->base_position;
    session_config.seed = deriveSeed(c.seed, kPlannerStream);
    ActiveVisionSession session(session_config);
    session.setCamera(K);
    session.setRoi(roi);
    const Viewpoint v0(c.initial_view.position +
                           (plant->base_position - paperPlantBase()),
                       c.initial_view.orientation);
    CloudXYZL frame0, frame;
    sensor.capture(v0, frame0);
    session.integrate(frame0, v0.position);
    session.setCurrentView(v0);
    NextBestView next;
    session.nextBestView(next);
    const std::vector<CandidateView>& candidates = next.result.candidates;
    ASSERT_EQ(candidates.size(), 27u);
    ASSERT_EQ(next.ranking.front().index, next.result.chosen);

    std::vector<LevelScore> scores;
    CloudXYZ occupied;
    session.getMap()->getOccupiedVoxelCentres(occupied);
    evaluator.compute(occupied, scores);
    const double f1_v0 = scores[0].f1;
    std::vector<double> f1(candidates.size());
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      OccupancyMap map(c.map);
      map.insert(frame0, v0.position);
      sensor.capture(candidates[i].view, frame);
      map.insert(frame, candidates[i].view.position);
      map.getOccupiedVoxelCentres(occupied);
      evaluator.compute(occupied, scores);
      f1[i] = scores[0].f1;
    }
    double mean = 0.0;
    for (double x : f1)
      mean += x / double(f1.size());
    const double best = f1[next.result.chosen];
    const std::size_t better =
        std::count_if(f1.begin(), f1.end(), [&](double x) { return x > best; });
    std::printf("plant %d: F1 v0 %.4f, v0 + NBV %.4f (gain %.1f bits, candidate %zu), "
                "mean over 27 candidates %.4f, min %.4f, max %.4f, candidates better "
                "than NBV %zu\n",
                plant_seed, f1_v0, best, next.result.gain, next.result.chosen, mean,
                *std::min_element(f1.begin(), f1.end()),
                *std::max_element(f1.begin(), f1.end()), better);
    EXPECT_GT(best, f1_v0);
    EXPECT_GT(best, mean);
  }
}

TEST(TrialFrames, SensorDepthFollowsThePixelConvention)
{
  // An off-centre principal point: depth at (u, v) is the plane's along the ray
  // ((u - cx) / fx, (v - cy) / fy, 1), and depthToCloud gives the sensor's points.
  const CameraIntrinsics K = CameraIntrinsics::custom(64, 48, 40.0, 42.0, 20.25, 30.5);
  const Viewpoint view = Pose::fromXyzQuat(0.646, 0.353, 1.383, 0.0, 0.0, -0.383, 0.924);
  const Pose T_W_O = opticalFrame(view);
  const double distance_m = 1.2;
  const Eigen::Vector3d centre_O(0.0, 0.0, distance_m);
  for (const Eigen::Vector3d& normal :
       {Eigen::Vector3d(0.0, 0.0, -1.0), Eigen::Vector3d(0.3, -0.2, -1.0).normalized()}) {
    SCOPED_TRACE("normal " + std::to_string(normal.x()) + " " +
                 std::to_string(normal.y()));
    // A 10 m square through centre_O with this normal (optical frame), in the world.
    const Eigen::Vector3d a_O = normal.unitOrthogonal(), b_O = normal.cross(a_O);
    TriangleMesh plane;
    for (int i = 0; i < 4; ++i) {
      const double sa = (i == 1 || i == 2) ? 1.0 : -1.0;
      const double sb = (i >= 2) ? 1.0 : -1.0;
      const Eigen::Vector3d p_O = centre_O + 5.0 * (sa * a_O + sb * b_O);
      plane.vertices.push_back((T_W_O.orientation * p_O + T_W_O.position).cast<float>());
    }
    plane.triangles = {{0, 1, 2}, {0, 2, 3}};
    plane.labels = {PartLabel::leaflet, PartLabel::leaflet};
    auto scene = std::make_shared<SensorScene>();
    scene->addMesh(plane);
    scene->commit();

    SimulatedDepthSensor sensor(K);
    sensor.setScene(scene);
    CloudXYZL cloud;
    DepthImage depth;
    sensor.capture(view, cloud, &depth);
    ASSERT_EQ(depth.width, K.width);
    ASSERT_EQ(depth.height, K.height);
    CloudXYZ back;
    depthToCloud(depth, K, T_W_O, back);
    ASSERT_EQ(back.size(), cloud.size());
    std::size_t returns = 0;
    double worst_point = 0.0, worst_depth = 0.0;
    for (std::uint32_t v = 0; v < K.height; ++v)
      for (std::uint32_t u = 0; u < K.width; ++u) {
        const Eigen::Vector3d ray((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
        const double expected = normal.dot(centre_O) / normal.dot(ray);
        const float d = depth.at(u, v);
        if (!std::isfinite(d))
          continue;
        ++returns;
        worst_depth = std::max(worst_depth, std::abs(d - expected));
        worst_point =
            std::max(worst_point, (back.at(u, v).getVector3fMap().cast<double>() -
                                   cloud.at(u, v).getVector3fMap().cast<double>())
                                      .norm());
      }
    EXPECT_EQ(returns, K.pixelCount()); // the plane fills the image
    EXPECT_LT(worst_depth, 1e-5);
    EXPECT_LT(worst_point, 1e-5);
  }
}
