// VoxelLattice is OctoMap's key arithmetic: the same keys and centres as OcTree's own.
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <plantnbv/common/voxel_lattice.h>

using plantnbv::VoxelLattice;

namespace {

/// Coordinates where rounding matters: on and next to voxel faces, far out, at the
/// tree's border, and random ones.
std::vector<double> hardCoordinates(double resolution)
{
  std::vector<double> c{0.0, -0.0, 1.0, -1.0, 0.5 * resolution, -0.5 * resolution};
  for (int k : {1, 2, 3, 7, 100, 333, 1000, 32767, 32768})
    for (int sign : {-1, 1}) {
      const double face = sign * k * resolution;
      c.push_back(face);
      c.push_back(std::nextafter(face, 1e9));
      c.push_back(std::nextafter(face, -1e9));
      c.push_back(static_cast<float>(face)); // as a float point would hold it
    }
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int i = 0; i < 20000; ++i)
    c.push_back(u(rng));
  return c;
}

} // namespace

TEST(VoxelLattice, KeysAndCentresAreOctoMaps)
{
  for (double resolution : {0.003, 0.005, 0.007, 0.01, 0.1, 1.0 / 3.0}) {
    SCOPED_TRACE(resolution);
    const octomap::OcTree tree(resolution);
    const VoxelLattice lattice(resolution);
    EXPECT_EQ(lattice.resolutionFactor(), 1.0 / tree.getResolution());
    for (double c : hardCoordinates(resolution)) {
      octomap::key_type expected = 0;
      const bool inside = tree.coordToKeyChecked(c, expected);
      int key = -1;
      ASSERT_EQ(lattice.coordToKey(c, key), inside) << c;
      if (!inside)
        continue;
      ASSERT_EQ(key, expected) << c;
      ASSERT_EQ(lattice.keyToCoord(key), tree.keyToCoord(expected)) << c;
      ASSERT_EQ(lattice.indexToCoord(key - VoxelLattice::kKeyOffset),
                tree.keyToCoord(expected))
          << c;
    }
  }
}

TEST(VoxelLattice, PointsAreRangeCheckedPerAxis)
{
  const VoxelLattice lattice(0.003);
  const octomap::OcTree tree(0.003);
  const float p[3] = {1.0f, -0.25f, 1.15f};
  int key[3];
  ASSERT_TRUE(lattice.coordToKey(p, key));
  octomap::OcTreeKey expected;
  ASSERT_TRUE(tree.coordToKeyChecked(octomap::point3d(p[0], p[1], p[2]), expected));
  for (int a = 0; a < 3; ++a)
    EXPECT_EQ(key[a], expected[a]);

  const float far[3] = {1.0f, 1e6f, 0.0f}; // beyond +-32768 voxels on y
  EXPECT_FALSE(lattice.coordToKey(far, key));
  int k = 7;
  EXPECT_FALSE(lattice.coordToKey(std::numeric_limits<double>::quiet_NaN(), k));
  EXPECT_FALSE(lattice.coordToKey(std::numeric_limits<double>::infinity(), k));
  EXPECT_FALSE(lattice.coordToKey(1e300, k));
  EXPECT_EQ(k, 7); // unchanged
  EXPECT_EQ(lattice.keyToLowerFace(VoxelLattice::kKeyOffset + 2), 2 * 0.003);
  EXPECT_EQ(VoxelLattice::kKeyLimit, 65536);
}
