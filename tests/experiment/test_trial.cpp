// The trial loop: determinism, the planners' paths, and the attention mechanism's effect.

#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/plant_scene.h>
#include <plantnbv/experiment/trial.h>
#include <plantnbv/planning/view_planner.h>
#include <plantnbv/plant/plant_rois.h>
#include <plantnbv/plant/tomato_plant_generator.h>

using namespace plantnbv;

namespace {

/// A small trial: the youngest default plant, a 160 x 120 camera with the L515's field
/// of view, few views. Everything else is the paper's.
TrialConfig smallConfig(PlannerKind planner, int views)
{
  TrialConfig c;
  c.camera = CameraIntrinsics::l515(L515Mode::qvga_320x240);
  c.camera =
      CameraIntrinsics::custom(160, 120, c.camera.fx / 2, c.camera.fy / 2, 79.5, 59.5);
  c.planner = planner;
  c.views = views;
  c.gain.rays_x = 32;
  c.gain.rays_y = 24;
  return c;
}

std::shared_ptr<Plant> plantAt(int seed, double yaw_deg,
                               const Eigen::Vector3d& base = paperPlantBase())
{
  auto plant =
      std::make_shared<Plant>(TomatoPlantGenerator(defaultPlantConfig(seed)).generate());
  posePlant(*plant, base, yaw_deg * M_PI / 180.0);
  return plant;
}

std::vector<EvaluationLevel> levelsOf(const Plant& plant)
{
  return {{"whole_plant", wholePlantRoi(plant)},
          {"leaf_nodes", leafNodeRoi(plant), true}};
}

/// A trial on `plant` attending to `attention`, scored at levelsOf(plant), not run yet.
std::unique_ptr<Trial> setUpTrial(const TrialConfig& config,
                                  const std::shared_ptr<Plant>& plant,
                                  const Roi& attention)
{
  auto trial = std::make_unique<Trial>(config);
  trial->setPlant(plant);
  trial->setAttentionRoi(attention);
  trial->setEvaluationLevels(levelsOf(*plant));
  return trial;
}

TrialResult runTrial(const TrialConfig& config, const std::shared_ptr<Plant>& plant,
                     const Roi& attention)
{
  TrialResult result;
  setUpTrial(config, plant, attention)->run(result);
  return result;
}

/// Everything of two trials but their timings.
void expectSameSteps(const TrialResult& a, const TrialResult& b)
{
  ASSERT_EQ(a.steps.size(), b.steps.size());
  for (std::size_t i = 0; i < a.steps.size(); ++i) {
    const TrialStep& s = a.steps[i];
    const TrialStep& t = b.steps[i];
    EXPECT_EQ(s.view.position, t.view.position) << i;
    EXPECT_EQ(s.view.orientation.coeffs(), t.view.orientation.coeffs()) << i;
    EXPECT_TRUE(s.gain == t.gain || (std::isnan(s.gain) && std::isnan(t.gain))) << i;
    EXPECT_EQ(s.unknown_seen, t.unknown_seen) << i;
    EXPECT_EQ(s.candidates, t.candidates) << i;
    EXPECT_EQ(s.occupied_voxels, t.occupied_voxels) << i;
    ASSERT_EQ(s.organs.size(), t.organs.size());
    for (std::size_t o = 0; o < s.organs.size(); ++o)
      EXPECT_TRUE(s.organs[o].recall == t.organs[o].recall ||
                  (std::isnan(s.organs[o].recall) && std::isnan(t.organs[o].recall)));
    ASSERT_EQ(s.scores.size(), t.scores.size());
    for (std::size_t l = 0; l < s.scores.size(); ++l) {
      EXPECT_EQ(s.scores[l].precision, t.scores[l].precision) << i;
      EXPECT_EQ(s.scores[l].recall, t.scores[l].recall) << i;
      EXPECT_EQ(s.scores[l].f1, t.scores[l].f1) << i;
      EXPECT_EQ(s.scores[l].reconstruction_points, t.scores[l].reconstruction_points)
          << i;
      EXPECT_TRUE(s.scores[l].chamfer == t.scores[l].chamfer ||
                  (std::isnan(s.scores[l].chamfer) && std::isnan(t.scores[l].chamfer)));
    }
  }
}

} // namespace

