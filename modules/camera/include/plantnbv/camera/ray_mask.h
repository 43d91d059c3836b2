#pragma once
/// \file ray_mask.h
/// \brief RayMask: the pixels of a camera whose rays may meet given boxes within a
/// range, so that a sensor casts only those (SimulatedDepthSensor::setRayMask).

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/common/pose.h>

namespace plantnbv {

/// \brief A set of pixels of a camera at one pose: at least every pixel whose ray (from
/// the optical centre through the pixel centre, up to `range_m`) meets one of the boxes
/// added, in cells of 4 x 4 pixels. Conservative: a marked pixel's ray may miss every
/// box, an unmarked one's meets none.
///
/// A trial marks the bricks of its map's update region: a pixel outside the mask would
/// only change voxels that nothing reads, so the sensor need not cast it (Trial, with
/// regionRayMask).
///
/// \code
/// RayMask mask(K, T_W_O, 0.75);
/// mask.addBox(lo_W, hi_W);          // e.g. every brick of an UpdateRegion
/// sensor.setRayMask(std::make_shared<const RayMask>(mask));
/// \endcode
class RayMask {
public:
  static constexpr std::uint32_t kCellPixels = 4; ///< a cell's side (pixels)

  /// \brief No pixel yet, for camera `K` with its optical frame at `T_W_O` (world), rays
  /// `range_m` long. \throws InvalidArgumentError as K.validate(), or if range_m is not
  /// finite and > 0.
  RayMask(const CameraIntrinsics& K, const Pose& T_W_O, double range_m);

  /// \brief Adds at least every pixel whose ray meets the box [lo_W, hi_W] (metres,
  /// world frame): the cells that the projection of the box (grown by a millionth of
  /// the optical centre's largest coordinate, at least 1 um, for rays that start at the
  /// centre rounded to float), its bounding rectangle grown by a pixel for the rays'
  /// directions' rounding, overlaps; of a box that reaches behind the camera, its part
  /// in front. Nothing when the box lies farther than the range or behind the camera (or
  /// has a NaN bound); every pixel when it holds the optical centre or, within range,
  /// reaches infinity.
  void addBox(const double lo_W[3], const double hi_W[3]);
  /// \brief Adds every pixel.
  void addAll();

  /// \brief Whether pixel (u, v) (column, row) is in the mask; false outside the image.
  bool containsPixel(std::uint32_t u, std::uint32_t v) const
  {
    return u < width_ && v < height_ &&
           cells_[static_cast<std::size_t>(v / kCellPixels) * cells_x_ +
                  u / kCellPixels] != 0;
  }
  /// \brief The pixels in the mask.
  std::size_t pixelCount() const;
  /// \brief The image's columns.
  std::uint32_t width() const { return width_; }
  /// \brief The image's rows.
  std::uint32_t height() const { return height_; }

private:
  void addCells(double u_lo, double u_hi, double v_lo, double v_hi);

  std::uint32_t width_, height_;
  double fx_, fy_, cx_, cy_;
  double range_m_;
  double min_ray_z_; ///< the least z of a pixel ray's unit direction (optical frame)
  Eigen::Vector3d origin_W_;
  double origin_slack_m_; ///< boxes grown by it: the float rounding of rays' origins
  Eigen::Matrix3d R_O_W_; ///< world to optical frame
  std::size_t cells_x_, cells_y_;
  std::vector<std::uint8_t> cells_; ///< 1 where the cell is in the mask, rows of cells
};

} // namespace plantnbv
