#pragma once
// A pixel's ray against a box, as a RayMask must hold it, and a camera of odd size for
// the masks' tests.

#include <algorithm>
#include <cstdint>

#include <Eigen/Geometry>

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/common/pose.h>

namespace plantnbv {
namespace test {

/// Whether the ray of pixel (u, v), from the optical centre of T_W_O up to range_m,
/// meets the box [lo, hi] (slabs, in double).
inline bool pixelRayMeetsBox(const CameraIntrinsics& K, const Pose& T_W_O, double range_m,
                             std::uint32_t u, std::uint32_t v, const double lo[3],
                             const double hi[3])
{
  const Eigen::Vector3d d_O =
      Eigen::Vector3d((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0).normalized();
  const Eigen::Vector3d d = T_W_O.orientation * d_O;
  const Eigen::Vector3d& o = T_W_O.position;
  double t0 = 0.0, t1 = range_m;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < lo[a] || o[a] > hi[a])
        return false;
      continue;
    }
    double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
    if (ta > tb)
      std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1;
}

/// A 70 x 45 camera: sizes that the masks' 4-pixel cells do not divide.
inline CameraIntrinsics oddSizedCamera()
{
  CameraIntrinsics K;
  K.width = 70;
  K.height = 45;
  K.fx = 50.0;
  K.fy = 48.0;
  K.cx = 33.7;
  K.cy = 23.1;
  return K;
}

} // namespace test
} // namespace plantnbv
