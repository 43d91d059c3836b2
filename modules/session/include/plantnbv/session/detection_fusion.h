#pragma once
/// \file detection_fusion.h
/// \brief DetectionFusion: the `detections` ROI source. 2D detections of one class,
/// frame after frame, become 3D instances whose boxes are the ROI the planner attends
/// to (the paper, section 5.3: "the algorithm should be able to automatically recognise
/// the ROIs").
///
/// The rules, each a Config value:
/// - A detection of another class, or with a score below min_score, is left out
///   (counted).
/// - Its pixels (camera/detection.h: the mask, else the box) with a depth are
///   back-projected with the frame's pose. A box holds the background too, and a mask
///   may spill over an edge: only the detection's depth cluster is kept, the pixels
///   whose depths, sorted, follow each other by at most depth_gap_m; for a box the
///   nearest cluster (the object in front), for a mask the cluster of its median depth.
///   A detection with fewer than min_points such pixels is left out (counted).
/// - Association: a detection joins the instance whose centroid is nearest to its own
///   points' centroid, if within association_distance_m; else it starts a new instance.
///   An instance's centroid is the mean of all its points; its extent, the bounds of
///   all of them.
/// - The ROI: one box per instance seen in at least min_views frames: its points' bounds
///   grown by margin_m on every side, each side at least min_size_m (centred on the
///   bounds). Instances seen in fewer frames wait (counted); none at all gives an empty
///   ROI, which a planner reads as "every voxel counts": it explores until something is
///   found.
///
/// Deterministic: the same frames in the same order give the same ROI.

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/camera/depth_image.h>
#include <plantnbv/camera/detection.h>
#include <plantnbv/common/box.h>
#include <plantnbv/common/pose.h>

namespace plantnbv {

/// \brief Fuses the 2D detections of one class across frames into 3D boxes.
///
/// \code
/// DetectionFusion fusion;                      // leaf_node, the paper's box size
/// for (each frame)
///   fusion.addFrame(detections, depth, intrinsics, T_W_O);
/// session.setRoi(fusion.getRoi());             // what the planner attends to
/// \endcode
class DetectionFusion {
public:
  /// \brief The rules (see the file's comment). Defaults: leaf nodes, the paper's
  /// leaf-node box (0.03 x 0.03 x 0.05 m) as the smallest box.
  struct Config {
    std::string class_name = "leaf_node"; ///< the class fused; others are left out
    double min_score = 0.5;               ///< detections below it are left out
    /// A detection joins an instance whose centroid is this near (metres).
    double association_distance_m = 0.03;
    double depth_gap_m = 0.01;  ///< the largest step between depths of one cluster
    std::size_t min_points = 5; ///< fewer back-projected pixels: left out
    double margin_m = 0.005;    ///< an instance's bounds grow by this on every side
    /// The smallest box an instance gets (metres): the paper's leaf-node box.
    Eigen::Vector3d min_size_m{0.03, 0.03, 0.05};
    int min_views = 1; ///< frames an instance must be seen in before it is in the ROI

    /// \throws InvalidArgumentError naming the first bad field (an empty class, a score
    /// outside [0, 1], a distance, gap, margin or size not finite and > 0 (margin >= 0),
    /// min_views < 1, min_points < 1).
    void validate() const;
  };

  /// \brief A 3D instance: the detections of one object, fused.
  struct Instance {
    Eigen::Vector3d centroid_W{Eigen::Vector3d::Zero()}; ///< mean of its points
    Eigen::Vector3d min_W{Eigen::Vector3d::Zero()};      ///< its points' lowest corner
    Eigen::Vector3d max_W{Eigen::Vector3d::Zero()};      ///< and highest corner
    std::size_t points = 0;                              ///< back-projected pixels
    int views = 0;           ///< frames with a detection of it
    double best_score = 0.0; ///< the highest score of its detections
  };

  /// \brief What the detections became, summed over the frames added.
  struct Counts {
    std::size_t frames = 0;         ///< frames added
    std::size_t detections = 0;     ///< detections given, every class
    std::size_t other_class = 0;    ///< of another class: left out
    std::size_t low_score = 0;      ///< under min_score: left out
    std::size_t too_few_points = 0; ///< fewer than min_points with a depth: left out
    std::size_t fused = 0;          ///< joined an instance, new or existing
  };

  /// \brief Leaf nodes with the default rules.
  DetectionFusion() = default;
  /// \throws InvalidArgumentError as Config::validate.
  explicit DetectionFusion(const Config& config);

  /// \brief Replaces the rules and forgets every instance. \throws as Config::validate.
  void setConfig(const Config& config);
  /// \brief The rules.
  const Config& getConfig() const { return config_; }

  /// \brief Adds one frame's detections.
  /// \param[in] detections the frame's, of any class
  /// \param[in] depth the frame's depth image (metres; NaN: no return)
  /// \param[in] intrinsics the camera's (its size is the image's)
  /// \param[in] T_W_O the optical frame (z forward, x right, y down) in the world
  /// \throws InvalidArgumentError if the depth image's size is not the camera's, or a
  /// mask's is not (detectionPixels).
  void addFrame(const std::vector<Detection>& detections, const DepthImage& depth,
                const CameraIntrinsics& intrinsics, const Pose& T_W_O);

  /// \brief The instances so far, in the order they were first seen.
  const std::vector<Instance>& getInstances() const { return instances_; }
  /// \brief The ROI: a box per instance seen in at least min_views frames, named
  /// "<class>_<k>" by the instance's index k.
  Roi getRoi() const;
  /// \brief What the detections became.
  const Counts& getCounts() const { return counts_; }

private:
  Config config_;
  std::vector<Instance> instances_;
  std::vector<std::size_t> last_frame_; ///< per instance: the last frame that saw it
  Counts counts_;
};

} // namespace plantnbv
