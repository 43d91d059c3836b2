#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/reconstruction_evaluator.h>
#include <plantnbv/plant/plant_rois.h>
#include <plantnbv/plant/tomato_plant_generator.h>
#include <plantnbv/sensor/sensor_scene.h>

using namespace plantnbv;

namespace {

/// A plant that is a flat 6 x 6 cm square at height z (two triangles, no anatomy).
Plant squarePlant(double z)
{
  Plant plant;
  plant.name = "square";
  plant.mesh.vertices = {{0.0f, 0.0f, float(z)},
                         {0.06f, 0.0f, float(z)},
                         {0.06f, 0.06f, float(z)},
                         {0.0f, 0.06f, float(z)}};
  plant.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  plant.mesh.labels = {PartLabel::leaflet, PartLabel::leaflet};
  return plant;
}

/// A 10 x 10 cm plate under the square plant, its top face at z = 0.
TriangleMesh supportPlate()
{
  return supportMesh(Eigen::Vector3d(0.03, 0.03, 0.0), 0.05, -0.5);
}

Box boxAround(double x0, double x1)
{
  return Box::fromMinMax({x0, -0.01, 0.0}, {x1, 0.07, 0.02});
}

/// The map of a square plant of 12 x 12 voxels of `res` lying on the support plate:
/// every voxel of the bottom layer of x, y in [-2, 13] (the plant's rows y < `plant_rows`
/// and the support's), a row of noise above the support, and 4 voxels far from it.
CloudXYZ mapOverTheSupport(double res, int plant_rows)
{
  CloudXYZ map;
  auto add = [&](int x, int y, int z) {
    map.push_back(pcl::PointXYZ(float((x + 0.5) * res), float((y + 0.5) * res),
                                float((z + 0.5) * res)));
  };
  for (int x = -2; x <= 13; ++x)
    for (int y = -2; y <= 13; ++y)
      if (x < 0 || x > 11 || y < 0 || y > 11 || y < plant_rows)
        add(x, y, 0);
  for (int x = -2; x <= 13; ++x)
    add(x, -2, 1);
  for (int x = 0; x < 4; ++x)
    add(x, 5, 6);
  return map;
}

} // namespace

TEST(ReconstructionEvaluator, GroundTruthIsOnTheMapsVoxelLattice)
{
  ReconstructionEvaluator evaluator;
  evaluator.setResolution(0.003);
  evaluator.setGroundTruth(squarePlant(0.0105)); // inside voxel k = 3 along z
  const CloudXYZ& truth = evaluator.getGroundTruth();
  ASSERT_EQ(truth.size(), 20u * 20u); // 6 cm / 3 mm per side
  for (const auto& p : truth) {
    EXPECT_FLOAT_EQ(p.z, float(3.5 * 0.003));
    const double i = p.x / 0.003 - 0.5;
    EXPECT_NEAR(i, std::round(i), 1e-4);
  }
}

