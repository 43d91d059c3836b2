// LeafNodePrior: leaf-node boxes predicted along a synthetic stem, with and without
// anchors.

#include <cmath>
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

  const Roi nodes = prior.predict(stemCloud(0.4), kBase, 0.7);
  // From 0.088 above the lowest stem point, every 4 cm up to the highest: 0.898 ...
  // 1.178 m, 8 boxes.
  ASSERT_EQ(nodes.size(), 8u);
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const Box& b = nodes.boxes()[k];
    EXPECT_NEAR(b.center.z(), 0.81 + 0.088 + 0.04 * double(k), 1e-9) << k;
    EXPECT_NEAR(b.center.x(), 1.0, 1e-6);
    EXPECT_EQ(b.size, Eigen::Vector3d(0.03, 0.03, 0.05));
    EXPECT_EQ(b.name, "leaf_node_prior_" + std::to_string(k));
  }
}

TEST(LeafNodePrior, AnchorsMoveThePredictionAndALeaningStemIsFollowed)
{
  const LeafNodePrior prior;
  const Roi anchored = prior.predict(stemCloud(0.4), kBase, 0.7, {{1.0, 0.0, 1.05}});
  // From the anchor down to 0.81 and up to 1.19, 4 cm apart, the anchor itself left to
  // its own box: 0.85 ... 1.01 and 1.09 ... 1.17.
  std::vector<double> heights;
  for (const Box& b : anchored.boxes())
    heights.push_back(b.center.z());
  const std::vector<double> expected = {0.85, 0.89, 0.93, 0.97, 1.01, 1.09, 1.13, 1.17};
  ASSERT_EQ(heights.size(), expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k)
    EXPECT_NEAR(heights[k], expected[k], 1e-9) << k;
  // An anchor off the stem's range is not one.
  EXPECT_EQ(prior.predict(stemCloud(0.4), kBase, 0.7, {{1.0, 0.0, 1.5}}).size(), 8u);

  // A stem leaning 10 cm per metre (within the 3 cm radius up to 0.3 m): the boxes sit
  // on it.
  const Roi leaning = prior.predict(stemCloud(0.3, 0.1), kBase, 0.7);
  ASSERT_GT(leaning.size(), 3u);
  for (const Box& b : leaning.boxes())
    EXPECT_NEAR(b.center.x(), 1.0 + 0.1 * (b.center.z() - 0.8), 0.002) << b.center.z();
}

TEST(LeafNodePrior, NoStemNoPredictionAndBadRulesAreRefused)
{
  const LeafNodePrior prior;
  CloudXYZ floor_only = stemCloud(0.0);
  EXPECT_TRUE(prior.predict(floor_only, kBase, 0.7).empty());
  EXPECT_TRUE(prior.predict(CloudXYZ(), kBase, 0.7).empty());
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
}

} // namespace
} // namespace plantnbv
