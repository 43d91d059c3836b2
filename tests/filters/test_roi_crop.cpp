#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/box.h>
#include <plantnbv/common/random.h>
#include <plantnbv/filters/roi_crop.h>

using plantnbv::Box;
using plantnbv::Roi;
using plantnbv::RoiCrop;
using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using CloudL = pcl::PointCloud<pcl::PointXYZL>;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

/// Two overlapping boxes: [0, 1]^3 and [0.5, 1.5] x [0, 1] x [0, 1] (binary-exact faces).
Roi twoBoxes()
{
  Roi roi;
  roi.addBox(Box::fromMinMax(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1), "a"));
  roi.addBox(
      Box::fromMinMax(Eigen::Vector3d(0.5, 0, 0), Eigen::Vector3d(1.5, 1, 1), "b"));
  return roi;
}

/// Index: 0 in a only, 1 in the overlap, 2 in b only, 3 outside, 4 on b's far face
/// (kept: closed boxes), 5 NaN, 6 just outside b, 7 infinite.
Cloud::Ptr testCloud()
{
  auto cloud = std::make_shared<Cloud>();
  cloud->push_back(pcl::PointXYZ(0.25f, 0.5f, 0.5f));
  cloud->push_back(pcl::PointXYZ(0.75f, 0.5f, 0.5f));
  cloud->push_back(pcl::PointXYZ(1.25f, 0.5f, 0.5f));
  cloud->push_back(pcl::PointXYZ(2.0f, 0.5f, 0.5f));
  cloud->push_back(pcl::PointXYZ(1.5f, 1.0f, 0.0f));
  cloud->push_back(pcl::PointXYZ(kNaN, 0.5f, 0.5f));
  cloud->push_back(pcl::PointXYZ(std::nextafter(1.5f, 2.0f), 0.5f, 0.5f));
  cloud->push_back(pcl::PointXYZ(0.5f, kInf, 0.5f));
  cloud->is_dense = false;
  return cloud;
}

pcl::Indices filterIndices(RoiCrop<pcl::PointXYZ>& crop)
{
  pcl::Indices kept;
  crop.filter(kept);
  return kept;
}

} // namespace

TEST(RoiCrop, UnionOfOverlappingBoxesKeepsEachPointOnce)
{
  RoiCrop<pcl::PointXYZ> crop;
  crop.setRoi(twoBoxes());
  crop.setInputCloud(testCloud());
  EXPECT_EQ(filterIndices(crop), (pcl::Indices{0, 1, 2, 4}));

  Cloud out;
  crop.filter(out);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out.width, 4u);
  EXPECT_EQ(out.height, 1u);
  // (is_dense is copied from the input by pcl::copyPointCloud, as in pcl::CropBox.)
  EXPECT_FLOAT_EQ(out[1].x, 0.75f);
  EXPECT_FLOAT_EQ(out[3].x, 1.5f);

  // setIndices restricts the candidates.
  crop.setIndices(std::make_shared<pcl::Indices>(pcl::Indices{1, 3, 4, 5}));
  EXPECT_EQ(filterIndices(crop), (pcl::Indices{1, 4}));
}

TEST(RoiCrop, NegativeKeepsFinitePointsOutside)
{
  RoiCrop<pcl::PointXYZ> crop;
  crop.setRoi(twoBoxes());
  crop.setNegative(true);
  crop.setInputCloud(testCloud());
  EXPECT_EQ(filterIndices(crop), (pcl::Indices{3, 6})); // NaN and inf removed too
}

TEST(RoiCrop, RemovedIndices)
{
  RoiCrop<pcl::PointXYZ> crop(/*extract_removed_indices=*/true);
  crop.setRoi(twoBoxes());
  crop.setInputCloud(testCloud());
  filterIndices(crop);
  EXPECT_EQ(*crop.getRemovedIndices(), (pcl::Indices{3, 5, 6, 7}));
  crop.setNegative(true);
  filterIndices(crop);
  EXPECT_EQ(*crop.getRemovedIndices(), (pcl::Indices{0, 1, 2, 4, 5, 7}));

  // Without extraction, no removed indices (and none left over from before).
  RoiCrop<pcl::PointXYZ> plain;
  plain.setRoi(twoBoxes());
  plain.setInputCloud(testCloud());
  filterIndices(plain);
  EXPECT_TRUE(plain.getRemovedIndices()->empty());
}