TEST(Trial, StartsAtV0MovedWithThePlantAndScoresEveryView)
{
  const auto plant = plantAt(0, 0.0, Eigen::Vector3d(1.5, -0.2, 0.5));
  const TrialResult r =
      runTrial(smallConfig(PlannerKind::nbv, 3), plant, wholePlantRoi(*plant));
  ASSERT_EQ(r.steps.size(), 3u);
  ASSERT_EQ(r.level_names, (std::vector<std::string>{"whole_plant", "leaf_nodes"}));
  EXPECT_TRUE(
      r.steps[0].view.position.isApprox(Eigen::Vector3d(1.146, 0.153, 1.083), 1e-12));
  EXPECT_TRUE(std::isnan(r.steps[0].gain));
  EXPECT_EQ(r.steps[0].candidates, 0u);
  for (std::size_t i = 0; i < r.steps.size(); ++i) {
    EXPECT_EQ(r.steps[i].index, int(i));
    ASSERT_EQ(r.steps[i].scores.size(), 2u);
    ASSERT_EQ(r.steps[i].organs.size(), evaluatedOrgans().size());
    EXPECT_GT(r.steps[i].organs[0].recall, 0.0); // the stem, seen from v0 on
    EXPECT_GT(r.steps[i].organs[0].reference_points, 0u);
    EXPECT_GT(r.steps[i].occupied_voxels, 0u);
    EXPECT_GT(r.steps[i].scores[0].f1, 0.0);
    if (i > 0) {
      EXPECT_EQ(r.steps[i].candidates, 27u);
      EXPECT_GT(r.steps[i].gain, 0.0);
      // More views, more of the plant: the map only grows here (no noise).
      EXPECT_GE(r.steps[i].scores[0].recall, r.steps[i - 1].scores[0].recall);
      for (std::size_t o = 0; o < r.steps[i].organs.size(); ++o)
        EXPECT_FALSE(r.steps[i].organs[o].recall < r.steps[i - 1].organs[o].recall);
    }
  }
}

TEST(Trial, SameSeedSameTrialOnOneAndTwoThreads)
{
  const auto plant = plantAt(1, 30.0);
  for (PlannerKind kind : {PlannerKind::nbv, PlannerKind::random}) {
    TrialConfig config = smallConfig(kind, 4);
    config.seed = 7;
    config.threads = 1;
    const TrialResult one = runTrial(config, plant, leafNodeRoi(*plant));
    config.threads = 2;
    const TrialResult two = runTrial(config, plant, leafNodeRoi(*plant));
    expectSameSteps(one, two);
    // Another seed draws other candidates.
    config.seed = 8;
    const TrialResult other = runTrial(config, plant, leafNodeRoi(*plant));
    EXPECT_NE(other.steps[1].view.position, one.steps[1].view.position)
        << plannerKindName(kind);
  }
}

