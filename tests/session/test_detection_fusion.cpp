// DetectionFusion: 2D detections of hand-made frames land in the right 3D boxes, and
// views of one object fuse into one instance.

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/session/detection_fusion.h>

namespace plantnbv {
namespace {

const CameraIntrinsics kCamera =
    CameraIntrinsics::custom(64, 48, 200.0, 200.0, 31.5, 23.5);

/// A wall at z = 1 m, and in front of it at z = 0.5 m the squares of `objects` (centres
/// x, y; 2 cm sides), seen by a camera at (x, 0, 0) looking along +z (optical frame =
/// world axes). Returns the depth image and, per object, the box of its pixels.
DepthImage scene(double camera_x, const std::vector<Eigen::Vector2d>& objects,
                 std::vector<Detection>* boxes = nullptr)
{
  DepthImage depth;
  depth.width = kCamera.width;
  depth.height = kCamera.height;
  depth.depth_m.assign(kCamera.pixelCount(), 1.0f);
  std::vector<Eigen::Vector4d> bounds(objects.size(), Eigen::Vector4d(1e9, 1e9, -1, -1));
  for (std::uint32_t v = 0; v < depth.height; ++v)
    for (std::uint32_t u = 0; u < depth.width; ++u) {
      const double x = camera_x + (u - kCamera.cx) / kCamera.fx * 0.5;
      const double y = (v - kCamera.cy) / kCamera.fy * 0.5;
      for (std::size_t k = 0; k < objects.size(); ++k)
        if (std::abs(x - objects[k].x()) <= 0.01 &&
            std::abs(y - objects[k].y()) <= 0.01) {
          depth.depth_m[v * depth.width + u] = 0.5f;
          Eigen::Vector4d& b = bounds[k];
          b = Eigen::Vector4d(std::min(b[0], double(u)), std::min(b[1], double(v)),
                              std::max(b[2], u + 1.0), std::max(b[3], v + 1.0));
        }
    }
  if (boxes)
    for (const Eigen::Vector4d& b : bounds) {
      Detection d;
      d.class_name = "leaf_node";
      d.score = 0.9;
      // Grown by 3 pixels: the wall behind is in the box too.
      d.box_px = Eigen::Vector4d(b[0] - 3, b[1] - 3, b[2] + 3, b[3] + 3);
      boxes->push_back(d);
    }
  return depth;
}

Pose cameraAt(double x)
{
  return Pose(Eigen::Vector3d(x, 0.0, 0.0), Eigen::Quaterniond::Identity());
}

TEST(DetectionFusion, ABoxDetectionLandsOnItsObjectNotOnTheWallBehind)
{
  std::vector<Detection> detections;
  const DepthImage depth = scene(0.0, {{0.03, -0.02}}, &detections);
  DetectionFusion fusion;
  fusion.addFrame(detections, depth, kCamera, cameraAt(0.0));
  ASSERT_EQ(fusion.getInstances().size(), 1u);
  const DetectionFusion::Instance& instance = fusion.getInstances()[0];
  EXPECT_EQ(instance.views, 1);
  // Only the object's pixels (the nearest depth cluster): all at z = 0.5, within it.
  EXPECT_DOUBLE_EQ(instance.min_W.z(), 0.5);
  EXPECT_DOUBLE_EQ(instance.max_W.z(), 0.5);
  EXPECT_NEAR(instance.centroid_W.x(), 0.03, 0.5 / kCamera.fx);
  EXPECT_NEAR(instance.centroid_W.y(), -0.02, 0.5 / kCamera.fy);
  EXPECT_GE(instance.min_W.x(), 0.03 - 0.01 - 1e-9);
  EXPECT_LE(instance.max_W.x(), 0.03 + 0.01 + 1e-9);
  // The box: bounds grown by 5 mm, at least the leaf-node box (3 x 3 x 5 cm).
  const Roi roi = fusion.getRoi();
  ASSERT_EQ(roi.size(), 1u);
  const Box& box = roi.boxes()[0];
  EXPECT_EQ(box.name, "leaf_node_0");
  EXPECT_TRUE(box.contains(Eigen::Vector3d(0.03, -0.02, 0.5)));
  EXPECT_DOUBLE_EQ(box.size.z(), 0.05);
  EXPECT_DOUBLE_EQ(box.center.z(), 0.5);
  EXPECT_GE(box.size.x(), instance.max_W.x() - instance.min_W.x() + 0.01 - 1e-12);
}

TEST(DetectionFusion, AMaskThatSpillsOntoTheWallKeepsItsObject)
{
  std::vector<Detection> detections;
  const DepthImage depth = scene(0.0, {{0.0, 0.0}}, &detections);
  Detection& d = detections[0];
  const std::vector<std::uint32_t> box = detectionPixels(d, depth.width, depth.height);
  d.mask.assign(kCamera.pixelCount(), 0);
  std::size_t object = 0;
  for (std::uint32_t i : box) {
    d.mask[i] = depth.depth_m[i] < 0.75f ? 255 : 0;
    object += d.mask[i] != 0;
  }
  for (std::uint32_t u = 0; u < 6; ++u) // a few wall pixels: fewer than the object's
    d.mask[u] = 1;
  DetectionFusion fusion;
  fusion.addFrame(detections, depth, kCamera, cameraAt(0.0));
  ASSERT_EQ(fusion.getInstances().size(), 1u);
  EXPECT_EQ(fusion.getInstances()[0].points, object);
  EXPECT_DOUBLE_EQ(fusion.getInstances()[0].max_W.z(), 0.5);
}

TEST(DetectionFusion, TwoViewsOfOneObjectFuseIntoOneInstanceAndAnotherStaysApart)
{
  DetectionFusion fusion;
  for (double x : {0.0, 0.02}) {
    std::vector<Detection> detections;
    const DepthImage depth = scene(x, {{0.0, 0.0}, {0.05, 0.03}}, &detections);
    fusion.addFrame(detections, depth, kCamera, cameraAt(x));
  }
  ASSERT_EQ(fusion.getInstances().size(), 2u);
  for (const DetectionFusion::Instance& instance : fusion.getInstances())
    EXPECT_EQ(instance.views, 2);
  EXPECT_NEAR(fusion.getInstances()[0].centroid_W.x(), 0.0, 0.5 / kCamera.fx);
  EXPECT_NEAR(fusion.getInstances()[1].centroid_W.x(), 0.05, 0.5 / kCamera.fx);
  EXPECT_EQ(fusion.getRoi().size(), 2u);
  EXPECT_EQ(fusion.getCounts().frames, 2u);
  EXPECT_EQ(fusion.getCounts().fused, 4u);
}

TEST(DetectionFusion, OtherClassesLowScoresAndEmptyDetectionsAreLeftOutAndCounted)
{
  std::vector<Detection> detections;
  const DepthImage depth =
      scene(0.0, {{0.0, 0.0}, {0.05, 0.0}, {-0.05, 0.0}}, &detections);
  detections[1].class_name = "fruit";
  detections[2].score = 0.2;
  Detection outside; // a box over the image's corner, where the wall is: one cluster,
  outside.class_name = "leaf_node"; // but too few pixels
  outside.box_px = Eigen::Vector4d(0, 0, 2, 2);
  detections.push_back(outside);
  DetectionFusion fusion;
  fusion.addFrame(detections, depth, kCamera, cameraAt(0.0));
  const DetectionFusion::Counts& counts = fusion.getCounts();
  EXPECT_EQ(counts.detections, 4u);
  EXPECT_EQ(counts.other_class, 1u);
  EXPECT_EQ(counts.low_score, 1u);
  EXPECT_EQ(counts.too_few_points, 1u);
  EXPECT_EQ(counts.fused, 1u);
  EXPECT_EQ(fusion.getRoi().size(), 1u);

  // Seen in one frame only: with min_views 2 it waits; nothing found, an empty ROI.
  DetectionFusion::Config config;
  config.min_views = 2;
  DetectionFusion waiting(config);
  waiting.addFrame(detections, depth, kCamera, cameraAt(0.0));
  EXPECT_EQ(waiting.getInstances().size(), 1u);
  EXPECT_TRUE(waiting.getRoi().empty());
  EXPECT_TRUE(DetectionFusion().getRoi().empty());
}

TEST(DetectionFusion, BadRulesAndFramesAreRefused)
{
  DetectionFusion::Config config;
  config.min_score = 1.5;
  EXPECT_THROW(DetectionFusion{config}, InvalidArgumentError);
  config = DetectionFusion::Config();
  config.class_name = "";
  EXPECT_THROW(DetectionFusion{config}, InvalidArgumentError);
  config = DetectionFusion::Config();
  config.min_size_m.x() = 0.0;
  EXPECT_THROW(DetectionFusion{config}, InvalidArgumentError);
  config = DetectionFusion::Config();
  config.association_distance_m = std::nan("");
  EXPECT_THROW(DetectionFusion{config}, InvalidArgumentError);

  DetectionFusion fusion;
  DepthImage small = scene(0.0, {});
  small.width = 32;
  EXPECT_THROW(fusion.addFrame({}, small, kCamera, cameraAt(0.0)), InvalidArgumentError);
  Detection bad;
  bad.class_name = "leaf_node";
  bad.mask.assign(10, 1);
  EXPECT_THROW(fusion.addFrame({bad}, scene(0.0, {}), kCamera, cameraAt(0.0)),
               InvalidArgumentError);
}

} // namespace
} // namespace plantnbv
