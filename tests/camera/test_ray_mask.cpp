#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include <plantnbv/camera/optical_frame.h>
#include <plantnbv/camera/ray_mask.h>
#include <plantnbv/common/error.h>

#include "pixel_ray.h"

using namespace plantnbv;

using test::oddSizedCamera;
using test::pixelRayMeetsBox;

TEST(RayMask, HoldsEveryPixelWhoseRayMeetsABox)
{
  const CameraIntrinsics K = oddSizedCamera();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int partial = 0, straddling = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Eigen::Quaterniond q(unit(rng), unit(rng), unit(rng), unit(rng));
    const Pose T_W_O(Eigen::Vector3d(unit(rng), unit(rng), unit(rng)), q.normalized());
    const double range = 0.5 + 0.5 * (unit(rng) + 1.0);
    // Boxes anywhere around the camera, small to large: in front, behind, across the
    // optical centre's plane, beyond the range.
    const Eigen::Vector3d centre =
        T_W_O.position + 0.8 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    const double half = 0.01 + 0.2 * (unit(rng) + 1.0);
    const double lo[3] = {centre.x() - half, centre.y() - 0.5 * half, centre.z() - half};
    const double hi[3] = {centre.x() + half, centre.y() + 0.5 * half, centre.z() + half};
    RayMask mask(K, T_W_O, range);
    mask.addBox(lo, hi);
    std::size_t meeting = 0;
    for (std::uint32_t v = 0; v < K.height; ++v)
      for (std::uint32_t u = 0; u < K.width; ++u)
        if (pixelRayMeetsBox(K, T_W_O, range, u, v, lo, hi)) {
          ++meeting;
          ASSERT_TRUE(mask.containsPixel(u, v))
              << "trial " << trial << " pixel " << u << ", " << v;
        }
    const std::size_t total = std::size_t(K.width) * K.height;
    partial += meeting > 0 && mask.pixelCount() < total;
    // Corners on both sides of the optical centre's plane.
    int in_front = 0;
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d p(c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1],
                              c & 4 ? hi[2] : lo[2]);
      in_front += (T_W_O.orientation.inverse() * (p - T_W_O.position)).z() > 0.0;
    }
    straddling +=
        meeting > 0 && in_front > 0 && in_front < 8 && mask.pixelCount() < total;
  }
  // The cases that matter occurred: masks that hold the rays met and not every pixel,
  // also for boxes reaching behind the camera.
  EXPECT_GT(partial, 200) << partial;
  EXPECT_GT(straddling, 20) << straddling;
}

TEST(RayMask, MarksNothingBeyondTheRangeOrBehindAndAllAroundTheCentreOrForAnEndlessBox)
{
  const CameraIntrinsics K = oddSizedCamera();
  const Pose T_W_O; // looking along +z
  RayMask mask(K, T_W_O, 1.0);
  const double beyond_lo[3] = {-0.1, -0.1, 1.01}, beyond_hi[3] = {0.1, 0.1, 1.2};
  mask.addBox(beyond_lo, beyond_hi);
  const double behind_lo[3] = {-0.5, -0.5, -0.6}, behind_hi[3] = {0.5, 0.5, -0.01};
  mask.addBox(behind_lo, behind_hi);
  EXPECT_EQ(mask.pixelCount(), 0u);

  // A box straight ahead, within range: the pixels around the principal point only.
  const double ahead_lo[3] = {-0.01, -0.01, 0.5}, ahead_hi[3] = {0.01, 0.01, 0.6};
  mask.addBox(ahead_lo, ahead_hi);
  EXPECT_TRUE(mask.containsPixel(34, 23));
  EXPECT_FALSE(mask.containsPixel(0, 0));
  EXPECT_GT(mask.pixelCount(), 0u);
  EXPECT_LT(mask.pixelCount(), 200u);

  EXPECT_FALSE(mask.containsPixel(K.width, 0)); // outside the image
  EXPECT_FALSE(mask.containsPixel(0, 100000));

  // A NaN bound: no box; an endless slab ahead: every pixel (its corners do not
  // project).
  const double nan = std::nan("");
  const double nan_lo[3] = {nan, -0.1, 0.5}, nan_hi[3] = {0.1, 0.1, 0.6};
  const std::size_t before = mask.pixelCount();
  mask.addBox(nan_lo, nan_hi);
  EXPECT_EQ(mask.pixelCount(), before);
  RayMask slab(K, T_W_O, 1.0);
  const double slab_lo[3] = {-HUGE_VAL, -HUGE_VAL, 0.5},
               slab_hi[3] = {HUGE_VAL, HUGE_VAL, 0.6};
  slab.addBox(slab_lo, slab_hi);
  EXPECT_EQ(slab.pixelCount(), std::size_t(K.width) * K.height);

  const double around_lo[3] = {-0.01, -0.01, -0.01}, around_hi[3] = {0.01, 0.01, 0.01};
  mask.addBox(around_lo, around_hi);
  EXPECT_EQ(mask.pixelCount(), std::size_t(K.width) * K.height);
}

TEST(RayMask, ABoxWithinTheFloatRoundingOfTheCentreMarksEveryPixel)
{
  // At x = 1000 m a float's spacing is 6.1e-5 m: a sensor's rays start up to 3e-5 m
  // from the centre, so inside a box 1e-5 m beside it.
  const CameraIntrinsics K = oddSizedCamera();
  const Pose T_W_O(Eigen::Vector3d(1000.1, 0.2, 0.3), Eigen::Quaterniond::Identity());
  ASSERT_GT(std::abs(double(float(1000.1)) - 1000.1), 1e-5);
  RayMask mask(K, T_W_O, 1.0);
  const double lo[3] = {1000.1 + 1e-5, -0.3, -0.2}, hi[3] = {1000.2, 0.7, 0.8};
  mask.addBox(lo, hi);
  EXPECT_EQ(mask.pixelCount(), std::size_t(K.width) * K.height);
}

TEST(RayMask, RejectsABadRangeOrCamera)
{
  const CameraIntrinsics K = oddSizedCamera();
  for (double range : {0.0, -1.0, std::nan(""), HUGE_VAL})
    EXPECT_THROW(RayMask(K, Pose(), range), InvalidArgumentError) << range;
  CameraIntrinsics bad = K;
  bad.fx = 0.0;
  EXPECT_THROW(RayMask(bad, Pose(), 1.0), InvalidArgumentError);
}
