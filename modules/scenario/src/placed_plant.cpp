#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/io/cloud_io.h>
#include <plantnbv/io/file_kind.h>
#include <plantnbv/io/mesh_io.h>
#include <plantnbv/io/roi_io.h>
#include <plantnbv/plant/plant_model.h>
#include <plantnbv/plant/plant_rois.h>
#include <plantnbv/plant/tomato_plant_generator.h>
#include <plantnbv/scenario/placed_plant.h>

namespace plantnbv {
namespace scenario {

const Roi* PlacedPlant::roi(RoiKind kind) const
{
  const auto it = rois.find(kind);
  return it == rois.end() ? nullptr : &it->second;
}

namespace {

void checkSource(const PlantSource& s)
{
  if (s.seed.has_value() == !s.model.empty())
    throw InvalidArgumentError(s.seed ? "plant source: a seed and a model file; give one"
                                      : "plant source: give a seed or a model file");
  if (s.seed && (!s.labels.empty() || s.keep_frame || s.scale != 0.0 ||
                 s.up_axis != io::MeshLoadOptions::UpAxis::from_file))
    throw InvalidArgumentError(
        "plant source: labels, scale, up axis and keep_frame belong to a model file");
  if (!(std::isfinite(s.scale) && s.scale >= 0.0))
    throw InvalidArgumentError("plant source: the scale must be metres per file unit, "
                               "a finite number > 0, or 0 for the file's own unit");
  if (!s.model_parts.empty() && s.model.empty())
    throw InvalidArgumentError("plant source: model parts without a model file");
  if (!s.model.empty() && (s.stage || s.simplified))
    throw InvalidArgumentError(
        "plant source: stage and simplified belong to a generated plant");
  if (!s.base.allFinite())
    throw InvalidArgumentError(
        "plant source: the base must be three finite numbers x,y,z "
        "in metres");
  // A turn beyond one revolution is a mistake, and cos/sin of 1e19 degrees is not a turn.
  if (!(std::abs(s.yaw_deg) <= kMaxPlantYawDeg)) {
    std::ostringstream m;
    m << "plant source: the yaw " << s.yaw_deg << " must be an angle in [-"
      << kMaxPlantYawDeg << ", " << kMaxPlantYawDeg << "] degrees";
    throw InvalidArgumentError(m.str());
  }
}

PlacedPlant generatedPlant(const PlantSource& s, double yaw_rad)
{
  PlacedPlant out;
  TomatoPlantGenerator::Config config;
  if (*s.seed < static_cast<std::uint64_t>(kDefaultPlantCount))
    config = defaultPlantConfig(static_cast<int>(*s.seed), s.simplified);
  config.seed = *s.seed;
  config.simplified = s.simplified;
  if (s.stage)
    config.growth_stage = *s.stage;
  out.plant = TomatoPlantGenerator(config).generate(); // validates the stage
  posePlant(out.plant, s.base, yaw_rad);
  for (RoiKind kind : kRoiKinds) {
    Roi roi = plantRoi(out.plant, kind);
    if (!roi.empty())
      out.rois.emplace(kind, std::move(roi));
  }
  std::ostringstream d;
  d << "seed " << *s.seed << ", growth stage " << config.growth_stage
    << (s.simplified ? ", simplified" : "");
  out.description = d.str();
  return out;
}

/// A scan keeps its points; labels come from its label field. A label beyond ours (a
/// data set's own numbering) is read as background and counted in `warnings`.
Plant scannedPlant(const PlantSource& s, const std::string& name,
                   std::vector<std::string>& warnings)
{
  const std::string& path = s.model;
  const double scale = s.scale;
  const Eigen::Matrix3d up = io::upAxisRotation(s.up_axis);
  CloudXYZL cloud;
  io::loadCloud(path, cloud);
  constexpr auto kLast = static_cast<std::uint32_t>(kLastPartLabel);
  std::vector<Eigen::Vector3f> points;
  std::vector<PartLabel> labels;
  std::size_t foreign = 0;
  for (const auto& p : cloud)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) {
      const Eigen::Vector3f q =
          scale > 0.0 ? (scale * p.getVector3fMap().cast<double>()).cast<float>()
                      : Eigen::Vector3f(p.getVector3fMap());
      points.push_back((up * q.cast<double>()).cast<float>()); // as a mesh file's
      foreign += p.label > kLast;
      labels.push_back(p.label > kLast ? PartLabel::background : PartLabel(p.label));
    }
  if (foreign > 0)
    warnings.push_back(std::to_string(foreign) + " points of '" + path +
                       "' have a label above " + std::to_string(kLast) +
                       " (ours: 0 unknown to 7 flower; docs/plants.md) and are read "
                       "as background");
  return plantFromScan(std::move(points), std::move(labels), name, s.keep_frame);
}

/// The model's mesh files as one mesh. A file that names no node or mesh (PLY, STL)
/// names its triangles by its file's stem, so that label rules can tell the files of a
/// plant split by part apart ("stem=stem" for stem.ply).
TriangleMesh loadModelMesh(const PlantSource& s, std::vector<std::string>& warnings)
{
  std::vector<std::string> files{s.model};
  files.insert(files.end(), s.model_parts.begin(), s.model_parts.end());
  TriangleMesh all;
  for (const std::string& file : files) {
    if (io::fileKind(file) != io::FileKind::mesh)
      throw FormatError("model '" + file +
                        "': a plant split into several files takes mesh files (.dae "
                        ".obj .ply .stl .wrl)");
    io::MeshLoadOptions options;
    options.scale = s.scale;
    options.up_axis = s.up_axis;
    io::MeshFileUnits units;
    TriangleMesh mesh = io::loadMesh(file, options, &units);
    if (units.can_declare_unit && !units.unit_declared && s.scale == 0.0)
      warnings.push_back("'" + file +
                         "' declares no <unit>: read in metres (Collada's default); give "
                         "the model's scale if it is in other units");
    bool named = false;
    for (const auto* names :
         {&mesh.node_names, &mesh.geometry_names, &mesh.material_names})
      named = named || std::any_of(names->begin(), names->end(),
                                   [](const std::string& n) { return !n.empty(); });
    if (!named || mesh.node_ids.empty()) {
      mesh.node_names = {std::filesystem::path(file).stem().string()};
      mesh.geometry_names.clear();
      mesh.material_names.clear();
      mesh.node_ids.assign(mesh.triangles.size(), 0);
    }
    all.append(mesh);
  }
  return all;
}

/// The largest extent a plant model may have before its unit is suspect (metres):
/// larger than any plant a depth camera of 0.75 m range reconstructs from a sector.
constexpr double kLargestPlausiblePlantM = 3.0;
/// The smallest: below it, the scale given is most likely wrong (millimetres given to a
/// file in metres, say).
constexpr double kSmallestPlausiblePlantM = 0.01;

/// A model far larger or smaller than a plant is most often read in the wrong unit (an
/// OBJ in centimetres read as metres): said in `warnings`, with the scale to give.
void warnOfAnImplausibleSize(const Roi& whole, const PlantSource& s,
                             std::vector<std::string>& warnings)
{
  if (whole.empty())
    return;
  const Eigen::Vector3d size = whole.boxes().front().size;
  const double largest = size.maxCoeff();
  if (largest <= kLargestPlausiblePlantM && largest >= kSmallestPlausiblePlantM)
    return;
  std::ostringstream w;
  w << "'" << s.model << "' is " << size.z() << " m tall and "
    << std::max(size.x(), size.y()) << " m across, "
    << (largest > kLargestPlausiblePlantM ? "larger" : "smaller")
    << " than a plant: its unit may be wrong";
  if (s.scale == 0.0)
    w << " (read in "
      << (io::fileKind(s.model) == io::FileKind::mesh ? "its file's unit" : "metres")
      << "; give the model's scale, 0.01 for centimetres, 0.001 for millimetres)";
  else
    w << " (scale " << s.scale << " metres per file unit given)";
  // A file read with the wrong up axis lies on its side, less tall than wide.
  if (s.up_axis == io::MeshLoadOptions::UpAxis::from_file && size.z() < largest)
    w << "; if it lies on its side, give its up axis too (y for an OBJ from Blender)";
  warnings.push_back(w.str());
}

PlacedPlant modelPlant(const PlantSource& s, double yaw_rad)
{
  PlacedPlant out;
  const std::string name = std::filesystem::path(s.model).stem().string();
  const io::FileKind kind =
      s.model_parts.empty() ? io::fileKind(s.model) : io::FileKind::mesh;
  switch (kind) {
  case io::FileKind::mesh: {
    TriangleMesh mesh = loadModelMesh(s, out.warnings);
    if (!s.labels.empty()) {
      const std::vector<PartLabelRule> rules = parsePartLabelRules(s.labels);
      const std::vector<std::size_t> labelled = applyPartLabelRules(mesh, rules);
      for (std::size_t i = 0; i < rules.size(); ++i)
        if (labelled[i] == 0)
          out.warnings.push_back(
              "label rule " + std::string(partLabelName(rules[i].label)) + "=" +
              rules[i].pattern + " matches no triangle of '" + s.model + "'" +
              (s.model_parts.empty() ? "" : " and its other files") +
              " (rules match node, geometry and material names, or the file's name where "
              "it "
              "has none; the first that matches wins)");
    }
    out.plant = plantFromMesh(std::move(mesh), name, s.keep_frame);
    break;
  }
  case io::FileKind::cloud:
    if (!s.labels.empty())
      throw InvalidArgumentError("label rules map mesh node names; the scan '" + s.model +
                                 "' has none (its labels come from its label field)");
    out.plant = scannedPlant(s, name, out.warnings);
    break;
  case io::FileKind::octree:
    throw FormatError("model '" + s.model + "' is an octree; expected a mesh or a cloud");
  }
  if (!s.keep_frame)
    posePlant(out.plant, s.base, yaw_rad);
  Roi whole = boundingBoxRoi(out.plant);
  warnOfAnImplausibleSize(whole, s, out.warnings);
  out.rois.emplace(RoiKind::whole_plant, std::move(whole));
  // A labelled model's fruits, one box each: `--attention fruit` and the fruit level.
  if (Roi fruits = labelledPartRoi(out.plant, PartLabel::fruit); !fruits.empty())
    out.rois.emplace(RoiKind::fruit, std::move(fruits));

  std::ostringstream d;
  d << "model " << s.model;
  if (!s.model_parts.empty())
    d << " and " << s.model_parts.size() << " more file"
      << (s.model_parts.size() > 1 ? "s" : "");
  if (s.up_axis != io::MeshLoadOptions::UpAxis::from_file)
    d << ", " << io::upAxisName(s.up_axis) << " up";
  d << (s.labels.empty() ? "" : ", labelled by name")
    << (s.keep_frame ? ", file frame kept" : "");
  out.description = d.str();
  return out;
}

} // namespace

PlacedPlant makePlacedPlant(const PlantSource& source)
{
  checkSource(source);
  const double yaw_rad = source.yaw_deg * M_PI / 180.0;
  PlacedPlant placed =
      source.seed ? generatedPlant(source, yaw_rad) : modelPlant(source, yaw_rad);
  if (!source.rois.empty()) { // the user's boxes, generated plant or model
    placed.model_rois = io::loadRoi(source.rois);
    // Boxes drawn in another frame (a model file's own, the plant not kept there) miss.
    const Box plant_box = boundingBoxRoi(placed.plant).boxes().front();
    for (std::size_t i = 0; i < placed.model_rois.size(); ++i) {
      const Box& box = placed.model_rois.boxes()[i];
      if (!box.overlaps(plant_box))
        placed.warnings.push_back(
            "ROI box " + std::to_string(i) +
            (box.name.empty() ? "" : " '" + box.name + "'") + " of '" + source.rois +
            "' does not overlap the plant: ROI files are in the world frame the plant "
            "stands in (boxes in a model file's own coordinates need --keep-frame)");
    }
  }
  placed.source = source;
  return placed;
}

std::vector<PlacedPlant> rowNeighbours(const PlantSource& target, double spacing_m,
                                       double facing_rad)
{
  if (!(std::isfinite(spacing_m) && spacing_m > 0.0))
    throw InvalidArgumentError("row: the spacing must be a finite number of metres > 0");
  if (!std::isfinite(facing_rad))
    throw InvalidArgumentError("row: the facing azimuth must be finite");
  if (target.keep_frame)
    throw InvalidArgumentError(
        "row: a plant with its file frame kept has no base to place neighbours from");
  const Eigen::Vector3d along(-std::sin(facing_rad), std::cos(facing_rad), 0.0);
  std::vector<PlacedPlant> out;
  for (int side = 0; side < 2; ++side) {
    PlantSource s = target;
    s.rois.clear(); // the target's boxes, not theirs
    if (s.seed)
      s.seed = *s.seed < static_cast<std::uint64_t>(kDefaultPlantCount)
                   ? (*s.seed + 1 + side) % kDefaultPlantCount
                   : *s.seed + 1 + side;
    s.base = target.base + (side == 0 ? -spacing_m : spacing_m) * along;
    // The turn stays within +-360 degrees.
    s.yaw_deg = std::remainder(target.yaw_deg + 120.0 * (side + 1), 360.0);
    out.push_back(makePlacedPlant(s));
  }
  return out;
}

} // namespace scenario
} // namespace plantnbv
