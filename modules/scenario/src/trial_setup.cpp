#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>

#include <plantnbv/common/error.h>
#include <plantnbv/io/roi_io.h>
#include <plantnbv/scenario/trial_config_file.h>
#include <plantnbv/scenario/trial_setup.h>

namespace plantnbv {
namespace scenario {

Attention Attention::parse(const std::string& name)
{
  Attention a;
  if ((a.kind = roiKindFromName(name)))
    return a;
  if (std::filesystem::path(name).has_extension()) {
    a.file = name;
    return a;
  }
  throw InvalidArgumentError("unknown ROI '" + name + "' (expected " + roiKindNames() +
                             " or an ROI file, .yaml)");
}

std::string Attention::name() const
{
  return kind ? roiKindName(*kind) : file;
}

std::string nbvPlannerName(const Attention& attention, const RoiSource& source)
{
  std::string name;
  if (!attention.kind) {
    name = "nbv-" + std::filesystem::path(attention.file).stem().string();
  } else {
    std::string kind = roiKindName(*attention.kind);
    std::replace(kind.begin(), kind.end(), '_', '-');
    name = "nbv-" + kind;
  }
  std::ostringstream s;
  s << std::setprecision(6);
  if (source.kind == RoiSourceKind::noisy) {
    s << "-noisy" << source.sigma_m * 1000.0 << "mm";
    if (source.scale != 1.0)
      s << "-x" << source.scale;
  } else if (source.followsFrames()) {
    s << (source.kind == RoiSourceKind::detections ? "-detections"
          : source.kind == RoiSourceKind::prior    ? "-prior"
                                                   : "-detections-prior");
    if (source.detector_recall != 1.0)
      s << "-recall" << source.detector_recall;
    if (source.detector_false_positives != 0.0)
      s << "-fp" << source.detector_false_positives;
    if (source.detector_box_jitter_px != 0.0)
      s << "-jitter" << source.detector_box_jitter_px << "px";
    if (source.detector_mask_dilation_px != 0)
      s << "-dilation" << source.detector_mask_dilation_px << "px";
    if (!source.detector_masks)
      s << "-boxes";
    if (source.prior_internode_m != RoiSource().prior_internode_m)
      s << "-internode" << source.prior_internode_m * 1000.0 << "mm";
    if (source.detections_explore_views != RoiSource().detections_explore_views)
      s << "-explore" << source.detections_explore_views;
  }
  name += s.str();
  return name;
}

Roi attentionRoi(const PlacedPlant& placed, const Attention& attention)
{
  if (!attention.kind)
    return io::loadRoi(attention.file);
  if (const Roi* roi = placed.roi(*attention.kind))
    return *roi;
  throw InvalidArgumentError("attention " + attention.name() + ": the plant has no " +
                             attention.name() +
                             " ROI (a loaded model has whole_plant, fruit when triangles "
                             "are labelled fruit, and the boxes of its ROI file; give an "
                             "ROI file instead)");
}

std::vector<EvaluationLevel> evaluationLevels(const PlacedPlant& placed)
{
  std::vector<EvaluationLevel> levels;
  for (const auto& [kind, roi] : placed.rois) // std::map: kRoiKinds order
    levels.push_back({roiKindName(kind), roi, roiKindScoresBoxesApart(kind)});
  if (!placed.model_rois.empty())
    levels.push_back({kModelRoisLevel, placed.model_rois, true});
  return levels;
}

std::string canonicalLevelName(const std::string& name)
{
  if (const auto kind = roiKindFromName(name))
    return roiKindName(*kind);
  if (name == kModelRoisLevel)
    return name;
  throw InvalidArgumentError("unknown level '" + name + "' (expected " + roiKindNames() +
                             " or " + kModelRoisLevel + ")");
}

void setCandidateCount(int candidates, const std::string& what, TrialConfig& config)
{
  const int cells = config.grid_rows * config.grid_cols;
  if (cells <= 0 || candidates < cells || candidates % cells != 0)
    throw InvalidArgumentError(
        what + " " + std::to_string(candidates) + ": expected a multiple of the " +
        std::to_string(cells) + " grid cells (" + std::to_string(cells) + ", " +
        std::to_string(3 * cells) + ", " + std::to_string(5 * cells) + ", ...)");
  config.samples_per_cell = candidates / cells;
}

void fitSectorToPlant(const PlacedPlant& placed, std::optional<double> sector_height_m,
                      TrialConfig& config)
{
  if (sector_height_m) {
    config.sector.height_m = *sector_height_m;
    return;
  }
  if (placed.source.model.empty())
    return;
  Eigen::Vector3f lo, hi;
  placed.plant.bounds(lo, hi);
  config.sector.height_m =
      std::max(0.05, double(hi.z()) - placed.plant.base_position.z());
}

void RoiSourceOverrides::applyTo(RoiSource& roi, const std::string& option_prefix) const
{
  if (source) {
    try {
      roi.kind = roiSourceKindFromName(*source);
    } catch (const InvalidArgumentError& e) {
      throw InvalidArgumentError(
          (option_prefix.empty() ? "roi_source: " : option_prefix + "roi-source: ") +
          e.what());
    }
  }
  if (source) { // a config's parameters of another source mean nothing to this one
    const RoiSource defaults;
    if (roi.kind != RoiSourceKind::noisy) {
      roi.sigma_m = defaults.sigma_m;
      roi.scale = defaults.scale;
    }
    if (!roi.detects()) {
      roi.detector_recall = defaults.detector_recall;
      roi.detector_false_positives = defaults.detector_false_positives;
      roi.detector_box_jitter_px = defaults.detector_box_jitter_px;
      roi.detector_mask_dilation_px = defaults.detector_mask_dilation_px;
      roi.detector_masks = defaults.detector_masks;
    }
    if (!roi.predicts())
      roi.prior_internode_m = defaults.prior_internode_m;
    if (roi.kind != RoiSourceKind::detections)
      roi.detections_explore_views = defaults.detections_explore_views;
  }
  if (sigma_m)
    roi.sigma_m = *sigma_m;
  if (scale)
    roi.scale = *scale;
  if (detector_recall)
    roi.detector_recall = *detector_recall;
  if (detector_false_positives)
    roi.detector_false_positives = *detector_false_positives;
  if (detector_box_jitter_px)
    roi.detector_box_jitter_px = *detector_box_jitter_px;
  if (detector_mask_dilation_px)
    roi.detector_mask_dilation_px = *detector_mask_dilation_px;
  if (detector_masks)
    roi.detector_masks = *detector_masks;
  if (prior_internode_m)
    roi.prior_internode_m = *prior_internode_m;
  if (detections_explore_views)
    roi.detections_explore_views = *detections_explore_views;
  roi.validate(option_prefix);
}

TrialConfig makeTrialConfig(const TrialOverrides& o, const PlacedPlant& placed,
                            const std::string& option_prefix)
{
  TrialConfig c;
  if (!o.config_file.empty())
    loadTrialConfig(o.config_file, c);
  if (o.planner)
    c.planner = plannerKindFromName(*o.planner);
  if (o.pattern) {
    if (c.planner != PlannerKind::predefined) // it would be ignored
      throw InvalidArgumentError(option_prefix + "pattern " + std::to_string(*o.pattern) +
                                 ": only the predefined planner has patterns (the "
                                 "planner is " +
                                 plannerKindName(c.planner) + ")");
    c.pattern = *o.pattern;
  }
  if (o.views)
    c.views = *o.views;
  if (o.candidates)
    setCandidateCount(*o.candidates, option_prefix + "candidates", c);
  if (o.resolution_m)
    c.map.resolution_m = *o.resolution_m;
  if (o.seed)
    c.seed = *o.seed;
  if (o.threads)
    c.threads = *o.threads;
  if (o.depth_scale)
    c.depth_scale = *o.depth_scale;
  if (o.camera)
    c.camera = *o.camera;
  if (o.noise)
    c.noise.enabled = *o.noise;
  if (o.background)
    c.scene.floor = c.scene.support = *o.background;
  o.roi.applyTo(c.roi_source, option_prefix);
  fitSectorToPlant(placed, o.sector_height_m, c);
  if (o.sector_radius_m)
    c.sector.radius_m = *o.sector_radius_m;
  c.validate();
  return c;
}

std::vector<std::string> trialWarnings(const PlacedPlant& placed,
                                       const TrialConfig& config, const Roi& attention,
                                       const std::vector<EvaluationLevel>& levels)
{
  std::vector<std::string> warnings;
  const double res = config.map.resolution_m;
  for (const EvaluationLevel& level : levels) {
    double side = std::numeric_limits<double>::infinity();
    for (const Box& b : level.roi.boxes())
      side = std::min(side, b.size.minCoeff());
    if (2.0 * res > side) {
      std::ostringstream s;
      s << std::setprecision(3) << "the map's resolution " << res
        << " m gives fewer than 2 voxels across the " << side
        << " m side of a box of level " << level.name
        << ": its scores say little (the paper's is 0.003 m)";
      warnings.push_back(s.str());
    }
  }
  if (config.planner == PlannerKind::nbv && !attention.empty()) {
    Eigen::Vector3f lo, hi;
    placed.plant.bounds(lo, hi);
    const Box plant_box = Box::fromMinMax(lo.cast<double>(), hi.cast<double>());
    const Box roi = attention.boundingBox();
    // No box meets the plant (their union's bounding box may, between them).
    const bool apart = std::none_of(attention.boxes().begin(), attention.boxes().end(),
                                    [&](const Box& b) { return b.overlaps(plant_box); });
    if (apart) {
      std::ostringstream s;
      s << std::setprecision(3);
      const auto point = [&s](const Eigen::Vector3d& p) {
        s << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
      };
      s << "the attention ROI, ";
      point(roi.min());
      s << " to ";
      point(roi.max());
      s << ", does not meet the plant, ";
      point(lo.cast<double>());
      s << " to ";
      point(hi.cast<double>());
      s << " (world frame, metres): the planner attends to no part of it";
      warnings.push_back(s.str());
    }
  }
  return warnings;
}

NeighbourPlants rowNeighbourPlants(const PlacedPlant& placed, double spacing_m,
                                   const TrialConfig& config)
{
  NeighbourPlants neighbours;
  if (spacing_m == 0.0)
    return neighbours;
  CylindricalSector sector = config.sector; // facing the robot from the plant's base
  sector.axis_base = placed.plant.base_position;
  for (PlacedPlant& n : rowNeighbours(placed.source, spacing_m, sector.facingAzimuth()))
    neighbours.push_back(std::make_shared<const Plant>(std::move(n.plant)));
  return neighbours;
}

void setUpTrial(const PlacedPlant& placed, const Roi& attention,
                const std::vector<EvaluationLevel>& levels, Trial& trial)
{
  trial.setPlant(std::make_shared<Plant>(placed.plant));
  trial.setAttentionRoi(attention);
  if (const Roi* whole = placed.roi(RoiKind::whole_plant))
    trial.setExplorationRoi(*whole);
  trial.setEvaluationLevels(levels);
}

} // namespace scenario
} // namespace plantnbv
