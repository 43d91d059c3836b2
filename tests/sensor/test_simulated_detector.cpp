// SimulatedDetector: detections from ground truth, with seeded misses, false positives
// and box errors.

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/triangle_mesh.h>
#include <plantnbv/sensor/simulated_detector.h>

namespace plantnbv {
namespace {

/// A 40 x 30 frame: the floor (background) everywhere at z = 0, the stem (label stem) in
/// columns 10-13, rows 5-24 at x = u / 100, z = 1 - v / 100, and no return in column 39.
CloudXYZL frame()
{
  CloudXYZL cloud;
  cloud.width = 40;
  cloud.height = 30;
  cloud.points.resize(40 * 30);
  for (std::uint32_t v = 0; v < 30; ++v)
    for (std::uint32_t u = 0; u < 40; ++u) {
      pcl::PointXYZL& p = cloud.points[v * 40 + u];
      p.x = float(u) / 100.0f;
      p.y = 0.0f;
      p.z = 0.0f;
      p.label = std::uint32_t(PartLabel::background);
      if (u >= 10 && u <= 13 && v >= 5 && v <= 24) {
        p.z = 1.0f - float(v) / 100.0f;
        p.label = std::uint32_t(PartLabel::stem);
      }
      if (u == 39) {
        p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
        p.label = 0;
      }
    }
  return cloud;
}

/// A node box around rows 8-12 of the stem (z 0.88-0.92) that also holds floor points.
Roi node()
{
  return Roi(
      {Box::fromMinMax({0.095, -0.01, -0.01}, {0.135, 0.01, 0.925}, "leaf_node_0")});
}

TEST(SimulatedDetector, APerfectDetectorFindsTheVisibleInstanceWithItsPixels)
{
  SimulatedDetector detector;
  std::vector<Detection> out;
  detector.detect(frame(), node(), 0, out);
  ASSERT_EQ(out.size(), 1u);
  const Detection& d = out[0];
  EXPECT_EQ(d.class_name, "leaf_node");
  EXPECT_GE(d.score, 0.5);
  EXPECT_LE(d.score, 1.0);
  // The stem's pixels in the box: columns 10-13, rows 8-24 (z <= 0.92); the floor's
  // pixels in the box are not the plant's.
  EXPECT_EQ(d.box_px, Eigen::Vector4d(10, 8, 14, 25));
  ASSERT_EQ(d.mask.size(), 40u * 30u);
  std::size_t on = 0;
  for (std::uint32_t v = 0; v < 30; ++v)
    for (std::uint32_t u = 0; u < 40; ++u) {
      const bool stem = u >= 10 && u <= 13 && v >= 8 && v <= 24;
      EXPECT_EQ(d.mask[v * 40 + u] != 0, stem) << u << "," << v;
      on += d.mask[v * 40 + u] != 0;
    }
  EXPECT_EQ(on, 4u * 17u);
  // Boxes only: no mask.
  SimulatedDetector::Config config;
  config.masks = false;
  SimulatedDetector boxes(config);
  boxes.detect(frame(), node(), 0, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0].mask.empty());
  EXPECT_EQ(out[0].box_px, Eigen::Vector4d(10, 8, 14, 25));
  // Fewer visible pixels than min_pixels: not detected.
  config.min_pixels = 69;
  boxes.setConfig(config);
  boxes.detect(frame(), node(), 0, out);
  EXPECT_TRUE(out.empty());
}

// Masks grown or shrunk by a square (a segmenter's overshoot or undershoot): the stem's
// 4 x 17 pixels in the node box, grown by 2 into the floor around them, shrunk by 1 to
// their inside, shrunk by 2 to nothing (missed); the box follows the mask.
TEST(SimulatedDetector, MasksGrowAndShrinkAndTheBoxFollows)
{
  const auto detect = [](int dilation, bool masks) {
    SimulatedDetector::Config config;
    config.mask_dilation_px = dilation;
    config.masks = masks;
    std::vector<Detection> out;
    SimulatedDetector(config).detect(frame(), node(), 0, out);
    return out;
  };
  const auto maskIs = [](const Detection& d, int u0, int v0, int u1, int v1) {
    std::size_t wrong = 0;
    for (int v = 0; v < 30; ++v)
      for (int u = 0; u < 40; ++u)
        wrong += (d.mask[std::size_t(v) * 40 + u] != 0) !=
                 (u >= u0 && u <= u1 && v >= v0 && v <= v1);
    return wrong;
  };
  std::vector<Detection> grown = detect(2, true);
  ASSERT_EQ(grown.size(), 1u);
  EXPECT_EQ(grown[0].box_px, Eigen::Vector4d(8, 6, 16, 27));
  EXPECT_EQ(maskIs(grown[0], 8, 6, 15, 26), 0u);
  const std::vector<Detection> shrunk = detect(-1, true);
  ASSERT_EQ(shrunk.size(), 1u);
  EXPECT_EQ(shrunk[0].box_px, Eigen::Vector4d(11, 9, 13, 24));
  EXPECT_EQ(maskIs(shrunk[0], 11, 9, 12, 23), 0u);
  EXPECT_TRUE(detect(-2, true).empty()); // 4 columns: nothing survives a 5 x 5 square
  // Boxes only: the box still follows; the score is the same draw as without.
  const std::vector<Detection> boxes = detect(2, false);
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_TRUE(boxes[0].mask.empty());
  EXPECT_EQ(boxes[0].box_px, grown[0].box_px);
  EXPECT_EQ(boxes[0].score, detect(0, true)[0].score);
  // At the image's edge a grown mask is clipped: a node box over the whole stem's
  // columns, grown by 64, covers the image but for nothing.
  std::vector<Detection> huge = detect(64, true);
  ASSERT_EQ(huge.size(), 1u);
  EXPECT_EQ(huge[0].box_px, Eigen::Vector4d(0, 0, 40, 30));
  EXPECT_EQ(maskIs(huge[0], 0, 0, 39, 29), 0u);
}

TEST(SimulatedDetector, MissesFalsePositivesAndJitterAreSeededPerFrame)
{
  SimulatedDetector::Config config;
  config.recall = 0.0;
  std::vector<Detection> out;
  SimulatedDetector(config).detect(frame(), node(), 0, out);
  EXPECT_TRUE(out.empty());

  config.recall = 1.0;
  config.false_positives = 2.0;
  config.box_jitter_px = 1.5;
  config.seed = 4;
  const SimulatedDetector detector(config);
  std::vector<Detection> again, other;
  detector.detect(frame(), node(), 3, out);
  detector.detect(frame(), node(), 3, again);
  detector.detect(frame(), node(), 4, other);
  ASSERT_EQ(out.size(), 3u); // the instance, then 2 false positives
  ASSERT_EQ(again.size(), 3u);
  ASSERT_EQ(other.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(out[k].box_px, again[k].box_px);
    EXPECT_EQ(out[k].score, again[k].score);
    EXPECT_NE(out[k].box_px, other[k].box_px);
    const Eigen::Vector4d& b = out[k].box_px;
    EXPECT_TRUE(b[0] >= 0 && b[0] <= b[2] && b[2] <= 40 && b[1] >= 0 && b[1] <= b[3] &&
                b[3] <= 30)
        << b.transpose();
    EXPECT_EQ(out[k].class_name, "leaf_node");
  }
  EXPECT_NE(out[0].box_px, Eigen::Vector4d(10, 8, 14, 25)); // jittered
  EXPECT_LT((out[0].box_px - Eigen::Vector4d(10, 8, 14, 25)).cwiseAbs().maxCoeff(), 8.0);
  // A false positive's mask is its box.
  EXPECT_EQ(out[1].mask.size(), 40u * 30u);
  Detection box_only = out[1];
  box_only.mask.clear();
  std::size_t on = 0;
  for (std::uint8_t m : out[1].mask)
    on += m != 0;
  EXPECT_EQ(on, detectionPixels(box_only, 40, 30).size());

  // 0.5 false positives per frame: about half of the frames have one.
  config.false_positives = 0.5;
  config.box_jitter_px = 0.0;
  const SimulatedDetector half(config);
  int with_one = 0;
  for (std::uint64_t i = 0; i < 400; ++i) {
    half.detect(frame(), node(), i, out);
    ASSERT_GE(out.size(), 1u);
    ASSERT_LE(out.size(), 2u);
    with_one += out.size() == 2;
  }
  EXPECT_NEAR(with_one, 200, 40);
}

TEST(SimulatedDetector, BadQualityAndUnorganizedFramesAreRefused)
{
  SimulatedDetector::Config config;
  config.recall = 1.2;
  EXPECT_THROW(SimulatedDetector{config}, InvalidArgumentError);
  config = SimulatedDetector::Config();
  config.false_positives = -1.0;
  EXPECT_THROW(SimulatedDetector{config}, InvalidArgumentError);
  config = SimulatedDetector::Config();
  config.box_jitter_px = std::numeric_limits<double>::infinity();
  EXPECT_THROW(SimulatedDetector{config}, InvalidArgumentError);
  config = SimulatedDetector::Config();
  config.mask_dilation_px = -65;
  EXPECT_THROW(SimulatedDetector{config}, InvalidArgumentError);
  config = SimulatedDetector::Config();
  config.class_name = "";
  EXPECT_THROW(SimulatedDetector{config}, InvalidArgumentError);
  CloudXYZL flat = frame();
  flat.width = 7;
  std::vector<Detection> out;
  EXPECT_THROW(SimulatedDetector().detect(flat, node(), 0, out), InvalidArgumentError);
}

} // namespace
} // namespace plantnbv
