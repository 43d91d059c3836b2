#pragma once
// How a trial is set up from a placed plant: its evaluation levels and the attention ROI
// of the NBV planner. Shared by reconstruct and campaign (the same names and ROIs).

#include <string>
#include <vector>

#include <plantnbv/common/box.h>
#include <plantnbv/experiment/reconstruction_evaluator.h>

#include "plant_source.h"

namespace plantnbv {
namespace app {

/// The plant's ROI of an evaluation level. Level names are steps.csv's column prefixes.
struct LevelSource {
  const char* level;     ///< column prefix in steps.csv, level name in results
  const char* roi;       ///< name in PlacedPlant::rois
  const char* attention; ///< --attention value
  bool average_boxes;
};
/// whole_plant, main_stem, leaf_nodes, fruit.
const std::vector<LevelSource>& levelSources();

/// The ROI named `name` in placed.rois, or nullptr.
const Roi* findRoi(const PlacedPlant& placed, const std::string& name);

/// True for whole-plant, main-stem, leaf-nodes, fruit and names with an extension (a
/// ROI file).
bool isAttentionName(const std::string& attention);

/// The attention ROI: a level's ROI by its --attention name, or a ROI file (a name with
/// an extension). \throws InvalidArgumentError if the plant has no such ROI or the name
/// is unknown; the io errors of the file.
Roi attentionRoi(const PlacedPlant& placed, const std::string& attention);

/// The levels the plant has ROIs for, in levelSources() order, then model_rois (each box
/// scored on its own) for a model with --rois.
std::vector<EvaluationLevel> evaluationLevels(const PlacedPlant& placed);

} // namespace app
} // namespace plantnbv
