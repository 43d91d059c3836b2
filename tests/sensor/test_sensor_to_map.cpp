// End to end: what the sensor returns and what the map makes of it, in particular the
// far returns (floor, support) beyond the map's max range and rays with no return.

#include <cmath>
#include <memory>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/sensor/simulated_depth_sensor.h>

#include "sensor_test_util.h"

using namespace plantnbv;
using test::makeQuad;

namespace {

const Eigen::Vector3d kY = Eigen::Vector3d::UnitY();
const Eigen::Vector3d kZ = Eigen::Vector3d::UnitZ();

/// A small camera (70 deg wide, as the L515).
const CameraIntrinsics kCamera = CameraIntrinsics::custom(64, 48, 45.7, 45.7, 31.5, 23.5);

/// One frame of `wall` from the world origin, looking along +x.
CloudXYZL captureFromOrigin(const TriangleMesh& wall)
{
  auto scene = std::make_shared<SensorScene>();
  scene->addMesh(wall);
  scene->commit();
  SimulatedDepthSensor sensor(kCamera);
  sensor.setScene(scene);
  CloudXYZL cloud;
  sensor.capture(Pose(), cloud);
  return cloud;
}

/// The state of the voxel at `range` metres along the ray of pixel (u, v) (the rays are
/// 6 mm apart at 0.3 m: only points on a ray are sure to be observed).
VoxelState stateOnRay(const OccupancyMap& map, int u, int v, double range)
{
  return map.state(Eigen::Vector3d(range * test::pixelRay(kCamera, Pose(), u, v).normalized()));
}

} // namespace

TEST(SensorToMap, ReturnsBeyondMaxRangeCarveFreeSpaceOnlyUpToIt)
{
  // A wall 2 m away fills the image: every pixel returns a point beyond 0.75 m.
  const CloudXYZL cloud = captureFromOrigin(makeQuad(Eigen::Vector3d(2.0, 0, 0), kY, kZ, 3.0));
  ASSERT_EQ(cloud.size(), 64u * 48u);
  for (const auto& p : cloud.points)
    ASSERT_NEAR(p.x, 2.0, 1e-5);

  OccupancyMap map;
  map.insert(cloud, Eigen::Vector3d::Zero());
  EXPECT_EQ(map.getLastInsertStats().beyond_range, cloud.size());
  EXPECT_EQ(map.getLastInsertStats().non_finite, 0u);
  EXPECT_EQ(map.countVoxels().occupied, 0u); // the wall itself is never seen as occupied
  for (int u : {5, 32, 60}) {
    EXPECT_EQ(stateOnRay(map, u, 24, 0.30), VoxelState::free);
    EXPECT_EQ(stateOnRay(map, u, 24, 0.74), VoxelState::free);
    EXPECT_EQ(stateOnRay(map, u, 24, 0.76), VoxelState::unknown); // past max range
    EXPECT_EQ(stateOnRay(map, u, 24, 1.50), VoxelState::unknown);
  }
}

TEST(SensorToMap, RaysWithoutAReturnAddNothing)
{
  // The wall covers only the left half of the view (y > 0): the right half sees nothing
  // within the sensor's 9 m, gets NaN points and must leave the map unknown.
  const CloudXYZL cloud =
      captureFromOrigin(makeQuad(Eigen::Vector3d(0.5, 1.5, 0), kY, kZ, 1.5));
  std::size_t nan_points = 0;
  for (const auto& p : cloud.points)
    nan_points += std::isnan(p.x);
  ASSERT_GT(nan_points, 0u);
  ASSERT_LT(nan_points, cloud.size());

  OccupancyMap map;
  map.insert(cloud, Eigen::Vector3d::Zero());
  EXPECT_EQ(map.getLastInsertStats().non_finite, nan_points);
  // Pixel 10 of the middle row looks left (y > 0) at the wall, pixel 54 right at nothing.
  const pcl::PointXYZL& hit = cloud.at(10, 24);
  ASSERT_NEAR(hit.x, 0.5, 1e-5);
  const double wall_range = hit.getVector3fMap().norm();
  EXPECT_EQ(stateOnRay(map, 10, 24, 0.6 * wall_range), VoxelState::free);
  EXPECT_EQ(map.state(hit.getVector3fMap().cast<double>()), VoxelState::occupied);
  EXPECT_EQ(stateOnRay(map, 10, 24, wall_range + 0.05), VoxelState::unknown); // behind
  ASSERT_TRUE(std::isnan(cloud.at(54, 24).x));
  EXPECT_EQ(stateOnRay(map, 54, 24, 0.3), VoxelState::unknown); // no return that side
}