TEST(ReconstructionEvaluator, ScoresLevelsAndAveragesBoxes)
{
  ReconstructionEvaluator evaluator;
  evaluator.setGroundTruth(squarePlant(0.0105));
  Roi halves;
  halves.addBox(boxAround(-0.01, 0.03)); // x voxels 0-9
  halves.addBox(boxAround(0.03, 0.07));  // x voxels 10-19
  evaluator.setLevels({{"whole", Roi({boxAround(-0.01, 0.07)})},
                       {"halves", halves, /*average_boxes=*/true}});

  // The reconstruction: exactly the ground truth of the left half.
  CloudXYZ left;
  for (const auto& p : evaluator.getGroundTruth())
    if (p.x < 0.03f)
      left.push_back(p);
  ASSERT_EQ(left.size(), 200u);
  std::vector<LevelScore> scores;
  evaluator.compute(left, scores);
  ASSERT_EQ(scores.size(), 2u);
  // Whole: all of it is right, half of the plant is found.
  EXPECT_DOUBLE_EQ(scores[0].precision, 1.0);
  EXPECT_DOUBLE_EQ(scores[0].recall, 0.5);
  EXPECT_DOUBLE_EQ(scores[0].f1, 2.0 / 3.0);
  EXPECT_EQ(scores[0].reference_points, 400u);
  EXPECT_EQ(scores[0].reconstruction_points, 200u);
  // Halves, averaged: the left box is perfect, the right one empty (0, Chamfer undefined
  // there, so the mean Chamfer is the left box's: 0).
  EXPECT_DOUBLE_EQ(scores[1].precision, 0.5);
  EXPECT_DOUBLE_EQ(scores[1].recall, 0.5);
  EXPECT_DOUBLE_EQ(scores[1].f1, 0.5);
  EXPECT_DOUBLE_EQ(scores[1].chamfer, 0.0);

  evaluator.compute(CloudXYZ(), scores);
  EXPECT_EQ(scores[0].f1, 0.0);
  EXPECT_TRUE(std::isnan(scores[0].chamfer));
  EXPECT_TRUE(std::isnan(scores[1].chamfer));
}

TEST(ReconstructionEvaluator, RecallPerOrganCountsAVoxelForEveryOrganInIt)
{
  // A stem square (x voxels 0-19) and a fruit square from x = 5.85 cm (voxels 19-39):
  // voxel column 19 holds both.
  Plant plant = squarePlant(0.0105);
  const TriangleMesh stem = plant.mesh;
  for (Eigen::Vector3f v : stem.vertices) {
    v.x() += 0.0585f;
    plant.mesh.vertices.push_back(v);
  }
  plant.mesh.triangles.push_back({4, 5, 6});
  plant.mesh.triangles.push_back({4, 6, 7});
  plant.mesh.labels = {PartLabel::stem, PartLabel::stem, PartLabel::fruit,
                       PartLabel::fruit};
  ReconstructionEvaluator evaluator;
  evaluator.setGroundTruth(plant);
  ASSERT_EQ(evaluator.getGroundTruth().size(), 40u * 20u);

  CloudXYZ left; // voxel columns 0-9: half of the stem
  for (const auto& p : evaluator.getGroundTruth())
    if (p.x < 0.03f)
      left.push_back(p);
  std::vector<OrganRecall> organs;
  evaluator.computeOrganRecall(left, organs);
  ASSERT_EQ(organs.size(), evaluatedOrgans().size());
  ASSERT_EQ(organs.size(), 6u); // stem, petiole, leaflet, peduncle, fruit, flower
  for (std::size_t o = 0; o < organs.size(); ++o) {
    const OrganRecall& r = organs[o];
    EXPECT_EQ(r.organ, evaluatedOrgans()[o]);
    if (r.organ == PartLabel::stem) {
      EXPECT_EQ(r.reference_points, 20u * 20u);
      EXPECT_DOUBLE_EQ(r.recall, 0.5);
    } else if (r.organ == PartLabel::fruit) {
      EXPECT_EQ(r.reference_points, 21u * 20u);
      EXPECT_EQ(r.recall, 0.0);
    } else {
      EXPECT_EQ(r.reference_points, 0u);
      EXPECT_TRUE(std::isnan(r.recall)) << partLabelName(r.organ);
    }
  }
  evaluator.computeOrganRecall(evaluator.getGroundTruth(), organs);
  EXPECT_EQ(organs[0].recall, 1.0); // stem
  EXPECT_EQ(organs[4].recall, 1.0); // fruit

  // Without labels every organ is missing.
  plant.mesh.labels.clear();
  evaluator.setGroundTruth(plant);
  evaluator.computeOrganRecall(evaluator.getGroundTruth(), organs);
  for (const OrganRecall& r : organs)
    EXPECT_EQ(r.reference_points, 0u);
}

