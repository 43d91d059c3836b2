#include <array>
#include <cstddef>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include <plantnbv/common/box.h>
#include <plantnbv/experiment/region_ray_mask.h>

#include "pixel_ray.h"

using namespace plantnbv;

using test::oddSizedCamera;
using test::pixelRayMeetsBox;

namespace {

/// A region over [-1, 1]^3 at 1 cm (bricks of 8 cm) with a few boxes' bricks.
UpdateRegion regionOfBoxes(std::mt19937_64& rng)
{
  UpdateRegion region(0.01, Box::fromMinMax(Eigen::Vector3d::Constant(-1.0),
                                            Eigen::Vector3d::Constant(1.0)));
  std::uniform_real_distribution<double> place(-0.6, 0.4), size(0.01, 0.3);
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d lo(place(rng), place(rng), place(rng));
    region.addBox(
        Box::fromMinMax(lo, lo + Eigen::Vector3d(size(rng), size(rng), size(rng))));
  }
  return region;
}

Pose randomPose(std::mt19937_64& rng, double reach)
{
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Eigen::Quaterniond q(unit(rng), unit(rng), unit(rng), unit(rng));
  return Pose(reach * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)), q.normalized());
}

} // namespace

TEST(RegionRayMask, HoldsEveryPixelWhoseRayMeetsABrickWithinRange)
{
  const CameraIntrinsics K = oddSizedCamera();
  const std::size_t all_pixels = std::size_t(K.width) * K.height;
  std::mt19937_64 rng(11);
  int partial = 0, empty = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const UpdateRegion region = regionOfBoxes(rng);
    std::vector<std::array<double, 6>> bricks;
    region.forEachBrick([&](const double* lo, const double* hi) {
      bricks.push_back({lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]});
    });
    // Cameras among the boxes, their range's cube inside the region's bounds.
    const Pose T_W_O = randomPose(rng, 0.4);
    const double range = 0.3 + 0.3 * std::uniform_real_distribution<double>()(rng);
    const RayMask mask = regionRayMask(region, K, T_W_O, range);
    for (std::uint32_t v = 0; v < K.height; ++v)
      for (std::uint32_t u = 0; u < K.width; ++u)
        for (const auto& b : bricks)
          if (pixelRayMeetsBox(K, T_W_O, range, u, v, b.data(), b.data() + 3)) {
            ASSERT_TRUE(mask.containsPixel(u, v))
                << "trial " << trial << " pixel " << u << ", " << v;
            break;
          }
    partial += mask.pixelCount() > 0 && mask.pixelCount() < all_pixels;
    empty += mask.pixelCount() == 0;
  }
  // The cases that matter occurred: masks of some pixels, and of none (every brick out
  // of reach or out of view).
  EXPECT_GT(partial, 10) << partial;
  EXPECT_GT(empty, 2) << empty;
}

TEST(RegionRayMask, EveryPixelWhereTheRaysMayLeaveTheRegionsBounds)
{
  const CameraIntrinsics K = oddSizedCamera();
  const std::size_t all_pixels = std::size_t(K.width) * K.height;
  const UpdateRegion region(0.01, Box::fromMinMax(Eigen::Vector3d::Constant(-1.0),
                                                  Eigen::Vector3d::Constant(1.0)));
  // No brick: no pixel while the rays stay within the bounds, every pixel once they may
  // leave them (the space outside is all in the region), whichever way the camera looks.
  // The bounds are the bricks' (8 cm): 1.04 m here.
  double lo[3], hi[3];
  region.getBounds(lo, hi);
  const Pose T_W_O(Eigen::Vector3d(0.5, 0.0, 0.0), Eigen::Quaterniond::Identity());
  const double to_bound = hi[0] - 0.5;
  EXPECT_EQ(regionRayMask(region, K, T_W_O, to_bound - 0.01).pixelCount(), 0u);
  EXPECT_EQ(regionRayMask(region, K, T_W_O, to_bound + 0.01).pixelCount(), all_pixels);
}
