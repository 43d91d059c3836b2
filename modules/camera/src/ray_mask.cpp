#include <algorithm>
#include <cmath>
#include <sstream>

#include <plantnbv/camera/ray_mask.h>
#include <plantnbv/common/error.h>

namespace plantnbv {

RayMask::RayMask(const CameraIntrinsics& K, const Pose& T_W_O, double range_m)
{
  K.validate();
  if (!(std::isfinite(range_m) && range_m > 0.0)) {
    std::ostringstream s;
    s << "RayMask: range " << range_m << " must be finite and > 0 (metres)";
    throw InvalidArgumentError(s.str());
  }
  width_ = K.width;
  height_ = K.height;
  fx_ = K.fx;
  fy_ = K.fy;
  cx_ = K.cx;
  cy_ = K.cy;
  range_m_ = range_m;
  origin_W_ = T_W_O.position;
  // Float keeps 24 bits: its rounding is under 1e-7 of the largest coordinate.
  origin_slack_m_ = 1e-6 * std::max(1.0, origin_W_.cwiseAbs().maxCoeff());
  R_O_W_ = T_W_O.orientation.normalized().toRotationMatrix().transpose();
  // The ray of the pixel farthest from the principal point has the smallest z.
  const double x = std::max(std::abs(K.cx), std::abs(width_ - 1.0 - K.cx)) / K.fx;
  const double y = std::max(std::abs(K.cy), std::abs(height_ - 1.0 - K.cy)) / K.fy;
  min_ray_z_ = 1.0 / std::sqrt(1.0 + x * x + y * y);
  cells_x_ = (width_ + kCellPixels - 1) / kCellPixels;
  cells_y_ = (height_ + kCellPixels - 1) / kCellPixels;
  cells_.assign(cells_x_ * cells_y_, 0);
}

void RayMask::addAll()
{
  std::fill(cells_.begin(), cells_.end(), std::uint8_t{1});
}

void RayMask::addBox(const double lo_W[3], const double hi_W[3])
{
  // The box grown by the rounding of a ray's origin in float (a sensor's rays start at
  // the centre rounded so; a ray from there meets the box where one from the centre
  // meets it grown by that much).
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = lo_W[a] - origin_slack_m_;
    hi[a] = hi_W[a] + origin_slack_m_;
  }
  // Farther than the range: no ray reaches it. (A ray's far end may lie a rounding
  // beyond the range: the test keeps a relative 1e-9 of slack.)
  double distance2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double d = std::max({lo[a] - origin_W_[a], 0.0, origin_W_[a] - hi[a]});
    distance2 += d * d;
  }
  const double reach = range_m_ * (1.0 + 1e-9);
  if (!(distance2 <= reach * reach))
    return;
  bool finite = true;
  for (int a = 0; a < 3; ++a)
    finite = finite && std::isfinite(lo[a]) && std::isfinite(hi[a]);
  if (distance2 == 0.0 || !finite) { // every ray starts in it; or no corners to project
    addAll();
    return;
  }
  // A ray's points in the box lie at least `distance` from the centre, so deeper than
  // z_clip in the optical frame: the rays meet the box only in its part beyond that
  // plane, whose projection is the hull of its corners' there and of the points where
  // its edges cross the plane (a box reaching behind the camera projects to a region
  // that the image clips).
  const double z_clip = 0.5 * std::sqrt(distance2) * min_ray_z_;
  Eigen::Vector3d corners[8];
  for (int corner = 0; corner < 8; ++corner)
    corners[corner] =
        R_O_W_ * (Eigen::Vector3d(corner & 1 ? hi[0] : lo[0], corner & 2 ? hi[1] : lo[1],
                                  corner & 4 ? hi[2] : lo[2]) -
                  origin_W_);
  double u_lo = INFINITY, u_hi = -INFINITY, v_lo = INFINITY, v_hi = -INFINITY;
  const auto project = [&](const Eigen::Vector3d& p_O) {
    const double u = fx_ * p_O.x() / p_O.z() + cx_;
    const double v = fy_ * p_O.y() / p_O.z() + cy_;
    u_lo = std::min(u_lo, u);
    u_hi = std::max(u_hi, u);
    v_lo = std::min(v_lo, v);
    v_hi = std::max(v_hi, v);
  };
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d& a = corners[corner];
    if (a.z() < z_clip)
      continue;
    project(a);
    for (int axis = 0; axis < 3; ++axis) { // the edges to corners behind the plane
      const Eigen::Vector3d& b = corners[corner ^ (1 << axis)];
      if (b.z() < z_clip)
        project(a + (z_clip - a.z()) / (b.z() - a.z()) * (b - a));
    }
  }
  if (!(u_lo <= u_hi)) // wholly behind the plane
    return;
  addCells(u_lo - 1.0, u_hi + 1.0, v_lo - 1.0, v_hi + 1.0);
}

void RayMask::addCells(double u_lo, double u_hi, double v_lo, double v_hi)
{
  // Pixel centres at integer (u, v): those in [u_lo, u_hi] x [v_lo, v_hi], clipped to
  // the image (compared in double first, so that far projections do not overflow).
  const double last_u = width_ - 1.0, last_v = height_ - 1.0;
  if (!(u_hi >= 0.0 && v_hi >= 0.0 && u_lo <= last_u && v_lo <= last_v))
    return;
  const auto first_u = static_cast<std::size_t>(std::ceil(std::max(u_lo, 0.0)));
  const auto end_u = static_cast<std::size_t>(std::floor(std::min(u_hi, last_u)));
  const auto first_v = static_cast<std::size_t>(std::ceil(std::max(v_lo, 0.0)));
  const auto end_v = static_cast<std::size_t>(std::floor(std::min(v_hi, last_v)));
  if (first_u > end_u || first_v > end_v)
    return;
  for (std::size_t y = first_v / kCellPixels; y <= end_v / kCellPixels; ++y)
    std::fill(cells_.begin() + static_cast<std::ptrdiff_t>(y * cells_x_ + first_u / kCellPixels),
              cells_.begin() + static_cast<std::ptrdiff_t>(y * cells_x_ + end_u / kCellPixels + 1),
              std::uint8_t{1});
}

std::size_t RayMask::pixelCount() const
{
  std::size_t count = 0;
  for (std::size_t y = 0; y < cells_y_; ++y) {
    const std::size_t rows =
        std::min<std::size_t>(kCellPixels, height_ - y * kCellPixels);
    for (std::size_t x = 0; x < cells_x_; ++x)
      if (cells_[y * cells_x_ + x])
        count += rows * std::min<std::size_t>(kCellPixels, width_ - x * kCellPixels);
  }
  return count;
}

} // namespace plantnbv