TEST(ReconstructionEvaluator, LeavesTheBackgroundsVoxelsOut)
{
  // A support whose top face (z = 0) is the bottom face of the box, as in the default
  // scene; at 5 mm the lattice puts the centres of the voxels it passes through inside
  // the box. The plant lies on it, in those voxels too.
  const double res = 0.005;
  const Roi box({Box::fromMinMax({-0.01, -0.01, 0.0}, {0.07, 0.07, 0.04})});
  TriangleMesh support = supportPlate();
  ReconstructionEvaluator evaluator;
  evaluator.setResolution(res);
  evaluator.setGroundTruth(squarePlant(0.0025)); // 12 x 12 voxels in the layer k = 0
  ASSERT_EQ(evaluator.getGroundTruth().size(), 144u);
  evaluator.setLevels({{"whole", box}});
  EXPECT_EQ(evaluator.backgroundVoxelCount(), 0u);

  const CloudXYZ map = mapOverTheSupport(res, 12);
  std::vector<LevelScore> without, with;
  evaluator.compute(map, without);
  EXPECT_EQ(without[0].reconstruction_points, 276u);
  // (Neighbours exactly rho apart may match through float rounding: not asserted.)
  EXPECT_LT(without[0].precision, 0.75);

  evaluator.setBackground(support);
  EXPECT_GT(evaluator.backgroundVoxelCount(), 112u + 16u);
  evaluator.compute(map, with);
  EXPECT_EQ(with[0].reconstruction_points, 148u); // the plant's and the far ones
  EXPECT_DOUBLE_EQ(with[0].precision, 144.0 / 148.0);
  EXPECT_DOUBLE_EQ(with[0].recall, without[0].recall);
  EXPECT_DOUBLE_EQ(with[0].recall, 1.0);

  // Scores and organ recall in one call (the background left out once): the same as
  // the two calls.
  std::vector<LevelScore> together;
  std::vector<OrganRecall> organs, organs_alone;
  evaluator.compute(map, together, organs);
  evaluator.computeOrganRecall(map, organs_alone);
  ASSERT_EQ(together.size(), 1u);
  EXPECT_EQ(together[0].reconstruction_points, with[0].reconstruction_points);
  EXPECT_EQ(together[0].reference_points, with[0].reference_points);
  EXPECT_EQ(together[0].precision, with[0].precision);
  EXPECT_EQ(together[0].recall, with[0].recall);
  EXPECT_EQ(together[0].chamfer, with[0].chamfer);
  ASSERT_EQ(organs.size(), organs_alone.size());
  for (std::size_t o = 0; o < organs.size(); ++o) {
    EXPECT_EQ(organs[o].reference_points, organs_alone[o].reference_points);
    EXPECT_TRUE(organs[o].recall == organs_alone[o].recall ||
                (std::isnan(organs[o].recall) && std::isnan(organs_alone[o].recall)));
  }
  EXPECT_EQ(organs[2].organ, PartLabel::leaflet);
  EXPECT_EQ(organs[2].reference_points, 144u);
  EXPECT_EQ(organs[2].recall, 1.0);

  // The same whether the background or the levels come first.
  ReconstructionEvaluator reordered;
  reordered.setResolution(res);
  reordered.setGroundTruth(squarePlant(0.0025));
  reordered.setBackground(support);
  reordered.setLevels({{"whole", box}});
  EXPECT_EQ(reordered.backgroundVoxelCount(), evaluator.backgroundVoxelCount());
  std::vector<LevelScore> again;
  reordered.compute(map, again);
  EXPECT_EQ(again[0].reconstruction_points, 148u);

  support.triangles.push_back({0, 1, 99});
  EXPECT_THROW(evaluator.setBackground(support), FormatError);
}

