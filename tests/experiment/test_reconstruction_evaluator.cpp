#include <cmath>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/reconstruction_evaluator.h>

using namespace plantnbv;

namespace {

/// A plant that is a flat 6 x 6 cm square at height z (two triangles, no anatomy).
Plant squarePlant(double z)
{
  Plant plant;
  plant.name = "square";
  plant.mesh.vertices = {{0.0f, 0.0f, float(z)}, {0.06f, 0.0f, float(z)},
                         {0.06f, 0.06f, float(z)}, {0.0f, 0.06f, float(z)}};
  plant.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  plant.mesh.labels = {PartLabel::leaflet, PartLabel::leaflet};
  return plant;
}

Box boxAround(double x0, double x1)
{
  return Box::fromMinMax({x0, -0.01, 0.0}, {x1, 0.07, 0.02});
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

TEST(ReconstructionEvaluator, RejectsBadInput)
{
  ReconstructionEvaluator evaluator;
  EXPECT_THROW(evaluator.setResolution(0.0), InvalidArgumentError);
  EXPECT_THROW(evaluator.setLevels({{"whole", Roi({boxAround(0, 1)})}}),
               InvalidArgumentError); // no ground truth yet
  EXPECT_THROW(evaluator.setGroundTruth(Plant()), InvalidArgumentError);
  evaluator.setGroundTruth(squarePlant(0.0));
  EXPECT_THROW(evaluator.setLevels({{"whole", Roi()}}), InvalidArgumentError);
  EXPECT_THROW(evaluator.setLevels({{"a", Roi({boxAround(0, 1)})}, {"a", Roi({boxAround(0, 1)})}}),
               InvalidArgumentError);
}