TEST(Trial, WithoutTheFullMapTheStepsAndScoresAreTheFullMaps)
{
  // The update region (setKeepFullMap(false)) leaves free space out of the map, but
  // not a voxel that planning or scoring reads: every step equals the full map's.
  const auto plant = plantAt(3, 30.0);
  struct Case {
    PlannerKind planner;
    Roi attention;
    double depth_scale;
    double explore_share;
    RoiSourceKind source = RoiSourceKind::oracle;
    bool visibility_weighted = false;
  };
  const Case cases[] = {
      {PlannerKind::nbv, wholePlantRoi(*plant), 0.0, 0.0},
      {PlannerKind::nbv, leafNodeRoi(*plant), 0.0, 0.0},
      {PlannerKind::nbv, mainStemRoi(*plant), 1000.0, 0.0},
      {PlannerKind::nbv, leafNodeRoi(*plant), 0.0, 0.5},
      {PlannerKind::predefined, wholePlantRoi(*plant), 0.0, 0.0},
      {PlannerKind::random, leafNodeRoi(*plant), 0.0, 0.0},
      // Plans that may read any voxel: only the last frame leaves free space out.
      {PlannerKind::nbv, leafNodeRoi(*plant), 0.0, 0.0, RoiSourceKind::detections},
      {PlannerKind::nbv, wholePlantRoi(*plant), 0.0, 0.0, RoiSourceKind::oracle, true},
  };
  for (const Case& k : cases) {
    TrialConfig config = smallConfig(k.planner, 5);
    config.seed = 5;
    config.depth_scale = k.depth_scale;
    config.explore_share = k.explore_share;
    config.roi_source.kind = k.source;
    config.gain.visibility_weighted = k.visibility_weighted;
    TrialResult full_result, part_result;
    const auto full = setUpTrial(config, plant, k.attention);
    full->setExplorationRoi(wholePlantRoi(*plant));
    full->run(full_result);
    const auto part = setUpTrial(config, plant, k.attention);
    part->setExplorationRoi(wholePlantRoi(*plant));
    part->setKeepFullMap(false);
    part->run(part_result);
    SCOPED_TRACE(std::string(plannerKindName(k.planner)) + " " +
                 k.attention.boxes().front().name);
    expectSameSteps(full_result, part_result);
    // The same occupied voxels, with less free space around them.
    CloudXYZ full_occupied, part_occupied;
    full->getMap().getOccupiedVoxelCentres(full_occupied);
    part->getMap().getOccupiedVoxelCentres(part_occupied);
    ASSERT_EQ(full_occupied.size(), part_occupied.size());
    for (std::size_t i = 0; i < full_occupied.size(); ++i)
      ASSERT_EQ(full_occupied[i].getVector3fMap(), part_occupied[i].getVector3fMap());
    const bool plans_read_roi_only =
        k.source == RoiSourceKind::oracle && !k.visibility_weighted;
    EXPECT_LT(part->getMap().countVoxels().free,
              full->getMap().countVoxels().free / (plans_read_roi_only ? 2 : 1));
  }
}

TEST(Trial, TrialsThatStartAlikeTakeTheMapAfterV0FromTheCacheWithTheSameResults)
{
  // The same scene, camera, v0, map parameters and update region give the same map
  // after v0: a trial then takes a copy of an earlier one's (no capture), and its steps
  // and scores equal those of the trial on its own.
  const auto plant = plantAt(3, 30.0);
  const SensorScene::ConstPtr scene = makePlantScene(*plant);
  const auto cache = std::make_shared<InitialViewCache>();
  struct Case {
    PlannerKind planner;
    Roi attention;
    bool keep_full_map;
    double depth_scale;
    bool noise;
    bool from_cache;  ///< v0's map is an earlier case's
    std::size_t kept; ///< maps in the cache afterwards
  };
  const Case cases[] = {
      {PlannerKind::nbv, wholePlantRoi(*plant), false, 0.0, false, false, 1},
      {PlannerKind::random, wholePlantRoi(*plant), false, 0.0, false, true, 1},
      {PlannerKind::predefined, wholePlantRoi(*plant), false, 0.0, false, true, 1},
      // Another ROI, another update region.
      {PlannerKind::nbv, leafNodeRoi(*plant), false, 0.0, false, false, 2},
      // The full map (no region), then from it.
      {PlannerKind::nbv, leafNodeRoi(*plant), true, 0.0, false, false, 3},
      {PlannerKind::random, mainStemRoi(*plant), true, 0.0, false, true, 3},
      // Depth rounded: another frame.
      {PlannerKind::nbv, wholePlantRoi(*plant), false, 1000.0, false, false, 4},
      // Noise: every frame its own.
      {PlannerKind::nbv, wholePlantRoi(*plant), false, 0.0, true, false, 4},
  };
  for (const Case& k : cases) {
    TrialConfig config = smallConfig(k.planner, 3);
    config.seed = 5;
    config.depth_scale = k.depth_scale;
    config.noise.enabled = k.noise;
    auto run = [&](const InitialViewCache::Ptr& initial_views) {
      const auto trial = setUpTrial(config, plant, k.attention);
      trial->setScene(scene);
      trial->setKeepFullMap(k.keep_full_map);
      trial->setInitialViewCache(initial_views);
      TrialResult result;
      trial->run(result);
      return result;
    };
    const TrialResult alone = run(nullptr);
    const TrialResult shared = run(cache);
    SCOPED_TRACE(std::string(plannerKindName(k.planner)) + " " +
                 k.attention.boxes().front().name + (k.keep_full_map ? " full" : ""));
    expectSameSteps(alone, shared);
    ASSERT_FALSE(shared.steps.empty());
    if (k.from_cache) {
      EXPECT_EQ(shared.steps[0].capture_ms, 0.0);
    } else {
      EXPECT_GT(shared.steps[0].capture_ms, 0.0);
    }
    EXPECT_EQ(cache->size(), k.kept);
  }
  // Another scene (of the same plant) is not the same scene; with room for one map, the
  // last one stays.
  const auto one = std::make_shared<InitialViewCache>(1);
  for (int i = 0; i < 2; ++i) {
    const auto trial = setUpTrial(smallConfig(PlannerKind::random, 1), plant, Roi());
    trial->setScene(makePlantScene(*plant));
    trial->setInitialViewCache(one);
    TrialResult result;
    trial->run(result);
    EXPECT_GT(result.steps.at(0).capture_ms, 0.0);
  }
  EXPECT_EQ(one->size(), 1u);
  EXPECT_THROW(InitialViewCache(0), InvalidArgumentError);
}