TEST(ReconstructionEvaluator, ScoresAndOrganRecallDoNotDependOnTheThreadCount)
{
  // On two threads or more the levels' parts and the organs' distances are scored side
  // by side: the same numbers as on one thread, call after call (each part keeps the
  // distances of the call before).
  const Plant plant = TomatoPlantGenerator(defaultPlantConfig(2)).generate();
  const std::vector<EvaluationLevel> levels = {{"whole_plant", wholePlantRoi(plant)},
                                               {"main_stem", mainStemRoi(plant)},
                                               {"leaf_nodes", leafNodeRoi(plant), true},
                                               {"fruit", fruitRoi(plant), true}};
  std::vector<ReconstructionEvaluator> evaluators(3);
  for (std::size_t t = 0; t < evaluators.size(); ++t) {
    evaluators[t].setNumberOfThreads(int(t) + 1);
    evaluators[t].setSeed(5);
    evaluators[t].setGroundTruth(plant);
    evaluators[t].setLevels(levels);
  }
  // Reconstructions that grow: a share of the ground truth, some of it a voxel off.
  const CloudXYZ& truth = evaluators[0].getGroundTruth();
  ASSERT_GT(truth.size(), 1000u);
  CloudXYZ reconstruction;
  for (int call = 0; call < 3; ++call) {
    for (std::size_t i = std::size_t(call); i < truth.size(); i += 5) {
      pcl::PointXYZ p = truth[i];
      if (i % 3 == 0)
        p.z += 0.003f;
      reconstruction.push_back(p);
    }
    std::vector<std::vector<LevelScore>> scores(evaluators.size()), alone(scores);
    std::vector<std::vector<OrganRecall>> organs(evaluators.size()), recall(organs);
    for (std::size_t t = 0; t < evaluators.size(); ++t) {
      evaluators[t].compute(reconstruction, scores[t], organs[t]);
      evaluators[t].compute(reconstruction, alone[t]);
      evaluators[t].computeOrganRecall(reconstruction, recall[t]);
    }
    ASSERT_EQ(scores[0].size(), levels.size());
    EXPECT_GT(scores[0][0].recall, 0.0);
    for (std::size_t t = 1; t < evaluators.size(); ++t)
      for (const auto* other : {&scores[t], &alone[t], &alone[0]}) {
        ASSERT_EQ(other->size(), scores[0].size());
        for (std::size_t l = 0; l < levels.size(); ++l) {
          const LevelScore &a = scores[0][l], &b = (*other)[l];
          EXPECT_EQ(a.precision, b.precision) << call << " " << t << " " << l;
          EXPECT_EQ(a.recall, b.recall) << call << " " << t << " " << l;
          EXPECT_EQ(a.f1, b.f1) << call << " " << t << " " << l;
          EXPECT_EQ(a.reference_points, b.reference_points);
          EXPECT_EQ(a.reconstruction_points, b.reconstruction_points);
          EXPECT_TRUE(a.chamfer == b.chamfer ||
                      (std::isnan(a.chamfer) && std::isnan(b.chamfer)))
              << call << " " << t << " " << l;
        }
      }
    ASSERT_EQ(organs[0].size(), evaluatedOrgans().size());
    EXPECT_GT(organs[0][0].recall, 0.0); // the stem
    for (std::size_t t = 0; t < evaluators.size(); ++t)
      for (const auto* other : {&organs[t], &recall[t]}) {
        ASSERT_EQ(other->size(), organs[0].size());
        for (std::size_t o = 0; o < organs[0].size(); ++o) {
          const OrganRecall &a = organs[0][o], &b = (*other)[o];
          EXPECT_EQ(a.reference_points, b.reference_points);
          EXPECT_TRUE(a.recall == b.recall ||
                      (std::isnan(a.recall) && std::isnan(b.recall)))
              << call << " " << t << " " << o;
        }
      }
  }
}

