#pragma once
/// \file simulated_depth_sensor.h
/// \brief A simulated depth camera (the paper's RealSense L515, section 4.1): renders a
/// SensorScene from a pose with Embree packet ray casting and returns an organized,
/// labelled point cloud in the world frame, and optionally the depth image.

#include <cstdint>
#include <memory>
#include <vector>

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/camera/depth_image.h>
#include <plantnbv/camera/optical_frame.h>
#include <plantnbv/camera/ray_mask.h>
#include <plantnbv/common/pcl_fwd.h>
#include <plantnbv/common/pose.h>
#include <plantnbv/sensor/noise_model.h>
#include <plantnbv/sensor/sensor_scene.h>

namespace plantnbv {

/// \brief The simulated depth sensor: a PCL-style source of organized labelled clouds.
///
/// \code
/// SimulatedDepthSensor sensor(CameraIntrinsics::l515(L515Mode::vga_640x480));
/// sensor.setScene(makePlantScene(plant));
/// CloudXYZL cloud;
/// sensor.capture(Pose::fromXyzQuat(0.646, 0.353, 1.383, 0, 0, -0.383, 0.924), cloud);
/// \endcode
///
/// Each pixel casts one ray from the optical centre (the pose's position) through the
/// pixel centre (camera_intrinsics.h gives the image convention); the first surface it
/// meets, from either side, is the return. A pixel gives a point (x, y, z in the world
/// frame, label of the surface hit) when that surface is at a range r with
/// min_range_m <= r <= max_range_m (r along the ray, as a time-of-flight sensor measures
/// it); otherwise (no surface, or nearer than min_range_m, or beyond max_range_m) the
/// point is NaN (x = y = z = NaN, label 0) and the depth is NaN. A surface nearer than
/// min_range_m still hides what lies behind it.
///
/// Beyond the far limit: a real sensor returns nothing there, and neither does the
/// cloud. A map that wants OctoMap's treatment of far points (free space up to the
/// maximum range along such rays, insertPointCloud with maxrange) asks capture() for
/// `far_points_W`: one point per pixel whose first surface lies beyond max_range_m,
/// placed at exactly max_range_m along that pixel's ray. Insert them as free space only,
/// from the origin up to (not including) the point, never as hits. Pixels whose ray meets
/// no surface at all give nothing (neither a point nor a far point). For the paper's
/// setup the sensor's range (9 m) exceeds the map's (0.75 m), so the floor and the
/// support give ordinary points beyond the map's range, which insertPointCloud with
/// maxrange 0.75 already carves as free space; far_points_W matter when the sensor's
/// max_range_m is set to the map's.
///
/// Rays are traced as 4 x 4 packets (rtcIntersect16) over image tiles, in parallel with
/// OpenMP. Noise (noise_model.h) is off by default. Results are bit-identical for any
/// thread count, run after run.
///
/// Thread safety: capture() reuses buffers of the sensor: do not call it on the same
/// sensor from several threads at once; several sensors sharing one committed scene may
/// capture concurrently.
class SimulatedDepthSensor {
public:
  using Ptr = std::shared_ptr<SimulatedDepthSensor>; ///< shared sensor

  /// \brief A sensor with the L515 at 1024 x 768, no scene yet.
  SimulatedDepthSensor();
  /// \throws InvalidArgumentError as CameraIntrinsics::validate().
  explicit SimulatedDepthSensor(const CameraIntrinsics& intrinsics);
  ~SimulatedDepthSensor();
  /// \brief Moves the settings, the scene pointer and the capture buffers.
  SimulatedDepthSensor(SimulatedDepthSensor&&) noexcept;
  /// \brief Moves the settings, the scene pointer and the capture buffers.
  SimulatedDepthSensor& operator=(SimulatedDepthSensor&&) noexcept;

  /// \brief The scene to render. \throws InvalidArgumentError if it is null or not
  /// committed (SensorScene::commit()).
  void setScene(SensorScene::ConstPtr scene);
  /// \brief The scene rendered, or null before setScene().
  const SensorScene::ConstPtr& getScene() const { return scene_; }

  /// \throws InvalidArgumentError as CameraIntrinsics::validate().
  void setIntrinsics(const CameraIntrinsics& intrinsics);
  /// \brief The camera's pinhole model and range limits.
  const CameraIntrinsics& getIntrinsics() const { return intrinsics_; }

  /// \brief Sets the noise model and restarts its frame count at 0.
  /// \throws InvalidArgumentError as NoiseConfig::validate().
  void setNoise(const NoiseConfig& noise);
  /// \brief The noise model (off by default).
  const NoiseConfig& getNoise() const { return noise_; }
  /// \brief The index of the next frame's noise stream (frames since setNoise(), or as
  /// set here); the n-th capture draws from deriveSeed(noise.seed, n).
  void setFrameIndex(std::uint64_t index) { frame_index_ = index; }
  /// \brief The index of the next frame's noise stream.
  std::uint64_t getFrameIndex() const { return frame_index_; }

  /// \brief OpenMP threads for capture(); 0 (default) uses omp_get_max_threads().
  /// Results do not depend on it.
  void setNumberOfThreads(unsigned int threads) { threads_ = threads; }
  /// \brief OpenMP threads for capture(); 0 = omp_get_max_threads().
  unsigned int getNumberOfThreads() const { return threads_; }

  /// \brief Casts only the pixels of `mask` (null, the default: every pixel); the others
  /// give no return (a NaN point and depth, no far point), as if their rays met nothing,
  /// and with noise count as such in their neighbours' edge test. A mask is made for
  /// one pose: set it for the capture it was made for (Trial does, frame by frame).
  /// \throws InvalidArgumentError if its image size is not the camera's.
  void setRayMask(std::shared_ptr<const RayMask> mask);
  /// \brief The mask of the next capture, or null.
  const std::shared_ptr<const RayMask>& getRayMask() const { return ray_mask_; }

  /// \brief Renders the scene from the camera body pose T_W_C (x forward, y left, z up).
  /// \param[in] T_W_C the camera body frame in the world (a Viewpoint).
  /// \param[out] cloud organized width x height, world frame, NaN where there is no
  /// return (see the class comment); header.frame_id "world", header.seq the frame index;
  /// is_dense is true only if every pixel has a return.
  /// \param[out] depth if not null, the depth image of the same pixels.
  /// \param[out] far_points_W if not null, cleared and filled with the far points
  /// (unorganized, in pixel order; see the class comment).
  /// \throws Error if no scene is set or the scene is no longer committed;
  /// InvalidArgumentError if the ray mask's image size is not the camera's.
  void capture(const Pose& T_W_C, CloudXYZL& cloud, DepthImage* depth = nullptr,
               CloudXYZ* far_points_W = nullptr);

private:
  struct Buffers;
  SensorScene::ConstPtr scene_;
  CameraIntrinsics intrinsics_;
  std::shared_ptr<const RayMask> ray_mask_;
  NoiseConfig noise_;
  std::uint64_t frame_index_ = 0;
  unsigned int threads_ = 0;
  std::unique_ptr<Buffers> buffers_;
};

} // namespace plantnbv
