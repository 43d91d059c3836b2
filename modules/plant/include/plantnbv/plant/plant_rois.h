#pragma once
/// \file plant_rois.h
/// \brief Regions of interest from a plant's anatomy: the paper's attention ROIs (section
/// 3.2, Table 1) and one more for fruit.
///
/// All ROIs are axis-aligned boxes in the plant's current frame (the world frame once
/// posed), computed from the anatomy when called: pose the plant first, then take its
/// ROIs. Heights are measured along z from the plant's base.

#include <string>
#include <vector>

#include <Eigen/Core>

#include <plantnbv/common/box.h>
#include <plantnbv/common/roi_kind.h>
#include <plantnbv/plant/plant.h>

namespace plantnbv {

/// \brief The box centred on the stem axis `center_height_m` above the base (at exactly
/// that height; x and y of the stem axis there).
/// Defaults are the paper's whole-plant ROI: 0.3 x 0.3 x 0.7 m centred 0.35 m up (Table
/// 1: base (1.0, 0, 0.8), centre (1.0, 0, 1.15)). One box named "whole_plant". \throws
/// InvalidArgumentError for a negative size or a plant without stem axis.
Roi wholePlantRoi(const Plant& plant,
                  const Eigen::Vector3d& size = Eigen::Vector3d(0.3, 0.3, 0.7),
                  double center_height_m = 0.35);

/// \brief As wholePlantRoi with the paper's main-stem size 0.05 x 0.05 x 0.7 m, which
/// holds the whole stem (it deviates less than 2.5 cm from the vertical) but little of
/// the leaves. One box named "main_stem".
Roi mainStemRoi(const Plant& plant,
                const Eigen::Vector3d& size = Eigen::Vector3d(0.05, 0.05, 0.7),
                double center_height_m = 0.35);

/// \brief The default leaf nodes: three at low, middle and high positions (at 20, 50 and
/// 80 % of the way from the lowest to the highest node), as the paper chose; all nodes
/// when there are fewer than three.
std::vector<int> defaultLeafNodeIndices(const Plant& plant);

/// \brief One box of `size` (default 0.03 x 0.03 x 0.05 m, the paper's) centred on each
/// chosen leaf node (LeafNode::position), named "leaf_node_<index>".
/// \throws InvalidArgumentError for an index that is not a leaf of the plant.
Roi leafNodeRoi(const Plant& plant, const std::vector<int>& leaf_indices,
                const Eigen::Vector3d& size = Eigen::Vector3d(0.03, 0.03, 0.05));
/// \brief leafNodeRoi at defaultLeafNodeIndices().
Roi leafNodeRoi(const Plant& plant);

/// \brief One box per truss: the bounding box of its fruits' spheres (centre +- radius),
/// grown by `margin_m` (default 0) and 1 um (float rounding of the mesh) on every side,
/// named "truss_<index>". Empty when the plant has no fruit.
/// \throws InvalidArgumentError for a negative or non-finite margin.
Roi fruitRoi(const Plant& plant, double margin_m = 0.0);

/// \brief One box per connected group of the mesh's triangles labelled `label` (triangles
/// meet when they share a vertex position), the group's bounding box grown by 1 um,
/// named "<label>_<k>" (k from 0, lowest box centre first, then by x and y): the fruit
/// ROI of a labelled model (`labelledPartRoi(plant, PartLabel::fruit)`, one box per
/// fruit), whose anatomy has no trusses. Touching fruits make one box. Empty when no
/// triangle carries the label (a scan: its points have no connectivity).
Roi labelledPartRoi(const Plant& plant, PartLabel label);

/// \brief The axis-aligned bounding box of the plant's mesh or scan, named "whole_plant":
/// the whole-plant ROI of a loaded model, whose size the paper's 0.3 x 0.3 x 0.7 m box
/// may not fit. \throws InvalidArgumentError for an empty mesh.
Roi boundingBoxRoi(const Plant& plant);

/// \brief The ROI of `kind` with the defaults above (fruit: fruitRoi, empty without
/// fruit).
Roi plantRoi(const Plant& plant, RoiKind kind);

} // namespace plantnbv
