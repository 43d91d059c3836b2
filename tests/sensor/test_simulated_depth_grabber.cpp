#include <cmath>
#include <functional>
#include <memory>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/sensor/simulated_depth_grabber.h>

#include "sensor_test_util.h"

using namespace plantnbv;

TEST(SimulatedDepthGrabber, EmitsOneFramePerTrigger)
{
  auto scene = std::make_shared<SensorScene>();
  scene->addMesh(test::makeQuad(Eigen::Vector3d(1.5, 0, 0), Eigen::Vector3d::UnitY(),
                                Eigen::Vector3d::UnitZ(), 3.0, PartLabel::stem));
  scene->commit();
  const CameraIntrinsics K = test::smallCamera();
  auto sensor = std::make_shared<SimulatedDepthSensor>(K);
  sensor->setScene(scene);
  SimulatedDepthGrabber grabber(sensor);
  EXPECT_EQ(grabber.getName(), "SimulatedDepthGrabber");
  EXPECT_EQ(grabber.getFramesPerSecond(), 0.0f);
  EXPECT_FALSE(grabber.isRunning());
  EXPECT_TRUE(grabber.providesCallback<SimulatedDepthGrabber::CloudCallback>());
  EXPECT_TRUE(grabber.providesCallback<SimulatedDepthGrabber::CloudDepthCallback>());
  EXPECT_FALSE(grabber.trigger()); // nobody listens: nothing rendered
  EXPECT_EQ(sensor->getFrameIndex(), 0u);

  int clouds = 0, pairs = 0;
  float centre_x = 0.0f, centre_depth = 0.0f;
  std::function<SimulatedDepthGrabber::CloudCallback> on_cloud =
      [&](const pcl::PointCloud<pcl::PointXYZL>::ConstPtr& cloud) {
        ++clouds;
        ASSERT_EQ(cloud->width, K.width);
        ASSERT_EQ(cloud->height, K.height);
        centre_x = cloud->at(32, 24).x;
        EXPECT_EQ(cloud->at(32, 24).label, std::uint32_t(PartLabel::stem));
      };
  std::function<SimulatedDepthGrabber::CloudDepthCallback> on_pair =
      [&](const pcl::PointCloud<pcl::PointXYZL>::ConstPtr& cloud,
          const std::shared_ptr<const DepthImage>& depth) {
        ++pairs;
        ASSERT_TRUE(depth);
        ASSERT_EQ(depth->depth_m.size(), cloud->size());
        centre_depth = depth->at(32, 24);
      };
  boost::signals2::connection c1 = grabber.registerCallback(on_cloud);
  grabber.registerCallback(on_pair);

  // Moving the pose moves the next frame: 1 m back, the wall is 2.5 m away.
  grabber.setPose(Pose(Eigen::Vector3d(-1.0, 0, 0), Eigen::Quaterniond::Identity()));
  grabber.start();
  EXPECT_EQ(clouds, 1);
  EXPECT_EQ(pairs, 1);
  EXPECT_NEAR(centre_x, 1.5f, 1e-6f);
  EXPECT_NEAR(centre_depth, 2.5f, 1e-5f);
  grabber.stop(); // no effect for a triggered grabber
  EXPECT_TRUE(grabber.trigger());
  EXPECT_EQ(clouds, 2);
  EXPECT_EQ(pairs, 2);
  EXPECT_EQ(sensor->getFrameIndex(), 2u);

  c1.disconnect();
  grabber.trigger();
  EXPECT_EQ(clouds, 2);
  EXPECT_EQ(pairs, 3);

  EXPECT_THROW(SimulatedDepthGrabber(nullptr), InvalidArgumentError);
}
