#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/camera/depth_image.h>
#include <plantnbv/camera/optical_frame.h>
#include <plantnbv/common/error.h>

namespace plantnbv {
namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();

TEST(OpticalFrame, LooksAlongTheBodyXAxisWithImageRowsDownwards)
{
  const Pose body = Pose::fromXyzQuat(0.1, 0.2, 0.3, 0.0, 0.0, -0.383, 0.924);
  const Pose optical = opticalFrame(body);
  EXPECT_EQ(optical.position, body.position);
  const Eigen::Matrix3d R_W_O = optical.orientation.toRotationMatrix();
  const Eigen::Matrix3d R_W_C = body.orientation.toRotationMatrix();
  // z forward = body x, x right = body -y, y down = body -z.
  EXPECT_TRUE(R_W_O.col(2).isApprox(R_W_C.col(0), 1e-12));
  EXPECT_TRUE(R_W_O.col(0).isApprox(-R_W_C.col(1), 1e-12));
  EXPECT_TRUE(R_W_O.col(1).isApprox(-R_W_C.col(2), 1e-12));
  const Pose back = bodyFrame(optical);
  EXPECT_TRUE(back.orientation.toRotationMatrix().isApprox(R_W_C, 1e-12));
  EXPECT_EQ(back.position, body.position);
}

TEST(DepthImage, PixelCentresAtIntegerCoordinates)
{
  // 3 x 2 image, principal point at the centre of pixel (1, 0.5).
  const CameraIntrinsics K = CameraIntrinsics::custom(3, 2, 100.0, 200.0, 1.0, 0.5);
  DepthImage depth;
  depth.width = 3;
  depth.height = 2;
  depth.depth_m = {1.0f, 2.0f, kNaN, 0.0f, 0.5f, 4.0f};
  CloudXYZ cloud;
  depthToCloud(depth, K, Pose(), cloud); // optical frame = world
  ASSERT_EQ(cloud.width, 3u);
  ASSERT_EQ(cloud.height, 2u);
  EXPECT_FALSE(cloud.is_dense);
  // (u, v) = (0, 0), d = 1: ((0 - 1) / 100, (0 - 0.5) / 200, 1).
  EXPECT_FLOAT_EQ(cloud.at(0, 0).x, -0.01f);
  EXPECT_FLOAT_EQ(cloud.at(0, 0).y, -0.0025f);
  EXPECT_FLOAT_EQ(cloud.at(0, 0).z, 1.0f);
  // (1, 0), d = 2: on the principal column.
  EXPECT_FLOAT_EQ(cloud.at(1, 0).x, 0.0f);
  EXPECT_FLOAT_EQ(cloud.at(1, 0).y, -0.005f);
  // NaN and 0 are no return.
  EXPECT_TRUE(std::isnan(cloud.at(2, 0).x));
  EXPECT_TRUE(std::isnan(cloud.at(0, 1).z));
  // (2, 1), d = 4: (0.04, 0.01, 4).
  EXPECT_FLOAT_EQ(cloud.at(2, 1).x, 0.04f);
  EXPECT_FLOAT_EQ(cloud.at(2, 1).y, 0.01f);
  EXPECT_FLOAT_EQ(cloud.at(2, 1).z, 4.0f);
}

TEST(DepthImage, BackProjectsIntoTheWorldThroughTheOpticalPose)
{
  const CameraIntrinsics K = CameraIntrinsics::custom(1, 1, 10.0, 10.0, 0.0, 0.0);
  DepthImage depth{1, 1, {2.0f}};
  // Body at (1, 2, 3) looking along world +y: the point lies 2 m along +y.
  const Pose body(Eigen::Vector3d(1, 2, 3), Eigen::Quaterniond(Eigen::AngleAxisd(
                                                M_PI / 2, Eigen::Vector3d::UnitZ())));
  CloudXYZ cloud;
  depthToCloud(depth, K, opticalFrame(body), cloud);
  EXPECT_NEAR(cloud.points[0].x, 1.0, 1e-6);
  EXPECT_NEAR(cloud.points[0].y, 4.0, 1e-6);
  EXPECT_NEAR(cloud.points[0].z, 3.0, 1e-6);
  EXPECT_TRUE(cloud.is_dense);
  EXPECT_FLOAT_EQ(cloud.sensor_origin_.y(), 2.0f);
}

TEST(DepthImage, RefusesAnImageOfAnotherSize)
{
  const CameraIntrinsics K = CameraIntrinsics::custom(4, 3, 10.0, 10.0, 1.5, 1.0);
  DepthImage depth{3, 3, std::vector<float>(9, 1.0f)};
  CloudXYZ cloud;
  EXPECT_THROW(depthToCloud(depth, K, Pose(), cloud), InvalidArgumentError);
  depth = DepthImage{4, 3, std::vector<float>(5, 1.0f)};
  EXPECT_THROW(depthToCloud(depth, K, Pose(), cloud), InvalidArgumentError);
}

TEST(DepthImage, UnitsRoundToTheNearestAndZeroIsNoReturn)
{
  EXPECT_EQ(depthToUnits(0.4004f, 1000.0), 400);
  EXPECT_EQ(depthToUnits(0.4006f, 1000.0), 401);
  EXPECT_EQ(depthToUnits(0.2f, 5000.0), 1000);
  EXPECT_EQ(depthToUnits(kNaN, 1000.0), 0);
  EXPECT_EQ(depthToUnits(0.0004f, 1000.0), 0); // rounds to 0
  EXPECT_EQ(depthToUnits(65.6f, 1000.0), 0);   // over 65535 units
  EXPECT_EQ(depthToUnits(-1.0f, 1000.0), 0);
  EXPECT_TRUE(std::isnan(depthFromUnits(0, 1000.0)));
  EXPECT_FLOAT_EQ(depthFromUnits(1234, 1000.0), 1.234f);

  DepthImage depth{2, 1, {0.4004f, kNaN}};
  roundDepthToUnits(depth, 1000.0);
  EXPECT_EQ(depth.depth_m[0], depthFromUnits(400, 1000.0));
  EXPECT_TRUE(std::isnan(depth.depth_m[1]));
  EXPECT_THROW(roundDepthToUnits(depth, 0.0), InvalidArgumentError);
  EXPECT_THROW(roundDepthToUnits(depth, std::nan("")), InvalidArgumentError);
}

} // namespace
} // namespace plantnbv
