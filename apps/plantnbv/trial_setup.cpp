#include "trial_setup.h"

#include <filesystem>

#include <plantnbv/common/error.h>
#include <plantnbv/io/roi_io.h>

namespace plantnbv {
namespace app {

const std::vector<LevelSource>& levelSources()
{
  static const std::vector<LevelSource> levels{
      {"whole_plant", "whole_plant", "whole-plant", false},
      {"main_stem", "main_stem", "main-stem", false},
      {"leaf_nodes", "leaf_nodes", "leaf-nodes", true},
      {"fruit", "fruits", "fruit", true},
  };
  return levels;
}

const Roi* findRoi(const PlacedPlant& placed, const std::string& name)
{
  for (const auto& [roi_name, roi] : placed.rois)
    if (roi_name == name)
      return &roi;
  return nullptr;
}

bool isAttentionName(const std::string& attention)
{
  for (const LevelSource& l : levelSources())
    if (attention == l.attention)
      return true;
  return std::filesystem::path(attention).has_extension();
}

Roi attentionRoi(const PlacedPlant& placed, const std::string& attention)
{
  for (const LevelSource& l : levelSources())
    if (attention == l.attention) {
      const Roi* roi = findRoi(placed, l.roi);
      if (!roi)
        throw InvalidArgumentError("attention " + attention + ": the plant has no " +
                                   l.level +
                                   " ROI (a loaded model has whole-plant and "
                                   "the boxes of its ROI file; give a ROI file instead)");
      return *roi;
    }
  if (std::filesystem::path(attention).has_extension())
    return io::loadRoi(attention);
  throw InvalidArgumentError("attention '" + attention +
                             "': expected whole-plant, main-stem, leaf-nodes, fruit or "
                             "a ROI file (.yaml)");
}

std::vector<EvaluationLevel> evaluationLevels(const PlacedPlant& placed)
{
  std::vector<EvaluationLevel> levels;
  for (const LevelSource& l : levelSources())
    if (const Roi* roi = findRoi(placed, l.roi))
      levels.push_back({l.level, *roi, l.average_boxes});
  if (const Roi* roi = findRoi(placed, "model_rois"))
    levels.push_back({"model_rois", *roi, true});
  return levels;
}

} // namespace app
} // namespace plantnbv
