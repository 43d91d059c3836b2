#pragma once
/// \file leaf_node_prior.h
/// \brief LeafNodePrior: the `prior` ROI source. Leaf nodes recur along the main stem
/// (the paper, section 5.3: prediction "from prior knowledge of how the plant grows"),
/// so boxes are predicted along the stem seen in the map, one internode apart, anchored
/// on detected nodes when there are any.
///
/// The rules, each a Config value:
/// - The stem: the occupied voxels within stem_radius_m of the plant's vertical axis
///   (the sector's axis, which a robot knows as where the plant stands), above its base,
///   cut into slices of slice_m along z; a slice with at least min_slice_points voxels
///   gives a stem point (the median x and y of its voxels, the slice's middle z). The
///   stem runs from the lowest stem point to the highest. Fewer than two stem points: no
///   stem, no prediction.
/// - The nodes: with anchors (the centres of detected nodes), every anchor on the stem
///   (within the stem's z range grown by one internode) is a node, and nodes are
///   predicted from it one internode_m apart up and down, as long as they stay on the
///   stem and are more than half an internode from every other node. Without anchors,
///   nodes are predicted from first_node_m above the stem's bottom, one internode apart,
///   up to its top.
/// - The boxes: box_size_m (the paper's leaf-node box) centred on the stem at each
///   predicted node's height (the stem points' x, y interpolated along z). Anchors get no
///   box here: they have their own (the detections').
///
/// The defaults come from the anatomy of the generator's default plants (seeds 0-9,
/// docs/plants.md): internodes of 0.040 m on average (median 0.041, sd 0.009; 11-13
/// leaves per plant) and a first node 0.06-0.12 m above the base (mean 0.088).
/// Observations refute nothing explicitly: a predicted box whose voxels are all known
/// has no gain left, so the planner moves on from it by itself.

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include <plantnbv/common/box.h>
#include <plantnbv/common/pcl_fwd.h>

namespace plantnbv {

/// \brief Predicts leaf-node boxes along the main stem seen in a map.
///
/// \code
/// LeafNodePrior prior;                                 // tomato defaults
/// map.getOccupiedVoxelCentres(occupied_W);
/// Roi nodes = prior.predict(occupied_W, sector.axis_base, sector.height_m, anchors_W);
/// \endcode
class LeafNodePrior {
public:
  /// \brief The rules (see the file's comment). Defaults: the generator's tomato plants.
  struct Config {
    double internode_m = 0.04;   ///< the distance between successive leaf nodes
    double first_node_m = 0.088; ///< the first node above the stem's bottom (no anchor)
    double stem_radius_m = 0.03; ///< stem voxels lie this near the plant's axis
    double slice_m = 0.02;       ///< the height of a slice of stem voxels
    std::size_t min_slice_points = 3; ///< fewer voxels: the slice has no stem point
    /// Each predicted node's box (metres): the paper's leaf-node box.
    Eigen::Vector3d box_size_m{0.03, 0.03, 0.05};

    /// \throws InvalidArgumentError naming the first field that is not finite and > 0
    /// (first_node_m >= 0; min_slice_points >= 1).
    void validate() const;
  };

  /// \brief The defaults.
  LeafNodePrior() = default;
  /// \throws InvalidArgumentError as Config::validate.
  explicit LeafNodePrior(const Config& config);
  /// \brief Replaces the rules. \throws InvalidArgumentError as Config::validate.
  void setConfig(const Config& config);
  /// \brief The rules.
  const Config& getConfig() const { return config_; }

  /// \brief The stem points (median x, y and middle z of each slice with stem voxels),
  /// from bottom to top; fewer than two: no stem.
  /// \param[in] occupied_W the map's occupied voxel centres, world frame
  /// \param[in] axis_base_W the plant's base on its vertical axis, world frame
  /// \param[in] height_m how far above the base to look (the sector's height)
  std::vector<Eigen::Vector3d> stemPoints(const CloudXYZ& occupied_W,
                                          const Eigen::Vector3d& axis_base_W,
                                          double height_m) const;

  /// \brief The predicted leaf-node boxes, named "leaf_node_prior_<k>" from the bottom
  /// (none for the anchors themselves); empty when no stem is seen.
  /// \param[in] anchors_W detected nodes' centres, world frame (may be empty)
  Roi predict(const CloudXYZ& occupied_W, const Eigen::Vector3d& axis_base_W,
              double height_m, const std::vector<Eigen::Vector3d>& anchors_W = {}) const;

private:
  Config config_;
};

} // namespace plantnbv