TEST(ReconstructionEvaluator, ClassifiesTheVoxelsItScores)
{
  // The map of the background test: the plant's 144 voxels, the support's, noise over
  // it and 4 far voxels; half of the plant is left out of this reconstruction.
  const double res = 0.005;
  const Roi box({Box::fromMinMax({-0.01, -0.01, 0.0}, {0.07, 0.07, 0.04})});
  ReconstructionEvaluator evaluator;
  evaluator.setResolution(res);
  evaluator.setGroundTruth(squarePlant(0.0025));
  evaluator.setLevels({{"whole", box}, {"left", Roi({boxAround(-0.01, 0.03)})}});
  evaluator.setBackground(supportPlate());
  const CloudXYZ map = mapOverTheSupport(res, 6); // the plant's upper half is missed

  std::vector<LevelScore> scores;
  evaluator.compute(map, scores);
  for (std::size_t level = 0; level < 2; ++level) {
    SCOPED_TRACE(level);
    VoxelOutcomes outcomes;
    evaluator.classify(map, level, outcomes);
    const LevelScore& s = scores[level];
    // The same voxels as the scores, split as precision and recall count them.
    EXPECT_EQ(outcomes.correct.size() + outcomes.wrong.size(), s.reconstruction_points);
    EXPECT_DOUBLE_EQ(double(outcomes.correct.size()) / double(s.reconstruction_points),
                     s.precision);
    EXPECT_DOUBLE_EQ(double(s.reference_points - outcomes.missed.size()) /
                         double(s.reference_points),
                     s.recall);
  }
  VoxelOutcomes whole;
  evaluator.classify(map, 0, whole);
  EXPECT_EQ(whole.correct.size(), 72u); // 12 x 6 voxels of the plant
  EXPECT_EQ(whole.wrong.size(), 4u);    // the far ones: the support's are background
  // Missed: the ground truth of the upper half, less the voxels next to the lower half
  // that float rounding puts closer than rho (the metrics' rule, computed here by brute
  // force).
  std::size_t missed = 0;
  for (const pcl::PointXYZ& t : evaluator.getGroundTruth()) {
    bool near = false;
    for (const Eigen::Vector3f& r : whole.correct) {
      const double dx = double(t.x) - r.x(), dy = double(t.y) - r.y(),
                   dz = double(t.z) - r.z();
      near = near || std::sqrt(dx * dx + dy * dy + dz * dz) < res;
    }
    missed += !near;
  }
  EXPECT_EQ(whole.missed.size(), missed);
  EXPECT_GE(missed, 60u); // rows 7-11 at least
  for (const Eigen::Vector3f& p : whole.missed)
    EXPECT_GT(p.y(), float(6 * res));
  for (const Eigen::Vector3f& p : whole.wrong)
    EXPECT_FLOAT_EQ(p.z(), float(6.5 * res));

  VoxelOutcomes none;
  EXPECT_THROW(evaluator.classify(map, 2, none), InvalidArgumentError);
}

TEST(ReconstructionEvaluator, RejectsBadInput)
{
  ReconstructionEvaluator evaluator;
  EXPECT_THROW(evaluator.setResolution(0.0), InvalidArgumentError);
  EXPECT_THROW(evaluator.setLevels({{"whole", Roi({boxAround(0, 1)})}}),
               InvalidArgumentError); // no ground truth yet
  EXPECT_THROW(evaluator.setGroundTruth(Plant()), InvalidArgumentError);
  std::vector<LevelScore> scores;
  std::vector<OrganRecall> organs;
  EXPECT_THROW(evaluator.computeOrganRecall(CloudXYZ(), organs), InvalidArgumentError);
  EXPECT_THROW(evaluator.compute(CloudXYZ(), scores, organs), InvalidArgumentError);
  evaluator.setGroundTruth(squarePlant(0.0));
  EXPECT_THROW(evaluator.setLevels({{"whole", Roi()}}), InvalidArgumentError);
  EXPECT_THROW(
      evaluator.setLevels({{"a", Roi({boxAround(0, 1)})}, {"a", Roi({boxAround(0, 1)})}}),
      InvalidArgumentError);
}
