#include "plant_source.h"

#include <cmath>
#include <filesystem>
#include <sstream>

#include <CLI/CLI.hpp>
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

namespace plantnbv {
namespace app {

void addPlantSourceOptions(CLI::App& cmd, PlantSourceOptions& o, const std::string& seed_flag)
{
  o.seed_flag = seed_flag;
  auto* seed = cmd.add_option(
      seed_flag, o.seed, "Generate a tomato plant from this seed (0-9: the default set)");
  auto* model = cmd.add_option("--model", o.model,
                               "Load a plant instead: a mesh (.dae .obj .ply .stl .wrl) "
                               "or a scanned cloud (.pcd .ply)");
  seed->excludes(model);
  model->excludes(seed);
  cmd.add_option("--stage", o.stage,
                 "Growth stage in [0, 1] (default: seed/9 for seeds 0-9, else 0.5)")
      ->needs(seed);
  cmd.add_flag("--simplified", o.simplified, "Remove half of the leaflets of every leaf")
      ->needs(seed);
  cmd.add_option("--labels", o.labels,
                 "Part labels from node names, e.g. stem=Branch.*,leaflet=Leaf.*")
      ->needs(model);
  cmd.add_option("--rois", o.rois, "ROI file (YAML boxes, world frame) for the model")
      ->needs(model);
  auto* keep = cmd.add_flag("--keep-frame", o.keep_frame,
                            "Keep the model file's coordinates (no --base, --yaw-deg)")
                   ->needs(model);
  cmd.add_option("--yaw-deg", o.yaw_deg, "Turn the plant about its stem, degrees")
      ->capture_default_str()
      ->excludes(keep);
  cmd.add_option("--base", o.base, "Plant base position x,y,z in metres (world frame)")
      ->delimiter(',')
      ->capture_default_str()
      ->excludes(keep);
}

PlacedPlant makePlacedPlant(const PlantSourceOptions& o)
{
  if (!o.seed && o.model.empty())
    throw InvalidArgumentError("give a plant: " + o.seed_flag +
                               " S (generated) or --model FILE");
  if (o.base.size() != 3 || !std::isfinite(o.base[0]) || !std::isfinite(o.base[1]) ||
      !std::isfinite(o.base[2]))
    throw InvalidArgumentError("--base must be three finite numbers x,y,z in metres");
  if (!std::isfinite(o.yaw_deg))
    throw InvalidArgumentError("--yaw-deg must be a finite angle in degrees");
  const Eigen::Vector3d base(o.base[0], o.base[1], o.base[2]);
  const double yaw_rad = o.yaw_deg * M_PI / 180.0;

  PlacedPlant out;
  std::ostringstream d;
  if (o.seed) {
    TomatoPlantGenerator::Config config;
    if (*o.seed < static_cast<std::uint64_t>(kDefaultPlantCount))
      config = defaultPlantConfig(static_cast<int>(*o.seed), o.simplified);
    config.seed = *o.seed;
    config.simplified = o.simplified;
    if (o.stage)
      config.growth_stage = *o.stage;
    out.plant = TomatoPlantGenerator(config).generate(); // validates the stage
    posePlant(out.plant, base, yaw_rad);
    for (PlantRoiKind kind : {PlantRoiKind::whole_plant, PlantRoiKind::main_stem,
                              PlantRoiKind::leaf_nodes, PlantRoiKind::fruits}) {
      Roi roi = plantRoi(out.plant, kind);
      if (!roi.empty())
        out.rois.emplace_back(plantRoiKindName(kind), std::move(roi));
    }
    d << "seed " << *o.seed << ", growth stage " << config.growth_stage
      << (o.simplified ? ", simplified" : "");
    out.description = d.str();
    return out;
  }

  const std::string name = std::filesystem::path(o.model).stem().string();
  switch (io::fileKind(o.model)) {
  case io::FileKind::mesh: {
    TriangleMesh mesh = io::loadMesh(o.model);
    if (!o.labels.empty())
      applyPartLabelRules(mesh, parsePartLabelRules(o.labels));
    out.plant = plantFromMesh(std::move(mesh), name, o.keep_frame);
    break;
  }
  case io::FileKind::cloud: { // a scan: kept as points, labels from its label field
    if (!o.labels.empty())
      throw InvalidArgumentError("--labels maps mesh node names; the scan '" + o.model +
                                 "' has none (its labels come from its label field)");
    CloudXYZL cloud;
    io::loadCloud(o.model, cloud);
    std::vector<Eigen::Vector3f> points;
    std::vector<PartLabel> labels;
    for (const auto& p : cloud)
      if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) {
        points.push_back(p.getVector3fMap());
        labels.push_back(static_cast<PartLabel>(std::min<std::uint32_t>(p.label, 6)));
      }
    out.plant = plantFromScan(std::move(points), std::move(labels), name, o.keep_frame);
    break;
  }
  case io::FileKind::octree:
    throw FormatError("--model '" + o.model +
                      "' is an octree; expected a mesh or a cloud");
  }
  if (!o.keep_frame)
    posePlant(out.plant, base, yaw_rad);
  out.rois.emplace_back("whole_plant", boundingBoxRoi(out.plant));
  if (!o.rois.empty())
    out.rois.emplace_back("model_rois", io::loadRoi(o.rois));
  d << "model " << o.model << (o.labels.empty() ? "" : ", labelled by name")
    << (o.keep_frame ? ", file frame kept" : "");
  out.description = d.str();
  return out;
}

} // namespace app
} // namespace plantnbv
