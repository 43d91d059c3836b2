#pragma once
/// \file depth_image.h
/// \brief Depth images and their conversion to clouds with the pinhole model of
/// camera_intrinsics.h (OpenCV / ROS pixel convention), and the rounding of depth to the
/// integer units of a 16-bit depth PNG.

#include <cstdint>
#include <vector>

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/common/pcl_fwd.h>
#include <plantnbv/common/pose.h>

namespace plantnbv {

/// \brief A depth image: row-major, width x height, pixel (u, v) at v * width + u.
struct DepthImage {
  std::uint32_t width = 0;  ///< pixels (columns)
  std::uint32_t height = 0; ///< pixels (rows)
  /// Depth (metres): z of the point in the optical frame (not the range along the ray),
  /// as depth cameras report it; NaN where the pixel has no return.
  std::vector<float> depth_m;

  /// \brief The depth (metres, NaN: no return) at column u, row v; unchecked.
  float at(std::uint32_t u, std::uint32_t v) const
  {
    return depth_m[std::size_t(v) * width + u];
  }
};

/// \brief The integer units of a 16-bit depth PNG: round(depth * units_per_m), or 0 (no
/// return) for NaN, for a depth that rounds to 0 and for one above 65535 units. This and
/// depthFromUnits are the one rule that writing and reading depth PNGs follow.
std::uint16_t depthToUnits(float depth_m, double units_per_m);
/// \brief The depth (metres) of `units`; NaN for 0.
float depthFromUnits(std::uint16_t units, double units_per_m);

/// \brief Rounds every depth to what a 16-bit PNG in `units_per_m` stores and reads
/// back (depthFromUnits(depthToUnits(d))): a frame integrated after this gives the map
/// that its PNG gives. \throws InvalidArgumentError unless units_per_m is finite, > 0.
void roundDepthToUnits(DepthImage& depth, double units_per_m);

/// \brief Back-projects a depth image into the world frame: pixel (u, v) with a finite
/// depth d > 0 gives T_W_O * ((u - cx) / fx * d, (v - cy) / fy * d, d); other pixels
/// give NaN (no return). Computed in double precision, stored as float.
///
/// The camera's range limits are not applied (a depth frame holds what the camera
/// returned); the map's max_range_m decides what becomes a hit.
/// \param[in] T_W_O the optical frame in the world (z forward, x right, y down).
/// \param[out] cloud_W organized width x height; sensor_origin_ / sensor_orientation_
/// set to T_W_O; is_dense false unless every pixel has a return.
/// \throws InvalidArgumentError if the image size differs from the intrinsics' or the
/// image holds fewer values than width x height.
void depthToCloud(const DepthImage& depth, const CameraIntrinsics& intrinsics,
                  const Pose& T_W_O, CloudXYZ& cloud_W);

} // namespace plantnbv
