#pragma once
/// \file simulated_depth_grabber.h
/// \brief A pcl::Grabber in trigger mode around SimulatedDepthSensor, for code written
/// against PCL's grabber interface. Includes <pcl/io/grabber.h> (Boost.Signals2): include
/// it only where a grabber is wanted.

#include <memory>
#include <string>

#include <pcl/io/grabber.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/pose.h>
#include <plantnbv/sensor/simulated_depth_sensor.h>

namespace plantnbv {

/// \brief A triggered pcl::Grabber: every start() (or trigger()) captures one frame at
/// the current pose and emits it to the registered callbacks.
///
/// Signals: `void(const pcl::PointCloud<pcl::PointXYZL>::ConstPtr&)` (the organized
/// cloud, world frame) and `void(const pcl::PointCloud<pcl::PointXYZL>::ConstPtr&, const
/// std::shared_ptr<const DepthImage>&)` (with the depth image; rendered only when a slot
/// is connected).
/// \code
/// SimulatedDepthGrabber grabber(sensor);
/// std::function<SimulatedDepthGrabber::CloudCallback> f = [](const auto& cloud) {...};
/// grabber.registerCallback(f);
/// grabber.setPose(T_W_C);
/// grabber.start(); // one frame
/// \endcode
/// As PCL defines it for triggered devices, stop() does nothing, isRunning() is false and
/// getFramesPerSecond() is 0. Thread safety: as the sensor's capture(): one trigger at a
/// time.
class SimulatedDepthGrabber : public pcl::Grabber {
public:
  /// \brief The signature of a callback that receives each frame's labelled cloud
  /// (organized, world frame).
  using CloudCallback = void(const pcl::PointCloud<pcl::PointXYZL>::ConstPtr&);
  /// \brief The signature of a callback that receives each frame's cloud and its depth
  /// image.
  using CloudDepthCallback = void(const pcl::PointCloud<pcl::PointXYZL>::ConstPtr&,
                                  const std::shared_ptr<const DepthImage>&);

  /// \throws InvalidArgumentError if `sensor` is null.
  explicit SimulatedDepthGrabber(SimulatedDepthSensor::Ptr sensor);

  /// \brief The camera body pose T_W_C of the next frames (identity until set).
  void setPose(const Pose& T_W_C) { pose_ = T_W_C; }
  /// \brief The camera body pose T_W_C of the next frames.
  const Pose& getPose() const { return pose_; }
  /// \brief The sensor that captures the frames.
  const SimulatedDepthSensor::Ptr& getSensor() const { return sensor_; }

  /// \brief Captures one frame and emits it. \return false (and captures nothing) when
  /// no callback is registered. \throws Error as SimulatedDepthSensor::capture().
  bool trigger();

  /// \brief Triggers one frame (PCL's convention for triggered grabbers).
  void start() override { trigger(); }
  /// \brief Does nothing (a triggered grabber has no stream to stop).
  void stop() override {}
  /// \brief Always false: frames come only from start() or trigger().
  bool isRunning() const override { return false; }
  /// \brief "SimulatedDepthGrabber".
  std::string getName() const override { return "SimulatedDepthGrabber"; }
  /// \brief Always 0 (triggered, no frame rate).
  float getFramesPerSecond() const override { return 0.0f; }

private:
  SimulatedDepthSensor::Ptr sensor_;
  Pose pose_;
  boost::signals2::signal<CloudCallback>* cloud_signal_;
  boost::signals2::signal<CloudDepthCallback>* cloud_depth_signal_;
};

} // namespace plantnbv
