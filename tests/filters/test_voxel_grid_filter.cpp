#include <array>
#include <cmath>
#include <limits>
#include <set>
#include <tuple>

#include <gtest/gtest.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/filters/voxel_grid_filter.h>

using plantnbv::VoxelGridFilter;
using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using CloudL = pcl::PointCloud<pcl::PointXYZL>;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

template <typename PointT>
pcl::PointCloud<PointT> runFilter(const typename pcl::PointCloud<PointT>::Ptr& cloud,
                                  double leaf, bool centres,
                                  bool* used_fallback = nullptr)
{
  VoxelGridFilter<PointT> f;
  f.setLeafSize(leaf);
  f.setOutputVoxelCentres(centres);
  f.setInputCloud(cloud);
  pcl::PointCloud<PointT> out;
  f.filter(out);
  if (used_fallback)
    *used_fallback = f.usedOverflowFallback();
  return out;
}

/// Points at ((i + 0.5) mm) on a 1 mm lattice filling nx x ny x nz voxels of 3 mm whose
/// first voxel has index (ox, oy, oz): 27 points per voxel, away from voxel faces.
Cloud::Ptr millimetreLattice(int nx, int ny, int nz, int ox = 0, int oy = 0, int oz = 0,
                             double base = 0.0)
{
  auto cloud = std::make_shared<Cloud>();
  for (int k = 0; k < 3 * nz; ++k)
    for (int j = 0; j < 3 * ny; ++j)
      for (int i = 0; i < 3 * nx; ++i)
        cloud->push_back(
            pcl::PointXYZ(static_cast<float>(base + (3 * ox + i + 0.5) * 1e-3),
                          static_cast<float>(base + (3 * oy + j + 0.5) * 1e-3),
                          static_cast<float>(base + (3 * oz + k + 0.5) * 1e-3)));
  return cloud;
}

} // namespace

TEST(VoxelGridFilter, LatticeCountsCentroidsAndOrder)
{
  // Voxels of 3 mm with indices -1..1 in x, 0..3 in y, 2..6 in z (negative included:
  // the grid is origin-aligned, not aligned with the cloud's minimum).
  const auto cloud = millimetreLattice(3, 4, 5, -1, 0, 2);
  ASSERT_EQ(cloud->size(), 60u * 27u);
  bool fallback = true;
  const Cloud out = runFilter<pcl::PointXYZ>(cloud, 0.003, false, &fallback);
  EXPECT_FALSE(fallback);
  ASSERT_EQ(out.size(), 60u);
  EXPECT_EQ(out.width, 60u);
  EXPECT_EQ(out.height, 1u);
  EXPECT_TRUE(out.is_dense);
  // The 27 points of a voxel average to its centre; voxels in (z, y, x) order, x fastest.
  std::size_t n = 0;
  for (int vz = 2; vz < 7; ++vz)
    for (int vy = 0; vy < 4; ++vy)
      for (int vx = -1; vx < 2; ++vx, ++n) {
        EXPECT_NEAR(out[n].x, (vx + 0.5) * 0.003, 1e-7) << n;
        EXPECT_NEAR(out[n].y, (vy + 0.5) * 0.003, 1e-7) << n;
        EXPECT_NEAR(out[n].z, (vz + 0.5) * 0.003, 1e-7) << n;
      }
}

TEST(VoxelGridFilter, OriginAlignedLattice)
{
  // A grid aligned with the cloud's minimum would put -0.5 mm and 0.5 mm in one 3 mm
  // voxel.
  auto cloud = std::make_shared<Cloud>();
  cloud->push_back(pcl::PointXYZ(-0.0005f, 0.001f, 0.001f));
  cloud->push_back(pcl::PointXYZ(0.0005f, 0.001f, 0.001f));
  cloud->push_back(pcl::PointXYZ(0.0025f, 0.001f, 0.001f)); // same voxel as 0.5 mm
  for (const bool centres : {false, true}) {
    const Cloud out = runFilter<pcl::PointXYZ>(cloud, 0.003, centres);
    ASSERT_EQ(out.size(), 2u) << centres;
    EXPECT_NEAR(out[0].x, centres ? -0.0015 : -0.0005, 1e-9);
    EXPECT_NEAR(out[1].x, 0.0015, 1e-9); // centroid of 0.5 and 2.5 mm, or the centre
  }
}

