// plantnbv reproduces some of OctoMap's and PCL's internals bit for bit. This test names
// that assumption, so that an upgrade fails here with the reason, not as a drift of a
// few voxels somewhere else.
#include <string>

#include <gtest/gtest.h>
#include <pcl/pcl_config.h>

namespace {

/// "1.9.7" -> "1.9".
std::string majorMinor(const std::string& version)
{
  const auto first = version.find('.');
  const auto second = version.find('.', first + 1);
  return version.substr(0, second);
}

} // namespace

TEST(PinnedVersions, OctoMapIsTheVersionOurCopiesWereVerifiedAgainst)
{
  EXPECT_EQ(majorMinor(PLANTNBV_FOUND_OCTOMAP_VERSION), PLANTNBV_VERIFIED_OCTOMAP_VERSION)
      << "OctoMap " << PLANTNBV_FOUND_OCTOMAP_VERSION << " is not the "
      << PLANTNBV_VERIFIED_OCTOMAP_VERSION
      << ".x whose internals plantnbv reproduces bit for bit: the voxel lattice "
         "(common/voxel_lattice.h), the ray keys (octree/ray_traversal.h), the insertion "
         "(OccupancyMap::insert) and the .bt writer (writeOcTree). Run test_octree and "
         "test_planning (VoxelLattice.*, RayTraversal.*, OccupancyMap.*, "
         "OctreeConversion.*) against it; if they pass, move "
         "PLANTNBV_VERIFIED_OCTOMAP_VERSION in CMakeLists.txt.";
}

TEST(PinnedVersions, PclIsTheVersionOurCopiesWereVerifiedAgainst)
{
  EXPECT_EQ(majorMinor(PCL_VERSION_PRETTY), PLANTNBV_VERIFIED_PCL_VERSION)
      << "PCL " << PCL_VERSION_PRETTY << " is not the " << PLANTNBV_VERIFIED_PCL_VERSION
      << ".x whose pcl::VoxelGrid float arithmetic and index overflow check "
         "filters/impl/voxel_grid_filter.hpp reproduce, and whose PCD/PLY reader "
         "crashes io/cloud_io.cpp guards against. Run test_filters and test_io "
         "(VoxelGridFilter.*, CloudIo.*) against it; if they pass, move "
         "PLANTNBV_VERIFIED_PCL_VERSION in CMakeLists.txt.";
}