TEST(Trial, KeepsTheFullMapWhereItsReadsAreNotKnownBeforehand)
{
  // No attention ROI: the planner reads every voxel, so the frames it plans from go
  // whole into the map; the last frame, read by the scores only, goes into the voxels
  // near the surface.
  const auto plant = plantAt(3, 30.0);
  TrialConfig config = smallConfig(PlannerKind::nbv, 2);
  TrialResult full_result, part_result;
  const auto full = setUpTrial(config, plant, Roi());
  full->run(full_result);
  const auto part = setUpTrial(config, plant, Roi());
  part->setKeepFullMap(false);
  part->run(part_result);
  expectSameSteps(full_result, part_result);
  config.views = 1;
  const auto first = setUpTrial(config, plant, Roi());
  first->run(full_result);
  const std::size_t first_free = first->getMap().countVoxels().free;
  EXPECT_GE(part->getMap().countVoxels().free, first_free);
  EXPECT_LT(part->getMap().countVoxels().free, full->getMap().countVoxels().free);
  // The region of a single view holds no ROI: its only frame, the last, goes into the
  // voxels near the surface.
  const auto single = setUpTrial(config, plant, wholePlantRoi(*plant));
  single->setKeepFullMap(false);
  single->run(part_result);
  EXPECT_LT(single->getMap().countVoxels().free, first_free / 2);
  config.views = 2;

  // A sector of tens of metres: a region would cost more than it saves, and must not
  // fail the trial.
  config.sector.radius_m = 40.0;
  const auto far_full = setUpTrial(config, plant, wholePlantRoi(*plant));
  far_full->run(full_result);
  const auto far_part = setUpTrial(config, plant, wholePlantRoi(*plant));
  far_part->setKeepFullMap(false);
  far_part->run(part_result);
  expectSameSteps(full_result, part_result);
  EXPECT_EQ(far_part->getMap().countVoxels().free, far_full->getMap().countVoxels().free);
}

TEST(Trial, PredefinedPlannerVisitsTheGridCentresInItsPattern)
{
  const auto plant = plantAt(0, 0.0);
  TrialConfig config = smallConfig(PlannerKind::predefined, 11);
  config.pattern = 3;
  Trial trial(config);
  trial.setPlant(plant);
  trial.setEvaluationLevels(levelsOf(*plant));
  TrialResult r;
  trial.run(r);
  ASSERT_EQ(r.steps.size(), 11u);
  CylindricalSectorSampler sampler(trial.getSector());
  const std::vector<Viewpoint> centres = sampler.gridCellCentres();
  const std::vector<int> order = PredefinedPlanner::patternOrder(3);
  ASSERT_EQ(order.size(), 9u);
  for (int k = 0; k < 10; ++k)
    EXPECT_TRUE(
        r.steps[k + 1].view.position.isApprox(centres[order[k % 9]].position, 1e-12))
        << k;
  // The sector stands on the plant.
  EXPECT_EQ(trial.getSector().axis_base, plant->base_position);
}