TEST(VoxelGridFilter, CentreModeCoordinatesAreExact)
{
  plantnbv::Rng rng(11);
  const double leaf = 0.004;
  auto cloud = std::make_shared<Cloud>();
  std::set<std::array<long, 3>> voxels;
  for (int n = 0; n < 3000; ++n) {
    const std::array<long, 3> v{static_cast<long>(rng.index(40)) - 20,
                                static_cast<long>(rng.index(40)) - 20,
                                static_cast<long>(rng.index(40)) - 20};
    voxels.insert(v);
    // Inside the voxel, at least 10% of a leaf from its faces.
    cloud->push_back(
        pcl::PointXYZ(static_cast<float>((v[0] + rng.uniform(0.1, 0.9)) * leaf),
                      static_cast<float>((v[1] + rng.uniform(0.1, 0.9)) * leaf),
                      static_cast<float>((v[2] + rng.uniform(0.1, 0.9)) * leaf)));
  }
  const Cloud out = runFilter<pcl::PointXYZ>(cloud, leaf, true);
  ASSERT_EQ(out.size(), voxels.size());
  // (z, y, x) order: sort the expected voxels that way.
  std::set<std::array<long, 3>> zyx;
  for (const auto& v : voxels)
    zyx.insert({v[2], v[1], v[0]});
  std::size_t n = 0;
  for (const auto& v : zyx) {
    // Centre (i + 0.5) * leaf computed in double, stored as float: exact equality.
    EXPECT_EQ(out[n].x, static_cast<float>((v[2] + 0.5) * leaf)) << n;
    EXPECT_EQ(out[n].y, static_cast<float>((v[1] + 0.5) * leaf)) << n;
    EXPECT_EQ(out[n].z, static_cast<float>((v[0] + 0.5) * leaf)) << n;
    ++n;
  }
  // Centroid mode finds the same voxels.
  EXPECT_EQ(runFilter<pcl::PointXYZ>(cloud, leaf, false).size(), voxels.size());
}

TEST(VoxelGridFilter, OverflowUsesOwnGridInsteadOfPassingThrough)
{
  // Two clusters 1 km apart along each axis at a 1 mm leaf: ~1e18 voxels in the bounding
  // box, far beyond pcl::VoxelGrid's int32 indices.
  auto cloud = millimetreLattice(2, 2, 2); // 8 voxels of 3 mm near the origin
  const double base = 333333 * 0.003;      // 999.999, a voxel face
  const auto far = millimetreLattice(1, 1, 1, 0, 0, 0, base);
  *cloud += *far;

  // pcl::VoxelGrid itself warns and returns the input unfiltered.
  pcl::VoxelGrid<pcl::PointXYZ> pcl_grid;
  pcl_grid.setLeafSize(0.003f, 0.003f, 0.003f);
  pcl_grid.setInputCloud(cloud);
  Cloud pcl_out;
  pcl_grid.filter(pcl_out);
  EXPECT_EQ(pcl_out.size(), cloud->size());

  bool fallback = false;
  const Cloud out = runFilter<pcl::PointXYZ>(cloud, 0.003, false, &fallback);
  EXPECT_TRUE(fallback);
  ASSERT_EQ(out.size(), 9u);
  for (std::size_t n = 0; n < 8; ++n) {
    const double cx = ((n & 1) + 0.5) * 0.003, cy = (((n >> 1) & 1) + 0.5) * 0.003,
                 cz = (((n >> 2) & 1) + 0.5) * 0.003;
    EXPECT_NEAR(out[n].x, cx, 1e-7);
    EXPECT_NEAR(out[n].y, cy, 1e-7);
    EXPECT_NEAR(out[n].z, cz, 1e-7);
  }
  // Far cluster: float spacing near 1000 m is 6e-5 m.
  EXPECT_NEAR(out[8].x, base + 0.0015, 1e-4);
  EXPECT_NEAR(out[8].y, base + 0.0015, 1e-4);
  EXPECT_NEAR(out[8].z, base + 0.0015, 1e-4);

  // Leaves of 1 mm (1e18 voxels in the box) and 0.1 mm (1e21, beyond a 64-bit linear
  // index): every lattice point is its own voxel, in (z, y, x) order.
  for (const double leaf : {0.001, 0.0001}) {
    EXPECT_EQ(runFilter<pcl::PointXYZ>(cloud, leaf, false).size(), cloud->size()) << leaf;
    const Cloud centres = runFilter<pcl::PointXYZ>(cloud, leaf, true);
    ASSERT_EQ(centres.size(), cloud->size()) << leaf;
    for (std::size_t n = 1; n < centres.size(); ++n) {
      const auto& a = centres[n - 1];
      const auto& b = centres[n];
      EXPECT_LT(std::tie(a.z, a.y, a.x), std::tie(b.z, b.y, b.x)) << leaf << " " << n;
    }
    EXPECT_NEAR(centres[0].x, (std::floor(0.0005 / leaf) + 0.5) * leaf, 1e-9);
  }
}

