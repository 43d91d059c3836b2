#include <plantnbv/common/error.h>
#include <plantnbv/sensor/simulated_depth_grabber.h>

namespace plantnbv {

SimulatedDepthGrabber::SimulatedDepthGrabber(SimulatedDepthSensor::Ptr sensor)
    : sensor_(std::move(sensor))
{
  if (!sensor_)
    throw InvalidArgumentError("SimulatedDepthGrabber: the sensor is null");
  cloud_signal_ = createSignal<CloudCallback>();
  cloud_depth_signal_ = createSignal<CloudDepthCallback>();
}

bool SimulatedDepthGrabber::trigger()
{
  const bool want_cloud = cloud_signal_->num_slots() > 0;
  const bool want_depth = cloud_depth_signal_->num_slots() > 0;
  if (!want_cloud && !want_depth)
    return false;
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZL>>();
  std::shared_ptr<DepthImage> depth =
      want_depth ? std::make_shared<DepthImage>() : nullptr;
  sensor_->capture(pose_, *cloud, depth.get());
  const pcl::PointCloud<pcl::PointXYZL>::ConstPtr const_cloud = cloud;
  if (want_cloud)
    (*cloud_signal_)(const_cloud);
  if (want_depth)
    (*cloud_depth_signal_)(const_cloud, std::shared_ptr<const DepthImage>(depth));
  return true;
}

} // namespace plantnbv
