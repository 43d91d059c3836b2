#include <cmath>
#include <limits>
#include <string>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/camera/depth_image.h>
#include <plantnbv/common/error.h>

namespace plantnbv {

namespace {

void requireUnits(double units_per_m, const char* who)
{
  if (!(units_per_m > 0.0) || !std::isfinite(units_per_m))
    throw InvalidArgumentError(std::string(who) +
                               ": depth units per metre must be finite and > 0, got " +
                               std::to_string(units_per_m));
}

} // namespace

std::uint16_t depthToUnits(float depth_m, double units_per_m)
{
  const double units = std::round(double(depth_m) * units_per_m);
  return units >= 1.0 && units <= 65535.0 ? static_cast<std::uint16_t>(units)
                                          : 0; // NaN: 0
}

float depthFromUnits(std::uint16_t units, double units_per_m)
{
  return units == 0 ? std::numeric_limits<float>::quiet_NaN()
                    : float(units / units_per_m);
}

void roundDepthToUnits(DepthImage& depth, double units_per_m)
{
  requireUnits(units_per_m, "roundDepthToUnits");
  for (float& d : depth.depth_m)
    d = depthFromUnits(depthToUnits(d, units_per_m), units_per_m);
}

void depthToCloud(const DepthImage& depth, const CameraIntrinsics& K, const Pose& T_W_O,
                  CloudXYZ& cloud_W)
{
  const std::size_t n = std::size_t(depth.width) * depth.height;
  if (depth.width != K.width || depth.height != K.height || depth.depth_m.size() < n)
    throw InvalidArgumentError("depthToCloud: a " + std::to_string(depth.width) + "x" +
                               std::to_string(depth.height) + " image with " +
                               std::to_string(depth.depth_m.size()) +
                               " values for a camera of " + std::to_string(K.width) +
                               "x" + std::to_string(K.height));
  const Eigen::Matrix3d R = T_W_O.orientation.toRotationMatrix();
  const Eigen::Vector3d& t = T_W_O.position;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cloud_W.width = depth.width;
  cloud_W.height = depth.height;
  cloud_W.points.resize(n);
  cloud_W.sensor_origin_ =
      Eigen::Vector4f(float(t.x()), float(t.y()), float(t.z()), 0.0f);
  cloud_W.sensor_orientation_ = T_W_O.orientation.cast<float>();
  bool dense = true;
  for (std::uint32_t v = 0; v < depth.height; ++v)
    for (std::uint32_t u = 0; u < depth.width; ++u) {
      const std::size_t i = std::size_t(v) * depth.width + u;
      const double d = depth.depth_m[i];
      pcl::PointXYZ& p = cloud_W.points[i];
      if (!(d > 0.0) || !std::isfinite(d)) {
        p.x = p.y = p.z = nan;
        dense = false;
        continue;
      }
      const Eigen::Vector3d p_O((u - K.cx) / K.fx * d, (v - K.cy) / K.fy * d, d);
      const Eigen::Vector3d p_W = R * p_O + t;
      p.x = float(p_W.x());
      p.y = float(p_W.y());
      p.z = float(p_W.z());
    }
  cloud_W.is_dense = dense;
}

} // namespace plantnbv