TEST(VoxelGridFilter, NonFinitePointsAreDropped)
{
  for (const bool claims_dense : {false, true}) {
    auto cloud = millimetreLattice(2, 1, 1); // 2 voxels
    cloud->push_back(pcl::PointXYZ(kNaN, 0.0f, 0.0f));
    cloud->push_back(pcl::PointXYZ(0.0f, std::numeric_limits<float>::infinity(), 0.0f));
    cloud->push_back(pcl::PointXYZ(0.0f, 0.0f, -std::numeric_limits<float>::infinity()));
    cloud->is_dense = claims_dense; // a cloud that wrongly says dense is handled too
    for (const bool centres : {false, true}) {
      const Cloud out = runFilter<pcl::PointXYZ>(cloud, 0.003, centres);
      ASSERT_EQ(out.size(), 2u) << claims_dense << centres;
      EXPECT_TRUE(out.is_dense);
      for (const auto& p : out)
        EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
      EXPECT_NEAR(out[1].x, 0.0045, 1e-7);
    }
  }
  // Only non-finite points: an empty result.
  auto nans = std::make_shared<Cloud>();
  nans->push_back(pcl::PointXYZ(kNaN, kNaN, kNaN));
  nans->is_dense = false;
  EXPECT_EQ(runFilter<pcl::PointXYZ>(nans, 0.003, false).size(), 0u);
  EXPECT_EQ(runFilter<pcl::PointXYZ>(nans, 0.003, true).size(), 0u);
}

TEST(VoxelGridFilter, LabelsAreTheMajorityInEveryMode)
{
  auto cloud = std::make_shared<CloudL>();
  const auto add = [&](float x, std::uint32_t label) {
    pcl::PointXYZL p;
    p.x = x;
    p.y = p.z = 0.001f;
    p.label = label;
    cloud->push_back(p);
  };
  add(0.0005f, 3); // voxel 0: labels 3, 5, 5 -> 5
  add(0.0010f, 5);
  add(0.0020f, 5);
  add(0.0040f, 7); // voxel 1: labels 7, 2 -> tie -> 2 (the smaller)
  add(0.0050f, 2);
  add(0.0070f, 9); // voxel 2: 9
  for (const bool centres : {false, true}) {
    const CloudL out = runFilter<pcl::PointXYZL>(cloud, 0.003, centres);
    ASSERT_EQ(out.size(), 3u);
    EXPECT_EQ(out[0].label, 5u) << centres;
    EXPECT_EQ(out[1].label, 2u) << centres;
    EXPECT_EQ(out[2].label, 9u) << centres;
    // Centroid mode averages coordinates, never labels.
    EXPECT_NEAR(out[0].x, centres ? 0.0015 : (0.0005 + 0.001 + 0.002) / 3, 1e-7);
  }
  // The overflow fallback gives the same labels (and voxels).
  pcl::PointXYZL far;
  far.x = far.y = far.z = 1000.0f;
  far.label = 4;
  cloud->push_back(far);
  bool fallback = false;
  const CloudL out = runFilter<pcl::PointXYZL>(cloud, 0.003, false, &fallback);
  EXPECT_TRUE(fallback);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out[0].label, 5u);
  EXPECT_EQ(out[1].label, 2u);
  EXPECT_EQ(out[2].label, 9u);
  EXPECT_EQ(out[3].label, 4u);
  EXPECT_NEAR(out[0].x, (0.0005 + 0.001 + 0.002) / 3, 1e-7);
}

TEST(VoxelGridFilter, HonoursIndices)
{
  const auto cloud = millimetreLattice(2, 1, 1); // voxel 0: points with x < 3 mm
  auto indices = std::make_shared<pcl::Indices>();
  for (pcl::index_t i = 0; i < static_cast<pcl::index_t>(cloud->size()); ++i)
    if ((*cloud)[i].x > 0.003f)
      indices->push_back(i);
  for (const bool centres : {false, true}) {
    VoxelGridFilter<pcl::PointXYZ> f;
    f.setLeafSize(0.003);
    f.setOutputVoxelCentres(centres);
    f.setInputCloud(cloud);
    f.setIndices(indices);
    Cloud out;
    f.filter(out);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_NEAR(out[0].x, 0.0045, 1e-7);
  }
}

TEST(VoxelGridFilter, SettersValidate)
{
  VoxelGridFilter<pcl::PointXYZ> f;
  EXPECT_DOUBLE_EQ(f.getLeafSize(), 0.003);
  EXPECT_FALSE(f.getOutputVoxelCentres());
  for (const double bad :
       {0.0, -0.01, std::nan(""), std::numeric_limits<double>::infinity(),
        1e-50 /* 0 as a float */, 1e300 /* inf as a float */}) {
    try {
      f.setLeafSize(bad);
      ADD_FAILURE() << "no exception for " << bad;
    } catch (const plantnbv::InvalidArgumentError& e) {
      EXPECT_NE(std::string(e.what()).find("leaf size"), std::string::npos);
    }
  }
  try {
    f.setLeafSize(-0.25);
    ADD_FAILURE();
  } catch (const plantnbv::InvalidArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("-0.25"), std::string::npos) << e.what();
  }
  EXPECT_DOUBLE_EQ(f.getLeafSize(), 0.003); // unchanged by the failed calls
  f.setLeafSize(0.005);
  EXPECT_DOUBLE_EQ(f.getLeafSize(), 0.005);
}