TEST(Trial, LeafNodeAttentionReconstructsLeafNodesAtLeastAsFastAsRandom)
{
  // Mean leaf-node F1 over views 2-5, averaged over three yaws of one plant.
  double nbv = 0.0, random = 0.0;
  for (double yaw : {0.0, 120.0, 240.0}) {
    const auto plant = plantAt(4, yaw);
    for (PlannerKind kind : {PlannerKind::nbv, PlannerKind::random}) {
      TrialConfig config = smallConfig(kind, 5);
      config.seed = 11;
      const TrialResult r = runTrial(config, plant, leafNodeRoi(*plant));
      const std::vector<double> f1 = r.f1Curve(1);
      for (std::size_t i = 1; i < f1.size(); ++i)
        (kind == PlannerKind::nbv ? nbv : random) += f1[i];
    }
  }
  EXPECT_GE(nbv, random);
}

TEST(Trial, ANoisyRoiSourceWithSigmaZeroIsTheOracleBitForBit)
{
  const auto plant = plantAt(2, 60.0);
  TrialConfig config = smallConfig(PlannerKind::nbv, 4);
  config.seed = 3;
  const auto oracle = setUpTrial(config, plant, leafNodeRoi(*plant));
  TrialResult truth;
  oracle->run(truth);
  ASSERT_EQ(oracle->getAttendedRoi().size(), leafNodeRoi(*plant).size());

  config.roi_source.kind = RoiSourceKind::noisy;
  expectSameSteps(runTrial(config, plant, leafNodeRoi(*plant)), truth);

  // With an error, the planner attends to other boxes (drawn from the trial's seed, the
  // ones RoiSource::apply gives with roiSourceSeed), and so plans other views; the
  // evaluation levels stay the true ones.
  config.roi_source.sigma_m = 0.03;
  const auto noisy = setUpTrial(config, plant, leafNodeRoi(*plant));
  TrialResult moved;
  noisy->run(moved);
  const Roi expected = config.roi_source.apply(leafNodeRoi(*plant), roiSourceSeed(3));
  ASSERT_EQ(noisy->getAttendedRoi().size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(noisy->getAttendedRoi().boxes()[i].center, expected.boxes()[i].center);
    EXPECT_NE(noisy->getAttendedRoi().boxes()[i].center,
              leafNodeRoi(*plant).boxes()[i].center);
  }
  EXPECT_EQ(moved.steps[0].scores[1].reference_points,
            truth.steps[0].scores[1].reference_points);
  bool other_view = false;
  for (std::size_t i = 1; i < moved.steps.size(); ++i)
    other_view =
        other_view || moved.steps[i].view.position != truth.steps[i].view.position;
  EXPECT_TRUE(other_view);
}