TEST(RoiCrop, KeepOrganizedSetsRemovedPointsToTheFilterValue)
{
  // A 4 x 3 organized cloud with labels; a box holds the middle two columns.
  auto cloud = std::make_shared<CloudL>(4, 3);
  for (std::uint32_t v = 0; v < 3; ++v)
    for (std::uint32_t u = 0; u < 4; ++u) {
      auto& p = cloud->at(u, v);
      p.x = static_cast<float>(u);
      p.y = static_cast<float>(v);
      p.z = 1.0f;
      p.label = 10 * v + u;
    }
  cloud->at(1, 1).x = kNaN; // in the box's columns but not finite: removed
  cloud->is_dense = false;
  Roi roi;
  roi.addBox(Box::fromMinMax(Eigen::Vector3d(0.5, -1, 0), Eigen::Vector3d(2.5, 5, 2)));

  RoiCrop<pcl::PointXYZL> crop;
  crop.setRoi(roi);
  crop.setKeepOrganized(true);
  crop.setInputCloud(cloud);
  CloudL out;
  crop.filter(out);
  ASSERT_EQ(out.width, 4u);
  ASSERT_EQ(out.height, 3u);
  EXPECT_FALSE(out.is_dense);
  for (std::uint32_t v = 0; v < 3; ++v)
    for (std::uint32_t u = 0; u < 4; ++u) {
      const auto& p = out.at(u, v);
      const bool kept = (u == 1 || u == 2) && !(u == 1 && v == 1);
      if (kept) {
        EXPECT_EQ(p.x, static_cast<float>(u));
        EXPECT_EQ(p.y, static_cast<float>(v));
      } else {
        EXPECT_TRUE(std::isnan(p.x) && std::isnan(p.y) && std::isnan(p.z))
            << u << "," << v;
      }
      EXPECT_EQ(p.label, 10 * v + u); // PCL overwrites x, y, z only
    }

  // A user filter value instead of NaN.
  crop.setUserFilterValue(-5.0f);
  crop.filter(out);
  EXPECT_EQ(out.at(0, 0).x, -5.0f);
  EXPECT_EQ(out.at(3, 2).z, -5.0f);
  EXPECT_EQ(out.at(1, 1).x, -5.0f);
  EXPECT_EQ(out.at(2, 1).x, 2.0f);
}

TEST(RoiCrop, EmptyRoi)
{
  RoiCrop<pcl::PointXYZ> crop;
  crop.setInputCloud(testCloud());
  EXPECT_TRUE(crop.getRoi().empty());
  EXPECT_TRUE(filterIndices(crop).empty());
  crop.setNegative(true);
  EXPECT_EQ(filterIndices(crop), (pcl::Indices{0, 1, 2, 3, 4, 6}));
}

TEST(RoiCrop, AgreesWithRoiContains)
{
  // Coordinates on a 1/8 grid land exactly on faces often; also random ones.
  plantnbv::Rng rng(5);
  Roi roi;
  roi.addBox(Box(Eigen::Vector3d(0.25, 0.5, 1.0), Eigen::Vector3d(0.5, 0.75, 1.0)));
  roi.addBox(Box(Eigen::Vector3d(0.5, 0.25, 1.25), Eigen::Vector3d(0.25, 1.0, 0.5)));
  roi.addBox(Box(Eigen::Vector3d(1.0, 0.1, 0.7), Eigen::Vector3d(0.3, 0.3, 0.3)));
  auto cloud = std::make_shared<Cloud>();
  for (int n = 0; n < 20000; ++n) {
    if (n % 2 == 0)
      cloud->push_back(pcl::PointXYZ(static_cast<float>(rng.index(17)) / 8.0f - 0.5f,
                                     static_cast<float>(rng.index(17)) / 8.0f - 0.5f,
                                     static_cast<float>(rng.index(17)) / 8.0f));
    else
      cloud->push_back(pcl::PointXYZ(static_cast<float>(rng.uniform(-0.5, 1.5)),
                                     static_cast<float>(rng.uniform(-0.5, 1.5)),
                                     static_cast<float>(rng.uniform(0.0, 2.0))));
  }
  RoiCrop<pcl::PointXYZ> crop;
  crop.setRoi(roi);
  crop.setInputCloud(cloud);
  const pcl::Indices kept = filterIndices(crop);
  pcl::Indices expected;
  std::size_t on_face = 0;
  for (pcl::index_t i = 0; i < static_cast<pcl::index_t>(cloud->size()); ++i) {
    const auto& p = (*cloud)[i];
    if (roi.contains(p.x, p.y, p.z)) {
      expected.push_back(i);
      const Eigen::Vector3d q(p.x, p.y, p.z);
      for (const Box& b : roi.boxes())
        on_face +=
            ((q - b.center).cwiseAbs() - 0.5 * b.size).cwiseAbs().minCoeff() == 0.0;
    }
  }
  EXPECT_EQ(kept, expected);
  EXPECT_GT(on_face, 100u); // the face case was exercised
  EXPECT_GT(expected.size(), 1000u);
  EXPECT_LT(expected.size(), cloud->size());
}
