#pragma once
/// \file region_horizon.h
/// \brief RegionHorizon: how far the rays from one origin travel before they can enter a
/// brick of an UpdateRegion, so that their first jump starts there.

#include <algorithm>
#include <vector>

#include <Eigen/Core>

#include <plantnbv/octree/update_region.h>

namespace plantnbv {

/// \brief For the rays from one origin (a camera), a lower bound per direction of the
/// distance at which a ray can first enter a brick of an UpdateRegion.
///
/// A frame's rays start outside the region and, one by one, march the bricks between the
/// camera and the first brick of the region (ray_traversal::traverseRayInRegion); that
/// march was about a quarter of a trial's insertion. compute() bins the directions by
/// where they cross the plane at unit distance along an axis (a pinhole's image plane:
/// 256 x 256 bins out to 60 degrees from the axis on each side) and gives each bin the
/// distance of the nearest brick whose projection covers it. The bricks are grown by a
/// hundredth of a voxel first, far above the rounding of a ray's float direction and of
/// its steps, so that no ray enters a brick of the region before the bound of its bin:
/// the ray may start its march there (traverseRayInRegion's `clear_until`), and the
/// voxels it visits in the region are the same. A brick that reaches behind the plane
/// through the origin, and the bounds of the region (every voxel beyond them is in it),
/// bound every direction.
///
/// \code
/// RegionHorizon horizon;
/// horizon.compute(region, origin, axis, max_range_m);  // once per frame
/// const double clear = horizon.clearDistance(end);      // per ray
/// \endcode
class RegionHorizon {
public:
  /// \brief Bins per side of the plane of directions.
  static constexpr int kBins = 256;
  /// \brief The plane's half-width (tan 60 degrees): a direction whose crossing lies
  /// farther from the axis along either side (60 to 68 degrees off it) gets no bound.
  static constexpr double kHalfWidth = 1.7320508075688772;

  /// \brief The bounds of the rays from `origin_W` (the rays' float origin, metres)
  /// around `axis_W` (any length > 0; e.g. the mean of the rays' directions). Bricks
  /// farther than `reach_m` from the origin are left out: a bin that no nearer brick
  /// covers gets `reach_m`, so a ray shorter than that enters no brick at all.
  void compute(const UpdateRegion& region, const float origin_W[3],
               const Eigen::Vector3d& axis_W, double reach_m);

  /// \brief Metres along the ray from the origin to `end_W` before which it enters no
  /// brick of the region: 0 for a direction beyond the plane (kHalfWidth), or before
  /// compute().
  double clearDistance(const float end_W[3]) const
  {
    if (bins_.empty())
      return 0.0;
    double rel[3];
    for (int a = 0; a < 3; ++a)
      rel[a] = static_cast<double>(end_W[a]) - origin_[a];
    const double depth = dot(rel, axis_);
    if (!(depth > 0.0))
      return 0.0;
    const double u = dot(rel, e1_) / depth, v = dot(rel, e2_) / depth;
    if (!(u > -kHalfWidth && u < kHalfWidth && v > -kHalfWidth && v < kHalfWidth))
      return 0.0;
    return std::min(static_cast<double>(bins_[binOf(v) * kBins + binOf(u)]), everywhere_);
  }

private:
  static double dot(const double a[3], const double b[3])
  {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  }
  /// The bin of a plane coordinate (the same rounding in compute() and clearDistance(),
  /// so that both are monotone in it), clamped to the plane.
  static int binOf(double x)
  {
    const double f = (x + kHalfWidth) * (kBins / (2.0 * kHalfWidth));
    return f > 0.0 ? std::min(static_cast<int>(f), kBins - 1) : 0;
  }

  double origin_[3] = {0.0, 0.0, 0.0};
  double axis_[3] = {0.0, 0.0, 1.0}, e1_[3] = {1.0, 0.0, 0.0}, e2_[3] = {0.0, 1.0, 0.0};
  /// The bound of every direction: bricks behind the origin's plane, the bounds.
  double everywhere_ = 0.0;
  /// Per bin (row v, column u), the bound rounded down to float.
  std::vector<float> bins_;
};

} // namespace plantnbv
