#pragma once
/// \file roi_kind.h
/// \brief The regions of a plant that a planner attends to and a trial is scored on (the
/// paper's attention levels, section 3.2, plus fruit): one enum and one spelling each.
///
/// A kind's name is the same in every file we write and read, in steps.csv's column
/// prefixes, in campaign files and reports and on the command line: whole_plant,
/// main_stem, leaf_nodes, fruit. Where a name is read, '-' reads as '_' (so the CLI's
/// `--attention leaf-nodes` and campaign files written before this vocabulary keep
/// working), and `fruits` (the former ROI name of the fruit boxes) reads as fruit.

#include <array>
#include <optional>
#include <string>

namespace plantnbv {

/// \brief The plant regions of the paper's study.
enum class RoiKind {
  whole_plant, ///< 0.3 x 0.3 x 0.7 m around the stem (a loaded model: its bounding box)
  main_stem,   ///< 0.05 x 0.05 x 0.7 m around the stem
  leaf_nodes,  ///< 0.03 x 0.03 x 0.05 m boxes at three leaf nodes (low, middle, high)
  fruit,       ///< one box per truss (a labelled model: per connected fruit)
};

/// \brief Every kind, in the order the study reports them.
constexpr std::array<RoiKind, 4> kRoiKinds{RoiKind::whole_plant, RoiKind::main_stem,
                                           RoiKind::leaf_nodes, RoiKind::fruit};

/// \brief "whole_plant", "main_stem", "leaf_nodes" or "fruit".
const char* roiKindName(RoiKind kind);

/// \brief The kind named `name` in any accepted spelling ('-' for '_', "fruits" for
/// fruit), or nothing.
std::optional<RoiKind> roiKindFromName(const std::string& name);

/// \brief "Whole plant", "Main stem", "Leaf nodes", "Fruit": titles for figures.
const char* roiKindTitle(RoiKind kind);

/// \brief The title of an ROI or level named `name`: its kind's title for a kind in any
/// spelling ("leaf-nodes": "Leaf nodes"), else the name itself (a file, model_rois).
std::string roiTitle(const std::string& name);

/// \brief True where the ROI is several small boxes scored one by one and averaged (leaf
/// nodes, fruit: the paper averages its three leaf nodes), false where it is one box.
bool roiKindScoresBoxesApart(RoiKind kind);

/// \brief The accepted names for messages: "whole_plant, main_stem, leaf_nodes, fruit".
std::string roiKindNames();

} // namespace plantnbv
