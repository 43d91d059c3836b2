#pragma once
/// \file simulated_detector.h
/// \brief SimulatedDetector: the 2D detections a detector of known quality would give on
/// a simulated frame, made from ground truth, so that campaigns can sweep detector
/// quality and `reconstruct --frames-out` writes what a real detector would
/// (io/detections_io.h).
///
/// One true instance per box of the truth ROI (e.g. leafNodeRoi: a box around each leaf
/// node). Its pixels: those whose surface point lies in the box and belongs to the plant
/// (a label from stem to fruit; not the floor or the support). Seen by fewer than
/// min_pixels pixels, it is not detected. Otherwise it is detected with probability
/// `recall` (score uniform in [0.5, 1]), with its pixels as mask (or none) and their
/// bounds as box, each box edge moved by N(0, box_jitter_px^2) and clipped to the image.
/// With mask_dilation_px n != 0 its pixels are first grown (n > 0: every pixel within n
/// pixels, in both image directions, of one of them) or shrunk (n < 0: those whose
/// whole (2|n| + 1)^2 square is theirs), as a segmenter's masks overshoot into the
/// background or miss thin parts; the box follows, and an instance shrunk to nothing is
/// missed.
/// `false_positives` per frame on average (the whole part, and one more with the
/// fraction's probability) are boxes of 8-48 px sides at uniform positions, scores
/// uniform in [0.5, 1], their masks (if masks are on) the whole box. The draws of frame i
/// come from deriveSeed(seed, i): the same frames give the same detections.

#include <cstdint>
#include <string>
#include <vector>

#include <plantnbv/camera/detection.h>
#include <plantnbv/common/box.h>
#include <plantnbv/common/pcl_fwd.h>

namespace plantnbv {

/// \brief Detections from ground truth, with seeded misses, false positives and box
/// errors.
///
/// \code
/// SimulatedDetector detector(config);                 // class, recall, ...
/// std::vector<Detection> detections;
/// detector.detect(frame_W, leafNodeRoi(plant), view_index, detections);
/// \endcode
class SimulatedDetector {
public:
  /// \brief The detector's quality. Defaults: a perfect leaf-node detector with masks.
  struct Config {
    std::string class_name = "leaf_node"; ///< the class its detections carry
    double recall = 1.0;          ///< probability that a visible instance is detected
    double false_positives = 0.0; ///< per frame, on average, >= 0
    double box_jitter_px = 0.0;   ///< standard deviation of each box edge's error
    int mask_dilation_px = 0; ///< grow (> 0) or shrink (< 0) the true pixels, |n| <= 64
    bool masks = true; ///< instance masks (Mask R-CNN-like) or boxes only (YOLO-like)
    std::size_t min_pixels = 10; ///< fewer visible pixels: not detected
    std::uint64_t seed = 0;      ///< frame i draws from deriveSeed(seed, i)

    /// \throws InvalidArgumentError naming the first bad field (an empty class, recall
    /// outside [0, 1], false positives or jitter negative or not finite, false
    /// positives over 1000 per frame, or a dilation beyond 64 pixels either way).
    void validate() const;
  };

  /// \brief A perfect leaf-node detector.
  SimulatedDetector() = default;
  /// \throws InvalidArgumentError as Config::validate.
  explicit SimulatedDetector(const Config& config);

  /// \brief Replaces the quality. \throws InvalidArgumentError as Config::validate.
  void setConfig(const Config& config);
  /// \brief The quality.
  const Config& getConfig() const { return config_; }

  /// \brief The detections of one frame.
  /// \param[in] frame_W the frame: an organized labelled cloud in the world frame, as
  /// SimulatedDepthSensor::capture gives it (NaN points: no return)
  /// \param[in] truth the true objects, one box each
  /// \param[in] frame_index which frame (its draws)
  /// \param[out] out the detections: the true ones in the order of `truth`, then the
  /// false positives
  /// \throws InvalidArgumentError if the cloud is not organized (height 1 with width 1
  /// is allowed).
  void detect(const CloudXYZL& frame_W, const Roi& truth, std::uint64_t frame_index,
              std::vector<Detection>& out) const;

private:
  Config config_;
};

} // namespace plantnbv