TEST(Trial, DetectionsFindTheLeafNodesAndWithoutFindsTheTrialExplores)
{
  const auto plant = plantAt(2, 60.0);
  const Roi nodes = leafNodeRoi(*plant);
  TrialConfig config = smallConfig(PlannerKind::nbv, 4);
  config.seed = 5;
  config.roi_source.kind = RoiSourceKind::detections;
  const auto trial = setUpTrial(config, plant, nodes);
  std::size_t frames_with_detections = 0;
  trial->setFrameCallback([&](const TrialFrame& f) {
    ASSERT_NE(f.detections, nullptr);
    for (const Detection& d : *f.detections)
      EXPECT_EQ(d.class_name, "leaf_node"); // the boxes' names, "leaf_node_<k>"
    frames_with_detections += !f.detections->empty();
  });
  TrialResult result;
  trial->run(result);
  EXPECT_GT(frames_with_detections, 0u);
  // Each fused box lies on a true node: its centre within a node box grown by 1 cm.
  const Roi& found = trial->getAttendedRoi();
  ASSERT_FALSE(found.empty());
  EXPECT_LE(found.size(), nodes.size());
  for (const Box& box : found.boxes()) {
    bool on_a_node = false;
    for (const Box& node : nodes.boxes())
      on_a_node =
          on_a_node || Box(node.center, node.size + Eigen::Vector3d::Constant(0.02))
                           .contains(box.center);
    EXPECT_TRUE(on_a_node) << box.center.transpose();
  }

  // A detector that finds nothing leaves the ROI empty: the planner attends to every
  // voxel, as a trial without an attention ROI does, step for step.
  config.roi_source.detector_recall = 0.0;
  const auto blind = setUpTrial(config, plant, nodes);
  TrialResult explored;
  blind->run(explored);
  EXPECT_TRUE(blind->getAttendedRoi().empty());
  TrialConfig plain = smallConfig(PlannerKind::nbv, 4);
  plain.seed = 5;
  expectSameSteps(explored, runTrial(plain, plant, Roi()));
}

TEST(Trial, DetectionsAloneExploreTheWholePlantAfterTheFirstView)
{
  // The first plan ranks by the whole plant's gain (RoiSource::detections_explore_views
  // 1): the view of NBV-whole-plant, whatever v0's finds; with 0 the finds' own.
  const auto plant = plantAt(2, 60.0);
  TrialConfig config = smallConfig(PlannerKind::nbv, 3);
  config.seed = 5;
  const TrialResult whole = runTrial(config, plant, wholePlantRoi(*plant));
  config.roi_source.kind = RoiSourceKind::detections;
  auto run = [&](const TrialConfig& c) {
    const auto trial = setUpTrial(c, plant, leafNodeRoi(*plant));
    trial->setExplorationRoi(wholePlantRoi(*plant));
    TrialResult result;
    trial->run(result);
    return result;
  };
  const TrialResult explores = run(config);
  EXPECT_EQ(explores.steps[1].view.position, whole.steps[1].view.position);
  config.roi_source.detections_explore_views = 0;
  const TrialResult attends = run(config);
  EXPECT_NE(attends.steps[1].view.position, whole.steps[1].view.position);
  config.roi_source.kind = RoiSourceKind::prior; // only detections alone explore
  EXPECT_THROW(Trial{config}, InvalidArgumentError);
}

TEST(Trial, ThePriorPredictsNodesOnTheStemAndTheDetectionsComeFirst)
{
  const auto plant = plantAt(2, 60.0);
  const Roi nodes = leafNodeRoi(*plant);
  TrialConfig config = smallConfig(PlannerKind::nbv, 3);
  config.seed = 5;
  config.roi_source.kind = RoiSourceKind::prior;
  const auto trial = setUpTrial(config, plant, nodes);
  TrialResult result;
  trial->run(result);
  const Roi predicted = trial->getAttendedRoi();
  ASSERT_GE(predicted.size(), 3u);
  for (const Box& box : predicted.boxes()) {
    EXPECT_EQ(box.name.rfind("leaf_node_prior_", 0), 0u) << box.name;
    // On the stem: near the plant's vertical axis, above its base.
    EXPECT_LT((box.center - plant->base_position).head<2>().norm(), 0.03);
    EXPECT_GT(box.center.z(), plant->base_position.z());
  }

  // With detections, their boxes come first, then the prediction as without them: one
  // internode apart from the first node above the base.
  config.roi_source.kind = RoiSourceKind::detections_prior;
  const auto both = setUpTrial(config, plant, nodes);
  both->run(result);
  const Roi& attended = both->getAttendedRoi();
  std::size_t found = 0;
  while (found < attended.size() &&
         attended.boxes()[found].name.rfind("leaf_node_prior_", 0) != 0)
    ++found;
  EXPECT_GT(found, 0u);
  ASSERT_GT(attended.size(), found);
  const LeafNodePrior::Config rules = config.roi_source.priorConfig();
  for (std::size_t k = found; k < attended.size(); ++k) {
    EXPECT_EQ(attended.boxes()[k].name, "leaf_node_prior_" + std::to_string(k - found));
    EXPECT_NEAR(attended.boxes()[k].center.z(),
                plant->base_position.z() + rules.first_node_m +
                    rules.internode_m * double(k - found),
                1e-9);
  }
}

