#pragma once
/// \file detection.h
/// \brief A 2D detection in a depth frame, as YOLO-style (box) and Mask R-CNN-style
/// (box and instance mask) detectors give it, and the rule for its pixels. Files of
/// detections: io/detections_io.h; their fusion into 3D boxes:
/// session/detection_fusion.h.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace plantnbv {

/// \brief One 2D detection of an object in a depth frame.
struct Detection {
  /// The object's class, e.g. "leaf_node", "fruit", "main_stem"; any non-empty string.
  std::string class_name;
  /// The detector's confidence, in [0, 1].
  double score = 1.0;
  /// u0, v0, u1, v1 in pixels: the box's edges, in the continuous image coordinates
  /// where pixel u spans [u, u + 1) (COCO, Detectron2, YOLO in pixels); 0 <= u0 <= u1 <=
  /// width, 0 <= v0 <= v1 <= height. Pixel (u, v) is in the box when its centre is:
  /// u0 <= u + 0.5 <= u1 and v0 <= v + 0.5 <= v1.
  Eigen::Vector4d box_px{0.0, 0.0, 0.0, 0.0};
  /// The instance mask: empty (none), or width * height bytes, row-major (v * width +
  /// u), non-zero = the instance's pixels.
  std::vector<std::uint8_t> mask;
};

/// \brief The most pixels a simulated segmenter's masks grow or shrink by
/// (SimulatedDetector::Config::mask_dilation_px, RoiSource::detector_mask_dilation_px):
/// beyond it a leaf node's mask is mostly background or gone.
constexpr int kMaxMaskDilationPx = 64;

/// \brief The pixels of a detection: its mask's non-zero pixels when it has a mask (the
/// box is not applied to them), else the pixels whose centres lie in its box (u0 <= u +
/// 0.5 <= u1, v0 <= v + 0.5 <= v1), the box clipped to the image.
/// \param[in] d the detection
/// \param[in] width the image's width, pixels
/// \param[in] height the image's height, pixels
/// \return row-major pixel indices v * width + u, ascending.
/// \throws InvalidArgumentError if the mask is neither empty nor width * height bytes, or
/// the box has a non-finite number. Thread-safe.
std::vector<std::uint32_t> detectionPixels(const Detection& d, std::uint32_t width,
                                           std::uint32_t height);

} // namespace plantnbv
