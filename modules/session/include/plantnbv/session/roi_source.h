#pragma once
/// \file roi_source.h
/// \brief Where the planner's attention ROI comes from (the paper, section 5.3: on a
/// robot nobody knows the true boxes). `oracle` attends to the boxes it is given (a
/// plant's true ROIs in a trial, an ROI file on a robot); `noisy` displaces each of them
/// by a seeded Gaussian error, to measure what an ROI misplaced by a detector costs;
/// `detections` attends to what a detector finds, fused frame after frame
/// (DetectionFusion; in a trial the detector is SimulatedDetector, of the quality given
/// here); `prior` to leaf nodes predicted one internode apart along the stem seen in the
/// map (LeafNodePrior); `detections+prior` to both, the prediction anchored on the
/// detected nodes.

#include <cstdint>
#include <string>

#include <plantnbv/common/box.h>
#include <plantnbv/session/leaf_node_prior.h>

namespace plantnbv {

/// \brief The kinds of ROI source.
enum class RoiSourceKind {
  oracle,     ///< the given boxes as they are (the paper's study)
  noisy,      ///< the given boxes, each moved by N(0, sigma^2) per axis and scaled
  detections, ///< the 3D boxes of detections fused over the frames (DetectionFusion)
  prior, ///< leaf-node boxes predicted along the stem seen in the map (LeafNodePrior)
  detections_prior, ///< the detections' boxes and the prior's, anchored on them
};
/// \brief "oracle", "noisy", "detections", "prior" or "detections+prior" (the names
/// configs, campaigns and the CLI use).
const char* roiSourceKindName(RoiSourceKind kind);
/// \throws InvalidArgumentError naming the string and the accepted names.
RoiSourceKind roiSourceKindFromName(const std::string& name);

/// \brief An ROI source and its parameters (trial configs: `roi_source`, `roi_sigma`,
/// `roi_scale`; docs/trials.md).
struct RoiSource {
  RoiSourceKind kind = RoiSourceKind::oracle; ///< oracle (the default), noisy, detections
  /// noisy: the standard deviation of each box centre's error along x, y and z (metres).
  double sigma_m = 0.0;
  /// noisy: the factor on every side of every box (1: the given size).
  double scale = 1.0;
  /// detections, in trials: the simulated detector's recall (SimulatedDetector).
  double detector_recall = 1.0;
  /// detections, in trials: the simulated detector's false positives per frame.
  double detector_false_positives = 0.0;
  /// detections, in trials: the standard deviation of each box edge's error (pixels).
  double detector_box_jitter_px = 0.0;
  /// detections, in trials: the masks grown (> 0) or shrunk (< 0) by this many pixels
  /// (SimulatedDetector::Config::mask_dilation_px), in [-64, 64].
  int detector_mask_dilation_px = 0;
  /// detections, in trials: instance masks (Mask R-CNN-like; the fusion back-projects
  /// them) or, false, boxes only (YOLO-like; the fusion takes the box's nearest depth
  /// cluster), SimulatedDetector::Config::masks. Box jitter moves only boxes, so it
  /// needs false.
  bool detector_masks = true;
  /// prior: the distance between successive leaf nodes along the stem (metres;
  /// LeafNodePrior's default, from the generator's plants).
  double prior_internode_m = 0.04;
  /// detections (alone): while at most this many views have been taken, the NBV planner
  /// explores the whole plant instead of attending to the finds
  /// (AttentionNbvPlanner::setExplorationViews): one view's finds are the nodes it saw,
  /// and the hidden ones are found by showing more of the plant. The prior predicts
  /// those, so detections+prior needs none. 0: attend from the first plan.
  int detections_explore_views = 1;

  /// \brief True for the sources whose ROI follows the frames (detections, prior, both).
  bool followsFrames() const { return detects() || predicts(); }
  /// \brief True for detections and detections+prior.
  bool detects() const
  {
    return kind == RoiSourceKind::detections || kind == RoiSourceKind::detections_prior;
  }
  /// \brief True for prior and detections+prior.
  bool predicts() const
  {
    return kind == RoiSourceKind::prior || kind == RoiSourceKind::detections_prior;
  }

  /// \throws InvalidArgumentError for a negative or non-finite sigma, a scale that is
  /// not finite and positive, a recall outside [0, 1], false positives outside [0, 1000],
  /// exploring views outside [0, 1000], or a value set that the source does not use (a
  /// sigma with the oracle: it would be ignored). The message names the config keys
  /// (`roi_sigma`), or with an `option_prefix` the options ("--" gives `--roi-sigma`).
  void validate(const std::string& option_prefix = "") const;

  /// \brief The views up to which the NBV planner explores:
  /// detections_explore_views for detections, 0 for the other sources.
  int explorationViews() const
  {
    return kind == RoiSourceKind::detections ? detections_explore_views : 0;
  }

  /// \brief The prior's rules: LeafNodePrior's defaults, one internode of
  /// prior_internode_m apart.
  LeafNodePrior::Config priorConfig() const;

  /// \brief The ROI the planner attends to, from the `given` boxes. oracle: `given`
  /// itself. noisy: box i's centre moved by sigma_m times three standard normal draws
  /// (x, y, z, box after box, from Rng(seed)), its sides times `scale`, its name kept.
  /// sigma_m 0 and scale 1 give `given` exactly. The sources that follow the frames: an
  /// empty ROI (nothing is seen before the first frame; DetectionFusion and
  /// LeafNodePrior give the ROI after each).
  /// \throws InvalidArgumentError as validate().
  Roi apply(const Roi& given, std::uint64_t seed) const;
};

} // namespace plantnbv
