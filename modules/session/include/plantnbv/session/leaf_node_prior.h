#pragma once
/// \file leaf_node_prior.h
/// \brief LeafNodePrior: the `prior` ROI source. Leaf nodes recur along the main stem
/// (the paper, section 5.3: prediction "from prior knowledge of how the plant grows"),
/// so boxes are predicted one internode apart along the stem, as the map shows it and
/// beyond; detected nodes' boxes are added to them (or, on request, anchor them).
///
/// The rules, each a Config value:
/// - The stem: with stem detections (setStemObservations: the 3D boxes of a detector's
///   main-stem finds, as DetectionFusion or `integrate --roi-out --roi-class main_stem`
///   gives them), each box's centre within the height is a stem point: they find a stem
///   wherever it stands. Without them, the occupied voxels within stem_radius_m of the
///   plant's vertical axis (the sector's axis, which a robot knows as where the plant
///   stands), above its base, cut into slices of slice_m along z; a slice with at least
///   min_slice_points voxels gives a stem point (the median x and y of its voxels, the
///   slice's middle z).
/// - The stem spans the plant's whole height, from the axis's base to its top (below):
///   between stem points it is interpolated, beyond the lowest and the highest it keeps
///   their x and y, and with no stem point it is the axis itself. The parts the map does
///   not show yet, hidden behind leaves, are where attention has to go: predicting only
///   along the seen stem drew the views back to what was seen (docs/results.md, "ROIs
///   predicted from the plant's structure").
/// - The plant's top: the highest occupied voxel within top_radius_m of the axis, below
///   height_m (none: height_m). Above it is air, where no node grows; predicting there
///   drew views to empty space above plants shorter than the sector (0.45-0.70 m plants
///   under a 0.7 m sector). A top that no frame has shown yet is not known: the
///   prediction then ends at the highest part seen and grows as views see more.
/// - The nodes: with anchors (the centres of detected nodes), every anchor within the
///   height grown by one internode is a node, and nodes are predicted from it one
///   internode_m apart up and down, as long as they stay within the height and are
///   more than half an internode from every other node. Without anchors, nodes are
///   predicted from first_node_m above the base, one internode apart, up to the top.
///   predictAround() anchors on the detections only with anchor_on_found: the boxes
///   (5 cm tall, 4 cm apart) then no longer cover the stem without gaps, and the gaps
///   cost (docs/results.md, "ROIs predicted from the plant's structure").
/// - The boxes: box_size_m (the paper's leaf-node box) centred on the stem at each
///   predicted node's height. Anchors get no box here: they have their own (the
///   detections').
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

/// \brief Predicts leaf-node boxes along the main stem, from the part a map shows.
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
    double first_node_m = 0.088; ///< the first node above the plant's base (no anchor)
    double stem_radius_m = 0.03; ///< stem voxels lie this near the plant's axis
    double slice_m = 0.02;       ///< the height of a slice of stem voxels
    std::size_t min_slice_points = 3; ///< fewer voxels: the slice has no stem point
    /// The plant's top is the highest occupied voxel this near the axis (metres, half
    /// the paper's whole-plant box); 0: the given height is the top.
    double top_radius_m = 0.15;
    /// predictAround(): true anchors the prediction on the found boxes' centres; false
    /// (default) predicts as without them and adds them (the file's comment says why).
    bool anchor_on_found = false;
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

  /// \brief Boxes of detected stem parts, world frame (see the file's comment); an
  /// empty Roi (the default) finds the stem among the occupied voxels instead.
  /// \throws InvalidArgumentError for a box that is not finite.
  void setStemObservations(const Roi& stem_W);
  /// \brief The stem detections' boxes (empty: none).
  const Roi& getStemObservations() const { return stem_W_; }

  /// \brief The stem points from bottom to top: the centres of the stem observations'
  /// boxes between the base and height_m above it when there are any, else the median
  /// x, y and middle z of each slice with stem voxels; empty when neither gives one.
  /// \param[in] occupied_W the map's occupied voxel centres, world frame
  /// \param[in] axis_base_W the plant's base on its vertical axis, world frame
  /// \param[in] height_m how far above the base to look (the sector's height)
  std::vector<Eigen::Vector3d> stemPoints(const CloudXYZ& occupied_W,
                                          const Eigen::Vector3d& axis_base_W,
                                          double height_m) const;

  /// \brief The predicted leaf-node boxes from the plant's base to its top, named
  /// "leaf_node_prior_<k>" from the bottom (none for the anchors themselves).
  /// \param[in] occupied_W the map's occupied voxel centres, world frame (may be empty)
  /// \param[in] axis_base_W the plant's base on its vertical axis, world frame
  /// \param[in] height_m how far above the base the plant may reach (the sector's height)
  /// \param[in] anchors_W detected nodes' centres, world frame (may be empty)
  /// \throws InvalidArgumentError for a base that is not finite or a height <= 0.
  Roi predict(const CloudXYZ& occupied_W, const Eigen::Vector3d& axis_base_W,
              double height_m, const std::vector<Eigen::Vector3d>& anchors_W = {}) const;

  /// \brief The plant's top (world z): the highest occupied voxel within top_radius_m
  /// of the axis and below height_m above the base; the base + height_m without one.
  double plantTop(const CloudXYZ& occupied_W, const Eigen::Vector3d& axis_base_W,
                  double height_m) const;

  /// \brief The `detections+prior` ROI: the `found_W` boxes (the detected nodes, as
  /// DetectionFusion or an ROI file gives them) first, then predict()'s boxes, anchored
  /// on their centres with Config::anchor_on_found. With no box found, the prediction
  /// alone (the `prior` source).
  Roi predictAround(const Roi& found_W, const CloudXYZ& occupied_W,
                    const Eigen::Vector3d& axis_base_W, double height_m) const;

private:
  Config config_;
  Roi stem_W_; ///< detected stem parts
};

} // namespace plantnbv
