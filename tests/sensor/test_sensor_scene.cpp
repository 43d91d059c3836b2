#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/plant/plant_model.h>
#include <plantnbv/sensor/sensor_scene.h>
#include <plantnbv/sensor/simulated_depth_sensor.h>

#include "sensor_test_util.h"

using namespace plantnbv;

namespace {

/// A square grid of n x n points with spacing s in the plane x = x0.
std::vector<Eigen::Vector3f> gridPoints(int n, float s, float x0 = 1.0f)
{
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      points.emplace_back(x0, (i - 0.5f * (n - 1)) * s, (j - 0.5f * (n - 1)) * s);
  return points;
}

} // namespace

TEST(SurfelRadii, GridSpacingGivesTheSpacing)
{
  const float s = 0.002f;
  const int n = 21;
  const std::vector<float> radii = surfelRadii(gridPoints(n, s));
  ASSERT_EQ(radii.size(), std::size_t(n * n));
  // Interior points: 4 neighbours at s, then 4 at sqrt(2) s.
  for (int i = 1; i + 1 < n; ++i)
    for (int j = 1; j + 1 < n; ++j)
      EXPECT_NEAR(radii[std::size_t(i * n + j)], std::sqrt(2.0f) * s, 1e-7f);
  // A corner's 6th neighbour is at sqrt(5) s.
  EXPECT_NEAR(radii[0], std::sqrt(5.0f) * s, 1e-7f);
  SurfelOptions fourth;
  fourth.spacing_neighbours = 4;
  EXPECT_NEAR(surfelRadii(gridPoints(n, s), fourth)[std::size_t(n + 1)], s, 1e-7f);

  SurfelOptions fixed;
  fixed.radius_m = 0.01;
  for (float r : surfelRadii(gridPoints(3, s), fixed))
    EXPECT_FLOAT_EQ(r, 0.01f);
  SurfelOptions scaled;
  scaled.radius_factor = 0.5;
  scaled.spacing_neighbours = 1;
  EXPECT_NEAR(surfelRadii(gridPoints(n, s), scaled)[std::size_t(n + 1)], 0.5f * s, 1e-7f);
}

TEST(SurfelRadii, OutliersAreClampedToTheMedianSpacing)
{
  std::vector<Eigen::Vector3f> points = gridPoints(21, 0.002f);
  points.emplace_back(5.0f, 5.0f, 5.0f); // far from everything
  const std::vector<float> radii = surfelRadii(points);
  EXPECT_NEAR(radii.back(), 4.0f * std::sqrt(2.0f) * 0.002f, 1e-7f);
}

TEST(SurfelRadii, RejectsBadInput)
{
  EXPECT_THROW(surfelRadii({}), InvalidArgumentError);
  EXPECT_THROW(surfelRadii(gridPoints(2, 0.01f)), InvalidArgumentError); // 4 < 6 + 1
  std::vector<Eigen::Vector3f> nan_points = gridPoints(5, 0.01f);
  nan_points[3].y() = NAN;
  EXPECT_THROW(surfelRadii(nan_points), InvalidArgumentError);
  std::vector<Eigen::Vector3f> same(10, Eigen::Vector3f::Ones());
  EXPECT_THROW(surfelRadii(same), InvalidArgumentError);
  SurfelOptions bad;
  bad.spacing_neighbours = 0;
  EXPECT_THROW(surfelRadii(gridPoints(5, 0.01f), bad), InvalidArgumentError);
  bad = SurfelOptions();
  bad.radius_m = -1.0;
  EXPECT_THROW(surfelRadii(gridPoints(5, 0.01f), bad), InvalidArgumentError);
}

TEST(SensorScene, CountsBoundsAndCommitState)
{
  SensorScene scene;
  EXPECT_FALSE(scene.isCommitted());
  Eigen::Vector3f min, max;
  EXPECT_THROW(scene.bounds(min, max), InvalidArgumentError);
  const TriangleMesh quad = test::makeQuad(
      Eigen::Vector3d(1, 0, 0), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ(), 0.5);
  EXPECT_EQ(scene.addMesh(quad), 0u);
  EXPECT_EQ(scene.addSurfels(gridPoints(5, 0.01f, 2.0f), {}), 1u);
  EXPECT_EQ(scene.addFloor(0.0, 5.0), 2u);
  EXPECT_EQ(scene.addSupport(Eigen::Vector3d(1, 0, 0.8), 0.15, 0.0), 3u);
  EXPECT_EQ(scene.geometryCount(), 4u);
  EXPECT_EQ(scene.triangleCount(), 2u + 2u + 12u);
  EXPECT_EQ(scene.surfelCount(), 25u);
  scene.bounds(min, max);
  EXPECT_FLOAT_EQ(min.x(), -5.0f);
  EXPECT_FLOAT_EQ(max.y(), 5.0f);
  EXPECT_FLOAT_EQ(max.z(), 0.8f);
  EXPECT_FALSE(scene.isCommitted());
  scene.commit();
  EXPECT_TRUE(scene.isCommitted());
  scene.addMesh(quad);
  EXPECT_FALSE(scene.isCommitted());

  // A sensor refuses a scene that is not committed, and notices a later change.
  auto shared = std::make_shared<SensorScene>(std::move(scene));
  SimulatedDepthSensor sensor(test::smallCamera());
  EXPECT_THROW(sensor.setScene(shared), InvalidArgumentError);
  EXPECT_THROW(sensor.setScene(nullptr), InvalidArgumentError);
  shared->commit();
  sensor.setScene(shared);
  shared->addFloor(-1.0, 1.0);
  CloudXYZL cloud;
  EXPECT_THROW(sensor.capture(Pose(), cloud), Error);
}

TEST(SensorScene, RejectsBadGeometry)
{
  SensorScene scene;
  EXPECT_THROW(scene.addMesh(TriangleMesh()), InvalidArgumentError);
  TriangleMesh broken = test::makeQuad(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(),
                                       Eigen::Vector3d::UnitY(), 1);
  broken.triangles[1][2] = 7; // no such vertex
  EXPECT_THROW(scene.addMesh(broken), FormatError);
  const std::vector<Eigen::Vector3f> points = gridPoints(5, 0.01f);
  EXPECT_THROW(scene.addSurfels(points, std::vector<PartLabel>(3, PartLabel::stem)),
               InvalidArgumentError);
  EXPECT_THROW(scene.addSurfels(points, {}, std::vector<Eigen::Vector3f>(2)),
               InvalidArgumentError);
  EXPECT_THROW(scene.addSurfels(
                   points, {}, std::vector<Eigen::Vector3f>(25, Eigen::Vector3f::Zero())),
               InvalidArgumentError);
  CloudXYZL nan_cloud;
  pcl::PointXYZL p;
  p.x = p.y = p.z = NAN;
  nan_cloud.push_back(p);
  EXPECT_THROW(scene.addSurfels(nan_cloud), InvalidArgumentError);
  EXPECT_THROW(scene.addFloor(0.0, 0.0), InvalidArgumentError);
  EXPECT_THROW(scene.addSupport(Eigen::Vector3d(0, 0, 0.5), 0.1, 0.5),
               InvalidArgumentError);
  EXPECT_EQ(scene.geometryCount(), 0u);
}

