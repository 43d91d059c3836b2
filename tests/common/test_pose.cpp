#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/pose.h>

using plantnbv::Pose;

TEST(Pose, PaperInitialViewLooksAtTheStem)
{
  // Table 1: v0 at (0.646, 0.353, 1.383), quaternion (0, 0, -0.383, 0.924): a yaw of
  // -45 deg, so the body x axis points towards the plant at (1.0, 0.0).
  const Pose v0 = Pose::fromXyzQuat(0.646, 0.353, 1.383, 0, 0, -0.383, 0.924);
  const Eigen::Vector3d to_stem = Eigen::Vector3d(1.0, 0.0, 1.383) - v0.position;
  EXPECT_GT(v0.forward().dot(to_stem.normalized()), 0.9999);
  EXPECT_NEAR(v0.orientation.norm(), 1.0, 1e-12);
}

TEST(Pose, IsometryRoundTrip)
{
  const Pose p = Pose::fromXyzQuat(1, 2, 3, 0.1, 0.2, 0.3, 0.9);
  const Pose q = Pose::fromIsometry(p.toIsometry());
  EXPECT_TRUE(q.position.isApprox(p.position));
  EXPECT_NEAR(std::abs(q.orientation.dot(p.orientation)), 1.0, 1e-12);
}

TEST(Pose, RejectsZeroQuaternionAndNaN)
{
  EXPECT_THROW(Pose::fromXyzQuat(0, 0, 0, 0, 0, 0, 0), plantnbv::InvalidArgumentError);
  EXPECT_THROW(Pose::fromXyzQuat(NAN, 0, 0, 0, 0, 0, 1), plantnbv::InvalidArgumentError);
}