TEST(Trial, RejectsABadConfigOrAMissingPlant)
{
  TrialConfig c;
  c.views = 0;
  EXPECT_THROW(Trial{c}, InvalidArgumentError);
  c = TrialConfig();
  c.pattern = 5;
  EXPECT_THROW(Trial{c}, InvalidArgumentError);
  c = TrialConfig();
  c.planner = PlannerKind::predefined;
  c.grid_rows = 4;
  EXPECT_THROW(Trial{c}, InvalidArgumentError);
  c = TrialConfig();
  c.sector.radius_m = -1.0;
  EXPECT_THROW(Trial{c}, InvalidArgumentError);
  c = TrialConfig();
  c.roi_source.sigma_m = 0.01; // the oracle would ignore it
  try {
    Trial{c};
    ADD_FAILURE() << "accepted";
  } catch (const InvalidArgumentError& e) {
    EXPECT_EQ(std::string(e.what()), "trial config: roi_sigma 0.01: only the noisy ROI "
                                     "source uses it (roi_source is oracle)");
  }
  Trial trial;
  TrialResult r;
  EXPECT_THROW(trial.run(r), InvalidArgumentError);
  EXPECT_EQ(plannerKindFromName("random"), PlannerKind::random);
  EXPECT_THROW(plannerKindFromName("greedy"), InvalidArgumentError);
}

TEST(Trial, RejectsNonFiniteNumbersAndConfigsOverTheMemoryCap)
{
  TrialConfig c;
  c.initial_view.position.x() = std::nan("");
  EXPECT_THROW(c.validate(), InvalidArgumentError);
  c = TrialConfig();
  c.initial_view.orientation.coeffs().setConstant(
      std::numeric_limits<double>::infinity());
  EXPECT_THROW(c.validate(), InvalidArgumentError);
  c = TrialConfig();
  c.time_limit_s = std::nan("");
  EXPECT_THROW(c.validate(), InvalidArgumentError);

  // The paper's 3 mm fits the default cap; 0.5 mm (216 x the voxels) does not, and the
  // message gives the estimate.
  c = TrialConfig();
  EXPECT_NO_THROW(c.validate());
  EXPECT_GT(c.estimatedMemoryBytes(), 0.1e9);
  EXPECT_LT(c.estimatedMemoryBytes(), 0.5e9);
  c.map.resolution_m = 0.0005;
  EXPECT_GT(c.estimatedMemoryBytes(), c.memory_cap_bytes);
  try {
    c.validate();
    ADD_FAILURE() << "0.5 mm was accepted";
  } catch (const InvalidArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("GiB, over the memory cap of 8 GiB"),
              std::string::npos)
        << e.what();
  }
  c.memory_cap_bytes = 1e12;
  EXPECT_NO_THROW(c.validate());
}

TEST(Trial, StopsWithTimeLimitErrorOnceItsTimeIsUp)
{
  const auto plant = plantAt(0, 0.0);
  TrialConfig c = smallConfig(PlannerKind::random, 5);
  c.time_limit_s = 1e-6; // passed after the setup already
  try {
    runTrial(c, plant, wholePlantRoi(*plant));
    ADD_FAILURE() << "no TimeLimitError";
  } catch (const TimeLimitError& e) {
    EXPECT_NE(
        std::string(e.what()).find("trial time limit of 1e-06 s passed after setup"),
        std::string::npos)
        << e.what();
  }
  c.time_limit_s = 600.0; // far away: the trial runs all its views
  EXPECT_EQ(runTrial(c, plant, wholePlantRoi(*plant)).steps.size(), 5u);
}
