#pragma once
/// \file camera_intrinsics.h
/// \brief Pinhole intrinsics of the simulated depth sensor and the Intel RealSense L515
/// presets.
///
/// Image convention (OpenCV's): pixel (u, v) is column u (0 at the left) and row v (0 at
/// the top); pixel centres are at integer coordinates, so the ray of pixel (u, v) passes
/// through the normalised image point ((u - cx) / fx, (v - cy) / fy, 1) of the optical
/// frame (z forward, x right, y down). A centred principal point is therefore at
/// ((width - 1) / 2, (height - 1) / 2). Organised clouds store pixel (u, v) at index
/// v * width + u, as pcl::PointCloud::at(u, v) reads it.

#include <cstddef>
#include <cstdint>
#include <string>

namespace plantnbv {

/// \brief The depth modes of the L515 that the presets model.
enum class L515Mode {
  xga_1024x768, ///< 1024 x 768 (the L515's full depth resolution)
  vga_640x480,  ///< 640 x 480
  qvga_320x240, ///< 320 x 240
};

/// \brief Pinhole intrinsics (no distortion) and the range limits of the sensor.
///
/// A value type; validate() checks it and the sensor's setter calls it.
struct CameraIntrinsics {
  std::uint32_t width = 0;  ///< image columns (pixels), in [1, 16384]
  std::uint32_t height = 0; ///< image rows (pixels), in [1, 16384]
  double fx = 0.0;          ///< focal length along u (pixels), > 0
  double fy = 0.0;          ///< focal length along v (pixels), > 0
  double cx = 0.0;          ///< principal point, column (pixels), finite
  double cy = 0.0;          ///< principal point, row (pixels), finite
  /// Shortest range that gives a return (metres, along the ray, from the optical
  /// centre). Default 0.25 m, the L515's minimum range. In [0, max_range_m).
  double min_range_m = 0.25;
  /// Longest range that gives a return (metres, along the ray). Default 9 m, the L515's
  /// maximum range. Finite, > min_range_m.
  double max_range_m = 9.0;

  /// \brief The L515 in `mode`, square pixels, centred principal point, range 0.25-9 m.
  ///
  /// From the Intel RealSense LiDAR Camera L515 datasheet (rev. 003, January 2021):
  /// depth field of view 70 deg x 55 deg (+-2 deg), depth resolution up to 1024 x 768
  /// (also 640 x 480 and 320 x 240), range 0.25 m to 9 m. The focal length gives the
  /// datasheet's 70 deg horizontally, fx = fy = (width / 2) / tan(35 deg) (731.2 px at
  /// 1024 x 768, 457.0 px at 640 x 480); with square pixels the vertical field of view
  /// is then 55.4 deg, within the datasheet's tolerance of 55 deg.
  static CameraIntrinsics l515(L515Mode mode = L515Mode::xga_1024x768);

  /// \brief A custom pinhole camera; range limits as the defaults (0.25 m, 9 m).
  /// \throws InvalidArgumentError as validate().
  static CameraIntrinsics custom(std::uint32_t width, std::uint32_t height, double fx,
                                 double fy, double cx, double cy);

  /// \brief Horizontal field of view (rad), edge to edge of the image (pixel borders at
  /// u = -0.5 and u = width - 0.5).
  double horizontalFov() const;
  /// \brief Vertical field of view (rad), edge to edge of the image (pixel borders at
  /// v = -0.5 and v = height - 0.5).
  double verticalFov() const;
  /// \brief width x height.
  std::size_t pixelCount() const { return std::size_t(width) * height; }

  /// \brief Checks every field. \throws InvalidArgumentError naming the first bad field
  /// and its value.
  void validate() const;
  /// \brief "WxH fx=.. fy=.. cx=.. cy=.. range=[min, max] m", for logs.
  std::string toString() const;
};

/// \brief Intrinsics from a command-line string:
///  - "l515" or "l515-1024": the L515 at 1024 x 768; "l515-640": 640 x 480;
///    "l515-320": 320 x 240 (case-insensitive);
///  - "WxH:fx,fy,cx,cy", e.g. "640x480:457,457,319.5,239.5": a custom camera with the
///    default range limits (0.25 m, 9 m).
/// \throws InvalidArgumentError naming the string and the expected forms when it is
/// neither, or naming the bad value when a custom camera is invalid.
CameraIntrinsics parseCameraIntrinsics(const std::string& spec);

} // namespace plantnbv
