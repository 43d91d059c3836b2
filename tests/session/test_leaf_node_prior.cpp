// LeafNodePrior: leaf-node boxes predicted along a synthetic stem, seen whole, in part
// or not at all, with and without anchors.

#include <cmath>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/session/leaf_node_prior.h>

namespace plantnbv {
namespace {

const Eigen::Vector3d kBase(1.0, 0.0, 0.8);

/// Occupied voxels of a stem from the base up to `height_m`, leaning by `lean` (x per z),
/// 3 mm apart and 3 voxels wide; a leaf 6 cm from the axis and the floor below the base.
CloudXYZ stemCloud(double height_m, double lean = 0.0)
{
  CloudXYZ cloud;
  for (double dz = 0.0015; dz < height_m; dz += 0.003)
    for (int i = -1; i <= 1; ++i)
      cloud.push_back(pcl::PointXYZ(float(kBase.x() + lean * dz + 0.003 * i),
                                    float(kBase.y()), float(kBase.z() + dz)));
  for (double x = 0.06; x < 0.15; x += 0.003) // a leaf, off the axis
    cloud.push_back(pcl::PointXYZ(float(kBase.x() + x), 0.0f, float(kBase.z() + 0.2)));
  for (double x = -0.2; x < 0.2; x += 0.003) // the floor, under the base
    cloud.push_back(pcl::PointXYZ(float(kBase.x() + x), 0.0f, float(kBase.z() - 0.1)));
  return cloud;
}

TEST(LeafNodePrior, FindsTheStemAndPlacesNodesOneInternodeApartFromTheFirst)
{
  const LeafNodePrior prior;
  const std::vector<Eigen::Vector3d> stem = prior.stemPoints(stemCloud(0.4), kBase, 0.7);
  ASSERT_EQ(stem.size(), 20u); // 0.4 m in 2 cm slices
  for (const Eigen::Vector3d& p : stem) {
    EXPECT_NEAR(p.x(), 1.0, 1e-6);
    EXPECT_NEAR(p.y(), 0.0, 1e-6);
  }
  EXPECT_DOUBLE_EQ(stem.front().z(), 0.81);
  EXPECT_DOUBLE_EQ(stem.back().z(), 0.8 + 0.39);

  // The plant's top: the stem's highest voxel (the leaf is lower, the floor below the
  // base).
  EXPECT_NEAR(prior.plantTop(stemCloud(0.4), kBase, 0.7), 0.8 + 0.3975, 1e-6);
  const Roi nodes = prior.predict(stemCloud(0.4), kBase, 0.7);
  // From 0.088 above the base, every 4 cm up to the top: 0.888 ... 1.168 m, 8 boxes.
  ASSERT_EQ(nodes.size(), 8u);
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const Box& b = nodes.boxes()[k];
    EXPECT_NEAR(b.center.z(), 0.8 + 0.088 + 0.04 * double(k), 1e-9) << k;
    EXPECT_NEAR(b.center.x(), 1.0, 1e-6);
    EXPECT_NEAR(b.center.y(), 0.0, 1e-6);
    EXPECT_EQ(b.size, Eigen::Vector3d(0.03, 0.03, 0.05));
    EXPECT_EQ(b.name, "leaf_node_prior_" + std::to_string(k));
  }
  // Without a top from the map, up to the given height, 0.7 m above the base: 0.888 ...
  // 1.488 m.
  LeafNodePrior::Config to_height;
  to_height.top_radius_m = 0.0;
  EXPECT_EQ(LeafNodePrior(to_height).predict(stemCloud(0.4), kBase, 0.7).size(), 16u);
}

TEST(LeafNodePrior, TheStemGoesOnWhereTheMapDoesNotShowIt)
{
  // Only the lowest 0.2 m of a stem leaning 10 cm per metre is seen, and a leaf 8 cm
  // off the axis at 0.6 m (leaves hide the rest of the stem): the boxes follow the stem
  // up to 0.2 m and go on at its highest point's x up to the leaf.
  const LeafNodePrior prior;
  CloudXYZ seen = stemCloud(0.2, 0.1);
  seen.push_back(pcl::PointXYZ(float(kBase.x() + 0.08), 0.0f, float(kBase.z() + 0.6)));
  const std::vector<Eigen::Vector3d> stem = prior.stemPoints(seen, kBase, 0.7);
  ASSERT_EQ(stem.size(), 10u);
  const Roi nodes = prior.predict(seen, kBase, 0.7);
  ASSERT_EQ(nodes.size(), 13u); // 0.888 ... 1.368 m
  for (const Box& b : nodes.boxes()) {
    const double x = b.center.z() <= stem.back().z() ? 1.0 + 0.1 * (b.center.z() - 0.8)
                                                     : stem.back().x();
    EXPECT_NEAR(b.center.x(), x, 0.002) << b.center.z();
  }
  EXPECT_NEAR(nodes.boxes().back().center.z(), 0.8 + 0.088 + 0.48, 1e-9);
  EXPECT_NEAR(nodes.boxes().back().center.x(), 1.0 + 0.1 * 0.19, 0.002);
}

TEST(LeafNodePrior, StemDetectionsFindAStemAwayFromTheAxis)
{
  // A stem 8 cm from the sector's axis, beyond the 3 cm where the map's voxels are
  // looked for: without detections the prediction stands on the axis; with two detected
  // stem parts it runs through their centres, and on at the ends' x and y.
  CloudXYZ seen = stemCloud(0.4);
  for (pcl::PointXYZ& p : seen.points)
    p.y += 0.08f;
  LeafNodePrior prior;
  EXPECT_TRUE(prior.stemPoints(seen, kBase, 0.7).empty());
  const Roi on_axis = prior.predict(seen, kBase, 0.7);
  ASSERT_EQ(on_axis.size(), 8u);
  for (const Box& b : on_axis.boxes())
    EXPECT_NEAR(b.center.y(), 0.0, 1e-9);
  const Roi parts({Box(Eigen::Vector3d(1.0, 0.09, 1.1), Eigen::Vector3d(0.02, 0.02, 0.1),
                       "main_stem_1"),
                   Box(Eigen::Vector3d(1.0, 0.07, 0.9), Eigen::Vector3d(0.02, 0.02, 0.1),
                       "main_stem_0"),
                   Box(Eigen::Vector3d(1.0, 0.5, 2.0), Eigen::Vector3d(0.02, 0.02, 0.1),
                       "above_the_sector")});
  prior.setStemObservations(parts);
  EXPECT_EQ(prior.getStemObservations().size(), 3u);
  const std::vector<Eigen::Vector3d> stem = prior.stemPoints(seen, kBase, 0.7);
  ASSERT_EQ(stem.size(), 2u); // the two within the height, bottom first
  EXPECT_EQ(stem[0], parts.boxes()[1].center);
  const Roi nodes = prior.predict(seen, kBase, 0.7);
  ASSERT_EQ(nodes.size(), 8u); // the top is still the map's (within 0.15 m of the axis)
  for (const Box& b : nodes.boxes()) {
    const double z = b.center.z();
    const double y = z <= 0.9 ? 0.07 : z >= 1.1 ? 0.09 : 0.07 + 0.1 * (z - 0.9);
    EXPECT_NEAR(b.center.y(), y, 1e-9) << z;
  }
  prior.setStemObservations(Roi()); // none: the voxels again
  EXPECT_TRUE(prior.stemPoints(seen, kBase, 0.7).empty());
  Box not_finite(Eigen::Vector3d(1.0, 0.0, 1.0), Eigen::Vector3d(0.1, 0.1, 0.1));
  not_finite.center.y() = NAN; // the fields are public
  EXPECT_THROW(prior.setStemObservations(Roi({not_finite})), InvalidArgumentError);
}

TEST(LeafNodePrior, AnchorsMoveThePredictionAndALeaningStemIsFollowed)
{
  const LeafNodePrior prior;
  const Roi anchored = prior.predict(stemCloud(0.4), kBase, 0.7, {{1.0, 0.0, 1.05}});
  // From the anchor down to the base (0.8) and up to the plant's top (1.1975), 4 cm
  // apart, the anchor itself left to its own box: 0.81 ... 1.01 and 1.09 ... 1.17.
  std::vector<double> heights;
  for (const Box& b : anchored.boxes())
    heights.push_back(b.center.z());
  const std::vector<double> expected = {0.81, 0.85, 0.89, 0.93, 0.97,
                                        1.01, 1.09, 1.13, 1.17};
  ASSERT_EQ(heights.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k)
    EXPECT_NEAR(heights[k], expected[k], 1e-9) << k;
  // An anchor more than an internode above the top is not one.
  EXPECT_EQ(prior.predict(stemCloud(0.4), kBase, 0.7, {{1.0, 0.0, 1.25}}).size(), 8u);

  // A stem leaning 10 cm per metre (within the 3 cm radius up to 0.3 m): the boxes sit
  // on it.
  const Roi leaning = prior.predict(stemCloud(0.3, 0.1), kBase, 0.7);
  ASSERT_GT(leaning.size(), 3u);
  for (const Box& b : leaning.boxes())
    EXPECT_NEAR(b.center.x(), 1.0 + 0.1 * (b.center.z() - 0.8), 0.002) << b.center.z();

  // detections+prior: the found boxes first, as they are, then the prediction, by
  // default as without them, with anchor_on_found anchored on their centres.
  Roi found;
  found.addBox(Box({1.0, 0.0, 1.05}, {0.04, 0.04, 0.06}, "leaf_node_0"));
  LeafNodePrior::Config anchoring;
  anchoring.anchor_on_found = true;
  for (const LeafNodePrior& p : {prior, LeafNodePrior(anchoring)}) {
    const Roi& after = p.getConfig().anchor_on_found
                           ? anchored
                           : prior.predict(stemCloud(0.4), kBase, 0.7);
    const Roi both = p.predictAround(found, stemCloud(0.4), kBase, 0.7);
    ASSERT_EQ(both.size(), 1u + after.size());
    EXPECT_EQ(both.boxes()[0].name, "leaf_node_0");
    EXPECT_EQ(both.boxes()[0].size, Eigen::Vector3d(0.04, 0.04, 0.06));
    for (std::size_t k = 0; k < after.size(); ++k)
      EXPECT_EQ(both.boxes()[k + 1].center, after.boxes()[k].center) << k;
    EXPECT_EQ(p.predictAround(Roi(), stemCloud(0.4), kBase, 0.7).size(), 8u);
  }
}

TEST(LeafNodePrior, WithNoStemSeenTheAxisIsTheStemAndBadRulesAreRefused)
{
  const LeafNodePrior prior;
  // Nothing at all: up to the given height. A leaf 0.2 m up and the floor, no stem: up
  // to the leaf (0.888, 0.928, 0.968 m).
  const std::pair<CloudXYZ, std::size_t> cases[] = {{CloudXYZ(), 16},
                                                    {stemCloud(0.0), 3}};
  for (const auto& [nothing_of_it, count] : cases) {
    const Roi nodes = prior.predict(nothing_of_it, kBase, 0.7);
    ASSERT_EQ(nodes.size(), count);
    for (const Box& b : nodes.boxes()) {
      EXPECT_DOUBLE_EQ(b.center.x(), 1.0);
      EXPECT_DOUBLE_EQ(b.center.y(), 0.0);
    }
  }
  EXPECT_THROW(prior.predict(CloudXYZ(), kBase, 0.0), InvalidArgumentError);
  LeafNodePrior::Config config;
  config.internode_m = 0.0;
  EXPECT_THROW(LeafNodePrior{config}, InvalidArgumentError);
  config = LeafNodePrior::Config();
  config.slice_m = std::nan("");
  EXPECT_THROW(LeafNodePrior{config}, InvalidArgumentError);
  config = LeafNodePrior::Config();
  config.first_node_m = -0.1;
  EXPECT_THROW(LeafNodePrior{config}, InvalidArgumentError);
  config = LeafNodePrior::Config();
  config.top_radius_m = -0.1;
  EXPECT_THROW(LeafNodePrior{config}, InvalidArgumentError);
}

} // namespace
} // namespace plantnbv
