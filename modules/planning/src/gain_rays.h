#pragma once
// The rays of a candidate view, shared by the fast gain and the reference so that both
// walk exactly the same segments (internal to the planning module).

#include <vector>

#include <Eigen/Core>

#include <plantnbv/common/pose.h>
#include <plantnbv/planning/information_gain.h>

namespace plantnbv {
namespace gain_detail {

/// Unit directions of the rays in the camera body frame (x forward, y left, z up), ray
/// (i, j) at j * rays_x + i: through the centre of cell (i, j) of the image-plane grid,
/// column i from the left, row j from the top.
std::vector<Eigen::Vector3d> rayDirectionsBody(const GainConfig& config);

/// tan of half the field of view; the image-plane x (optical, right) of column i is
/// tan_half_h * ((2 i + 1) / rays_x - 1), likewise y (down) of row j.
struct ImagePlane {
  double tan_half_h = 0.0;
  double tan_half_v = 0.0;
};
ImagePlane imagePlane(const GainConfig& config);

/// A candidate's rays in the world: the float origin (OctoMap's point3d) and, per ray,
/// the float end position + range * R_W_C * d_C, computed in double and rounded once.
/// Not inlined, so every caller rounds alike.
void rayOrigin(const Viewpoint& view, float origin[3]);
void rayEnd(const Eigen::Matrix3d& R_W_C, const Eigen::Vector3d& position,
            const Eigen::Vector3d& direction_C, double range_m, float end[3]);

} // namespace gain_detail
} // namespace plantnbv
