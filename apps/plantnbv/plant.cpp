// plantnbv plant: generate (or load) a plant, place it in the world, and write its mesh,
// anatomy and ROIs; optionally a snapshot.

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>

#include <CLI/CLI.hpp>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/file_io.h>
#include <plantnbv/common/roi_kind.h>
#include <plantnbv/common/stopwatch.h>
#include <plantnbv/io/cloud_io.h>
#include <plantnbv/io/mesh_io.h>
#include <plantnbv/io/roi_io.h>
#include <plantnbv/plant/anatomy_json.h>
#include <plantnbv/scenario/trial_setup.h>
#include <plantnbv/viz/palette.h>
#include <plantnbv/viz/snapshot.h>

#include "cli_checks.h"
#include "commands.h"
#include "plant_options.h"

namespace plantnbv {
namespace app {

namespace {

using scenario::PlacedPlant;

struct PlantCommandOptions {
  PlantOptions plant;
  std::string output_dir;
  std::string snapshot;
};

std::string summary(const PlacedPlant& placed)
{
  const Plant& p = placed.plant;
  std::size_t leaflets = 0, fruits = 0;
  for (const auto& leaf : p.anatomy.leaves)
    leaflets += leaf.leaflets.size();
  for (const auto& truss : p.anatomy.trusses)
    fruits += truss.fruits.size();
  Eigen::Vector3f lo, hi;
  p.bounds(lo, hi);
  std::ostringstream s;
  s << std::fixed << std::setprecision(3) << p.name << " (" << placed.description
    << "): height " << p.anatomy.top_height_m << " m";
  if (!p.anatomy.leaves.empty())
    s << " (stem " << p.anatomy.stem_height_m << " m), " << p.anatomy.leaves.size()
      << " leaves with " << leaflets << " leaflets, " << p.anatomy.trusses.size()
      << " trusses with " << fruits << " fruits";
  const bool scan = !p.scan_points.empty();
  const auto& labels = scan ? p.scan_labels : p.mesh.labels;
  s << ", " << (scan ? p.scan_points.size() : p.mesh.size())
    << (scan ? " scan points (" : " triangles (");
  // Elements per part: shows at a glance whether a --labels mapping matched.
  std::vector<std::size_t> per_label(std::size_t(kLastPartLabel) + 1, 0);
  for (PartLabel l : labels)
    ++per_label[std::min(static_cast<std::size_t>(l), per_label.size() - 1)];
  bool first = true;
  for (std::size_t l = 0; l < per_label.size(); ++l)
    if (per_label[l]) {
      s << (first ? "" : ", ") << partLabelName(static_cast<PartLabel>(l)) << " "
        << per_label[l];
      first = false;
    }
  s << (labels.empty() ? "unlabelled" : "") << "); bounding box x [" << lo.x() << ", "
    << hi.x() << "], y [" << lo.y() << ", " << hi.y() << "], z [" << lo.z() << ", "
    << hi.z() << "] m; base at (" << p.base_position.x() << ", " << p.base_position.y()
    << ", " << p.base_position.z() << "), yaw " << std::setprecision(1)
    << p.yaw_rad * 180.0 / M_PI << " deg.";
  return s.str();
}

CloudXYZL scanCloud(const Plant& plant)
{
  CloudXYZL cloud;
  for (std::size_t i = 0; i < plant.scan_points.size(); ++i) {
    pcl::PointXYZL p;
    p.getVector3fMap() = plant.scan_points[i];
    p.label =
        plant.scan_labels.empty() ? 0u : static_cast<std::uint32_t>(plant.scan_labels[i]);
    cloud.push_back(p);
  }
  return cloud;
}

/// The plant coloured by part with its ROIs as wireframes, one colour per level.
void renderSnapshot(const PlacedPlant& placed, const std::string& png_path)
{
  viz::SceneSnapshot::Config config;
  config.width = 900;
  config.height = 1200; // plants are tall
  config.title = placed.plant.name;
  viz::SceneSnapshot snapshot(config);
  snapshot.addMesh(placed.plant.mesh);
  snapshot.addPoints(placed.plant.scan_points, placed.plant.scan_labels);
  viz::addPartLegend(placed.plant.scan_points.empty() ? placed.plant.mesh.labels
                                                      : placed.plant.scan_labels,
                     snapshot);
  const std::vector<EvaluationLevel> levels = scenario::evaluationLevels(placed);
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const viz::Rgb color = viz::distinctColor(i);
    snapshot.addRoi(levels[i].roi, color);
    snapshot.addLegendEntry(roiTitle(levels[i].name) + " ROI", color);
  }
  snapshot.render(png_path);
}

void runPlant(const PlantCommandOptions& o)
{
  if (!o.snapshot.empty())
    requireDisplayOrReexec();
  Stopwatch clock;
  const PlacedPlant placed = placePlant(o.plant);
  const double make_ms = clock.ms();
  const std::filesystem::path dir(o.output_dir);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec)
    throw IoError("cannot create output directory '" + o.output_dir +
                  "': " + ec.message());

  // A scanned plant stays a cloud: plant.pcd instead of plant.ply.
  const Plant& plant = placed.plant;
  const std::string geometry_file = plant.scan_points.empty() ? "plant.ply" : "plant.pcd";
  if (plant.scan_points.empty())
    io::saveMeshPly((dir / geometry_file).string(), plant.mesh);
  else
    io::saveCloud((dir / geometry_file).string(), scanCloud(plant));
  writeFileAtomically(dir / "anatomy.json", anatomyToJson(placed.plant) + "\n");
  // All ROIs in one file (boxes named by level), and one file per level for --roi.
  Roi all;
  const std::vector<EvaluationLevel> levels = scenario::evaluationLevels(placed);
  for (const EvaluationLevel& level : levels) {
    io::saveRoi((dir / ("roi_" + level.name + ".yaml")).string(), level.roi);
    for (const Box& b : level.roi.boxes())
      all.addBox(b);
  }
  io::saveRoi((dir / "rois.yaml").string(), all);

  std::cout << summary(placed) << "\n";
  std::cout << "wrote " << (dir / geometry_file).string()
            << ", anatomy.json, rois.yaml and " << levels.size() << " roi_<level>.yaml ("
            << all.size() << " boxes); generated in " << std::setprecision(0)
            << std::fixed << make_ms << " ms\n";
  if (!o.snapshot.empty()) {
    Stopwatch render_clock;
    renderSnapshot(placed, o.snapshot);
    std::cout << "snapshot " << o.snapshot << " in " << std::setprecision(0) << std::fixed
              << render_clock.ms() << " ms\n";
  }
}

} // namespace

void addPlantCommand(CLI::App& app)
{
  auto o = std::make_shared<PlantCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "plant", "Generate or load a plant, place it, write mesh, anatomy and ROIs");
  addPlantOptions(*cmd, o->plant);
  cmd->add_option("-o,--output", o->output_dir, "Output directory")->required();
  cmd->add_option("--snapshot", o->snapshot,
                  "Also render a PNG: parts coloured, ROIs as wireframes (needs X; "
                  "without a display the tool re-runs itself under xvfb-run)")
      ->check(pngPath());
  cmd->callback([o]() { runPlant(*o); });
}

} // namespace app
} // namespace plantnbv
