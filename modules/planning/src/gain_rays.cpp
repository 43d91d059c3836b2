#include <cmath>

#include "gain_rays.h"

namespace plantnbv {
namespace gain_detail {

ImagePlane imagePlane(const GainConfig& config)
{
  ImagePlane plane;
  plane.tan_half_h = std::tan(0.5 * config.horizontal_fov_rad);
  plane.tan_half_v = std::tan(0.5 * config.vertical_fov_rad);
  return plane;
}

std::vector<Eigen::Vector3d> rayDirectionsBody(const GainConfig& config)
{
  const ImagePlane plane = imagePlane(config);
  std::vector<Eigen::Vector3d> dirs;
  dirs.reserve(static_cast<std::size_t>(config.rays_x) * config.rays_y);
  for (int j = 0; j < config.rays_y; ++j) {
    const double y_o = plane.tan_half_v * ((2.0 * j + 1.0) / config.rays_y - 1.0);
    for (int i = 0; i < config.rays_x; ++i) {
      const double x_o = plane.tan_half_h * ((2.0 * i + 1.0) / config.rays_x - 1.0);
      // Optical (x right, y down, z forward) to body (x forward, y left, z up).
      dirs.push_back(Eigen::Vector3d(1.0, -x_o, -y_o).normalized());
    }
  }
  return dirs;
}

void rayOrigin(const Viewpoint& view, float origin[3])
{
  for (int a = 0; a < 3; ++a)
    origin[a] = static_cast<float>(view.position[a]);
}

void rayEnd(const Eigen::Matrix3d& R, const Eigen::Vector3d& p, const Eigen::Vector3d& d,
            double range_m, float end[3])
{
  // Written out (not an Eigen product) so the rounding is fixed here.
  for (int a = 0; a < 3; ++a) {
    const double w = R(a, 0) * d[0] + R(a, 1) * d[1] + R(a, 2) * d[2];
    end[a] = static_cast<float>(p[a] + range_m * w);
  }
}

} // namespace gain_detail
} // namespace plantnbv
