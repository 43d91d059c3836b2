#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include <plantnbv/octree/region_horizon.h>

namespace plantnbv {

namespace {

/// How much a brick is grown before it is projected (voxels): far above a ray's
/// deviation from the straight line to its end (its float direction, ~1e-7 of its length;
/// its steps' sums, ~1e-13 m) and the width of the ties in which OctoMap's steps may pass
/// through a neighbouring brick (1e-6 voxels, ray_traversal::nextBrickEntry).
constexpr double kGrowthVoxels = 0.01;
/// How much a brick's projection is grown (plane units, about 1e-9 rad): far above the
/// rounding of the divisions.
constexpr double kPlaneGrowth = 1e-9;

/// `v` rounded down to a float.
float floatBelow(double v)
{
  float f = static_cast<float>(v);
  if (static_cast<double>(f) > v)
    f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

} // namespace

void RegionHorizon::compute(const UpdateRegion& region, const float origin_W[3],
                            const Eigen::Vector3d& axis_W, double reach_m)
{
  const Eigen::Vector3d axis = axis_W.normalized();
  // Any unit vector across the axis, then the third.
  const Eigen::Vector3d across =
      std::fabs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = axis.cross(across).normalized();
  const Eigen::Vector3d e2 = axis.cross(e1);
  for (int a = 0; a < 3; ++a) {
    origin_[a] = origin_W[a];
    axis_[a] = axis[a];
    e1_[a] = e1[a];
    e2_[a] = e2[a];
  }
  if (!axis.allFinite()) { // no plane (no direction given): no bound
    bins_.clear();
    return;
  }
  bins_.assign(static_cast<std::size_t>(kBins) * kBins, floatBelow(reach_m));

  // Every voxel beyond the bounds is in the region: no ray leaves the largest ball
  // around the origin inside them before it may enter one.
  double lo[3], hi[3];
  region.getBounds(lo, hi);
  everywhere_ = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
    everywhere_ = std::min(everywhere_, std::min(origin_[a] - lo[a], hi[a] - origin_[a]));
  const double growth = kGrowthVoxels * region.resolution();
  everywhere_ = std::max(everywhere_ - growth, 0.0);

  region.forEachBrick([&](const double* brick_lo, const double* brick_hi) {
    double b_lo[3], b_hi[3], near2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      b_lo[a] = brick_lo[a] - growth;
      b_hi[a] = brick_hi[a] + growth;
      const double gap =
          std::max(std::max(b_lo[a] - origin_[a], origin_[a] - b_hi[a]), 0.0);
      near2 += gap * gap;
    }
    const double nearest = std::sqrt(near2);
    if (nearest >= everywhere_ || nearest >= reach_m)
      return; // no bin's bound gets smaller
    double u_lo = std::numeric_limits<double>::infinity(), u_hi = -u_lo;
    double v_lo = u_lo, v_hi = -u_lo;
    for (int corner = 0; corner < 8; ++corner) {
      double rel[3];
      for (int a = 0; a < 3; ++a)
        rel[a] = ((corner >> a) & 1 ? b_hi[a] : b_lo[a]) - origin_[a];
      const double depth = dot(rel, axis_);
      if (!(depth > 0.0)) { // reaches behind the origin's plane: any direction
        everywhere_ = std::min(everywhere_, nearest);
        return;
      }
      const double u = dot(rel, e1_) / depth, v = dot(rel, e2_) / depth;
      u_lo = std::min(u_lo, u);
      u_hi = std::max(u_hi, u);
      v_lo = std::min(v_lo, v);
      v_hi = std::max(v_hi, v);
    }
    // With every corner in front, the brick's projection is the hull of its corners'.
    u_lo -= kPlaneGrowth;
    v_lo -= kPlaneGrowth;
    u_hi += kPlaneGrowth;
    v_hi += kPlaneGrowth;
    if (u_hi <= -kHalfWidth || u_lo >= kHalfWidth || v_hi <= -kHalfWidth ||
        v_lo >= kHalfWidth)
      return; // beyond the plane's bins: those directions get no bound anyway
    const float bound = floatBelow(nearest);
    const int i0 = binOf(u_lo), i1 = binOf(u_hi), j0 = binOf(v_lo), j1 = binOf(v_hi);
    for (int j = j0; j <= j1; ++j) {
      float* row = &bins_[static_cast<std::size_t>(j) * kBins];
      for (int i = i0; i <= i1; ++i)
        row[i] = std::min(row[i], bound);
    }
  });
}

} // namespace plantnbv
