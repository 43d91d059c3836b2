// plantnbv reconstruct: one trial (capture at v0, then plan -> capture -> insert up to
// the view budget), scored after every view; writes steps.csv, summary.json, the map and
// the reconstruction.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/file_io.h>
#include <plantnbv/common/number_text.h>
#include <plantnbv/common/roi_kind.h>
#include <plantnbv/experiment/trial.h>
#include <plantnbv/io/cloud_io.h>
#include <plantnbv/io/frames_folder.h>
#include <plantnbv/io/roi_io.h>
#include <plantnbv/metrics/reconstruction_metrics.h>
#include <plantnbv/scenario/trial_setup.h>
#include <plantnbv/viz/snapshot.h>

#include "cli_checks.h"
#include "commands.h"
#include "frames_out.h"
#include "plant_options.h"
#include "roi_source_options.h"
#include "sensor_options.h"

namespace plantnbv {
namespace app {

namespace {

using scenario::PlacedPlant;

struct ReconstructOptions {
  PlantOptions plant;
  scenario::TrialOverrides trial;
  std::string attention = "whole_plant";
  SensorOptions sensor;
  std::string output_dir;
  std::string snapshot;
  std::string frames_out;
  double row_spacing_m = 0.0;
};

TrialConfig trialConfig(const ReconstructOptions& o, const PlacedPlant& placed)
{
  scenario::TrialOverrides overrides = o.trial;
  overrides.camera = intrinsicsOf(o.sensor);
  if (o.sensor.noise)
    overrides.noise = true;
  if (o.sensor.no_background)
    overrides.background = false;
  TrialConfig c = scenario::makeTrialConfig(overrides, placed, "--");
  if (!o.frames_out.empty() && !o.trial.depth_scale && c.depth_scale == 0.0) {
    c.depth_scale = 1000.0; // frames replay to the map only if depth is rounded as PNGs
    c.validate();
  }
  return c;
}

std::string csvNumber(double x)
{
  return std::isnan(x) ? std::string() : shortestText(x);
}

void writeSteps(const std::filesystem::path& path, const TrialResult& r)
{
  AtomicFile file(path);
  std::ostream& out = file.stream();
  out << "view,x,y,z,qx,qy,qz,qw,gain,unknown_seen,candidates,plan_ms,capture_ms,"
         "insert_ms,eval_ms,occupied_voxels";
  for (const std::string& level : r.level_names)
    out << "," << level << "_precision," << level << "_recall," << level << "_f1,"
        << level << "_chamfer";
  for (PartLabel organ : evaluatedOrgans())
    out << ",recall_" << partLabelName(organ);
  out << "\n";
  for (const TrialStep& s : r.steps) {
    const Eigen::Quaterniond& q = s.view.orientation;
    out << s.index;
    for (double x : {s.view.position.x(), s.view.position.y(), s.view.position.z(), q.x(),
                     q.y(), q.z(), q.w(), s.gain})
      out << "," << csvNumber(x);
    out << "," << s.unknown_seen << "," << s.candidates;
    for (double x : {s.plan_ms, s.capture_ms, s.insert_ms, s.eval_ms})
      out << "," << std::fixed << std::setprecision(3) << x << std::defaultfloat;
    out << "," << s.occupied_voxels;
    for (const LevelScore& score : s.scores)
      for (double x : {score.precision, score.recall, score.f1, score.chamfer})
        out << "," << csvNumber(x);
    for (const OrganRecall& organ : s.organs)
      out << "," << csvNumber(organ.recall);
    out << "\n";
  }
  file.commit();
}

nlohmann::json summaryJson(const ReconstructOptions& o, const PlacedPlant& placed,
                           const TrialConfig& c, const scenario::Attention& attention,
                           const Trial& trial, const TrialResult& r)
{
  nlohmann::json j;
  j["tool"] = {{"version", toolVersion()}, {"commit", toolCommit()}};
  j["plant"] = {
      {"name", placed.plant.name},
      {"description", placed.description},
      {"yaw_deg", placed.source.yaw_deg},
      {"base", {placed.source.base.x(), placed.source.base.y(), placed.source.base.z()}},
      {"keep_frame", placed.source.keep_frame},
      {"row_spacing", o.row_spacing_m}};
  const CylindricalSector& sector = trial.getSector();
  j["config"] = {
      {"planner", plannerKindName(c.planner)},
      {"pattern", c.pattern},
      {"attention", attention.name()},
      {"roi_source",
       {{"type", roiSourceKindName(c.roi_source.kind)},
        {"sigma", c.roi_source.sigma_m},
        {"scale", c.roi_source.scale},
        {"detector_recall", c.roi_source.detector_recall},
        {"detector_false_positives", c.roi_source.detector_false_positives},
        {"detector_box_jitter", c.roi_source.detector_box_jitter_px},
        {"detector_mask_dilation", c.roi_source.detector_mask_dilation_px},
        {"detector_masks", c.roi_source.detector_masks},
        {"prior_internode", c.roi_source.prior_internode_m},
        {"detections_explore_views", c.roi_source.detections_explore_views},
        {"seed", roiSourceSeed(c.seed)}}},
      {"views", c.views},
      {"candidates", c.grid_rows * c.grid_cols * c.samples_per_cell},
      {"seed", c.seed},
      {"camera",
       {{"width", c.camera.width},
        {"height", c.camera.height},
        {"fx", c.camera.fx},
        {"fy", c.camera.fy},
        {"cx", c.camera.cx},
        {"cy", c.camera.cy},
        {"min_range", c.camera.min_range_m},
        {"max_range", c.camera.max_range_m}}},
      {"noise", c.noise.enabled},
      {"background", c.scene.floor || c.scene.support},
      {"depth_scale", c.depth_scale},
      {"resolution", c.map.resolution_m},
      {"max_range", c.map.max_range_m},
      {"rays", {c.gain.rays_x, c.gain.rays_y}},
      {"raycast_range", c.gain.raycast_range_m},
      {"sector",
       {{"axis_base", {sector.axis_base.x(), sector.axis_base.y(), sector.axis_base.z()}},
        {"radius", sector.radius_m},
        {"height", sector.height_m},
        // Rounded for people: 90, not 89.999999999999986 (radians in, degrees out).
        {"angle_deg", std::round(sector.angle_rad * 180.0 / M_PI * 1e9) / 1e9}}},
      {"config_file", o.trial.config_file},
  };
  // What `plantnbv sample --voxel RES --seed SEED` needs to draw the same ground truth.
  j["ground_truth"] = {{"seed", groundTruthSeed(c.seed)},
                       {"voxel", c.map.resolution_m},
                       {"points", "voxel centres"}};
  nlohmann::json levels = nlohmann::json::object();
  for (std::size_t l = 0; l < r.level_names.size(); ++l) {
    const std::vector<double> f1 = r.f1Curve(l);
    const LevelScore& last = r.steps.back().scores[l];
    auto reach = [&](double tau) {
      const int v = viewsToReach(f1, tau);
      return v < 0 ? nlohmann::json(nullptr) : nlohmann::json(v);
    };
    levels[r.level_names[l]] = {
        {"views_to_f1_0.8", reach(0.8)},
        {"views_to_f1_0.9", reach(0.9)},
        {"final_f1", last.f1},
        {"final_precision", last.precision},
        {"final_recall", last.recall},
        {"final_chamfer", std::isfinite(last.chamfer) ? nlohmann::json(last.chamfer)
                                                      : nlohmann::json(nullptr)},
        {"reference_voxels", last.reference_points},
    };
  }
  j["levels"] = levels;
  nlohmann::json organs = nlohmann::json::object();
  for (const OrganRecall& o : r.steps.back().organs)
    organs[partLabelName(o.organ)] = {{"final_recall", std::isfinite(o.recall)
                                                           ? nlohmann::json(o.recall)
                                                           : nlohmann::json(nullptr)},
                                      {"reference_voxels", o.reference_points}};
  j["organs"] = organs;
  // The boxes the planner attended to (the ROI source's output), beside the true ones.
  j["attended_roi"] = roiBoxesJson(trial.getAttendedRoi());
  double plan = 0, capture = 0, insert = 0, eval = 0;
  for (const TrialStep& s : r.steps) {
    plan += s.plan_ms;
    capture += s.capture_ms;
    insert += s.insert_ms;
    eval += s.eval_ms;
  }
  j["totals"] = {{"views", r.steps.size()},
                 {"stopped_early", r.stopped_early},
                 {"setup_ms", r.setup_ms},
                 {"plan_ms", plan},
                 {"capture_ms", capture},
                 {"insert_ms", insert},
                 {"eval_ms", eval},
                 {"total_ms", r.total_ms},
                 {"occupied_voxels", r.steps.back().occupied_voxels}};
  return j;
}

/// The reconstruction at the end of the trial: the voxels the whole-plant level scores,
/// coloured by outcome against ground truth (the floor's and the support's voxels are
/// not scored, so not shown), the attention ROI of an NBV planner and the numbered views
/// along the camera path.
void renderSnapshot(const PlacedPlant& placed, const TrialConfig& c,
                    const scenario::Attention& attention, const Roi& attention_roi,
                    const Trial& trial, const TrialResult& r, const CloudXYZ& occupied,
                    const std::string& png)
{
  const ReconstructionEvaluator& evaluator = trial.getEvaluator();
  std::size_t level = 0;
  for (std::size_t l = 0; l < r.level_names.size(); ++l)
    if (r.level_names[l] == roiKindName(RoiKind::whole_plant))
      level = l;
  VoxelOutcomes outcomes;
  evaluator.classify(occupied, level, outcomes);

  const std::string scored_title = roiTitle(r.level_names[level]);
  const bool nbv = c.planner == PlannerKind::nbv;
  const std::string roi_title = roiTitle(attention.name());
  std::ostringstream title;
  title << placed.plant.name << ": " << plannerKindName(c.planner)
        << (nbv ? ", attention " + roi_title : std::string()) << "\n"
        << r.steps.size() << " views; F1 " << scored_title << " " << std::fixed
        << std::setprecision(3) << r.steps.back().scores[level].f1;
  viz::SceneSnapshot::Config config;
  config.width = 1200;
  config.height = 1200;
  config.title = title.str();
  viz::SceneSnapshot snapshot(config);

  const viz::Rgb correct{0.0f, 0.62f, 0.45f}; // Okabe-Ito bluish green
  const viz::Rgb wrong{0.84f, 0.37f, 0.0f};   // and vermillion: apart for all eyes
  const viz::Rgb missed{0.78f, 0.78f, 0.78f};
  const viz::Rgb roi{0.0f, 0.45f, 0.70f}; // Okabe-Ito blue
  const viz::Rgb path{0.25f, 0.25f, 0.25f};
  snapshot.addPoints(outcomes.missed, missed, 1.5f);
  snapshot.addPoints(outcomes.correct, correct, 3.0f);
  snapshot.addPoints(outcomes.wrong, wrong, 3.0f);
  snapshot.addLegendEntry(
      "correct voxel (" + std::to_string(outcomes.correct.size()) + ")", correct);
  snapshot.addLegendEntry("wrong voxel (" + std::to_string(outcomes.wrong.size()) + ")",
                          wrong);
  snapshot.addLegendEntry(
      "missed ground truth (" + std::to_string(outcomes.missed.size()) + ")", missed);
  if (nbv && !attention_roi.empty()) {
    snapshot.addRoi(attention_roi, roi);
    std::ostringstream source;
    if (c.roi_source.kind == RoiSourceKind::noisy)
      source << " (noisy, sigma " << c.roi_source.sigma_m * 1000.0 << " mm)";
    snapshot.addLegendEntry("attention ROI: " + roi_title + source.str(), roi);
  }
  std::vector<Eigen::Vector3d> positions;
  for (const TrialStep& s : r.steps) {
    positions.push_back(s.view.position);
    snapshot.addCameraFrustum(s.view, c.camera.horizontalFov(), c.camera.verticalFov(),
                              0.05, path, std::to_string(s.index + 1));
  }
  snapshot.addPolyline(positions, path);
  snapshot.addLegendEntry("views 1-" + std::to_string(r.steps.size()) + " in order",
                          path);
  snapshot.render(png);
}

void runReconstruct(const ReconstructOptions& o)
{
  if (!o.snapshot.empty())
    requireDisplayOrReexec();
  const PlacedPlant placed = placePlant(o.plant);
  const TrialConfig config = trialConfig(o, placed);
  scenario::Attention attention;
  try {
    attention = scenario::Attention::parse(o.attention);
  } catch (const InvalidArgumentError& e) {
    throw InvalidArgumentError(std::string("--attention: ") + e.what());
  }
  const Roi attention_roi = scenario::attentionRoi(placed, attention);
  std::optional<io::FramesFolderWriter> frames;
  if (!o.frames_out.empty()) {
    frames.emplace(o.frames_out,
                   framesCamera(o.frames_out, config.camera, config.depth_scale));
    if (frames->frameCount() > 0)
      throw InvalidArgumentError("--frames-out '" + o.frames_out + "' already holds " +
                                 std::to_string(frames->frameCount()) +
                                 " frames: give a new folder, so that it replays to "
                                 "this trial's map");
  }
  const std::filesystem::path dir(o.output_dir);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec)
    throw IoError("cannot create output directory '" + o.output_dir +
                  "': " + ec.message());

  Trial trial(config);
  if (frames)
    trial.setFrameCallback([&](const TrialFrame& f) {
      frames->append(*f.depth, f.T_W_O, double(f.index), f.detections);
    });
  const std::vector<EvaluationLevel> levels = scenario::evaluationLevels(placed);
  for (const std::string& w :
       scenario::trialWarnings(placed, config, attention_roi, levels))
    std::cerr << "plantnbv: warning: " << w << "\n";
  scenario::setUpTrial(placed, attention_roi, levels, trial);
  trial.setNeighbours(scenario::rowNeighbourPlants(placed, o.row_spacing_m, config));
  std::ostringstream row;
  if (o.row_spacing_m > 0.0)
    row << ", in a row with a neighbour " << o.row_spacing_m << " m away on each side";
  std::cout << placed.plant.name << " (" << placed.description << row.str()
            << "): " << plannerKindName(config.planner)
            << (config.planner == PlannerKind::predefined
                    ? " pattern " + std::to_string(config.pattern)
                : config.planner == PlannerKind::nbv ? " attention " + attention.name()
                                                     : std::string())
            << ", " << config.views << " views, "
            << config.grid_rows * config.grid_cols * config.samples_per_cell
            << " candidates, " << config.map.resolution_m * 1000.0 << " mm, seed "
            << config.seed << "\n";
  trial.setStepCallback([&](const TrialStep& s) {
    std::ostringstream line;
    line << std::fixed << std::setprecision(0) << "view " << std::setw(2) << s.index
         << " at (" << std::setprecision(3) << s.view.position.x() << ", "
         << s.view.position.y() << ", " << s.view.position.z() << ")";
    if (s.index > 0)
      line << std::setprecision(0) << " gain " << s.gain << " bits, plan "
           << std::setprecision(1) << s.plan_ms << " ms";
    line << std::setprecision(1) << ", capture " << s.capture_ms << " ms, insert "
         << s.insert_ms << " ms, eval " << s.eval_ms << " ms |";
    for (std::size_t l = 0; l < s.scores.size(); ++l)
      line << " " << levels[l].name << " F1 " << std::setprecision(3) << s.scores[l].f1;
    std::cout << line.str() << std::endl;
  });
  TrialResult result;
  trial.run(result);

  writeSteps(dir / "steps.csv", result);
  writeFileAtomically(dir / "summary.json",
                      summaryJson(o, placed, config, attention, trial, result).dump(2) +
                          "\n");
  trial.getMap().write((dir / "map.bt").string());
  CloudXYZ occupied;
  trial.getMap().getOccupiedVoxelCentres(occupied);
  io::saveCloud((dir / "reconstruction.pcd").string(), occupied);
  std::cout << "views to reach F1 0.8 / 0.9:";
  for (std::size_t l = 0; l < result.level_names.size(); ++l) {
    const std::vector<double> f1 = result.f1Curve(l);
    auto views = [&](double tau) {
      const int v = viewsToReach(f1, tau);
      return v < 0 ? std::string("-") : std::to_string(v);
    };
    std::cout << (l ? ", " : " ") << result.level_names[l] << " " << views(0.8) << " / "
              << views(0.9);
  }
  std::cout << " (- = not within " << result.steps.size() << " views)\n";
  std::cout << std::fixed << std::setprecision(0) << "trial in " << result.total_ms
            << " ms (setup " << result.setup_ms << " ms); wrote "
            << (dir / "steps.csv").string()
            << ", summary.json, map.bt, reconstruction.pcd (" << occupied.size()
            << " occupied voxels)";
  // The folder holds this run's results only: an earlier run's picture would lie.
  const std::filesystem::path stale = dir / "snapshot.png";
  const bool overwritten =
      !o.snapshot.empty() && std::filesystem::equivalent(stale, o.snapshot, ec);
  if (!overwritten && std::filesystem::remove(stale, ec))
    std::cout << "; removed an earlier run's snapshot.png";
  std::cout << "\n";
  if (!o.snapshot.empty()) {
    renderSnapshot(placed, config, attention, trial.getAttendedRoi(), trial, result,
                   occupied, o.snapshot);
    std::cout << "snapshot " << o.snapshot << "\n";
  }
}

} // namespace

void addReconstructCommand(CLI::App& app)
{
  auto o = std::make_shared<ReconstructOptions>();
  CLI::App* cmd = app.add_subcommand(
      "reconstruct", "Run one reconstruction trial with a planner; write the steps, a "
                     "summary, the map and the reconstruction");
  addPlantOptions(*cmd, o->plant, "--plant");
  cmd->add_option("--config", o->trial.config_file,
                  "Trial config (YAML, e.g. data/paper.yaml); options below override it");
  cmd->add_option("--planner", o->trial.planner,
                  "nbv, predefined or random (default nbv)");
  cmd->add_option("--pattern", o->trial.pattern,
                  "Pattern of the predefined planner, 1-4");
  cmd->add_option(
         "--attention", o->attention,
         "ROI of the NBV planner: whole_plant, main_stem, leaf_nodes, fruit ('-' "
         "for '_' works too) or an ROI file")
      ->capture_default_str();
  cmd->add_option("--views", o->trial.views, "View budget, v0 included (default 10)");
  cmd->add_option(
      "--candidates", o->trial.candidates,
      "Candidates per step: a multiple of the grid cells (27 on the 3x3 grid)");
  cmd->add_option("--resolution", o->trial.resolution_m,
                  "Map voxel size in metres (0.003)");
  cmd->add_option("--sector-height", o->trial.sector_height_m,
                  "Height of the cylindrical sector in metres (0.7; a loaded model: "
                  "its height)");
  cmd->add_option("--row-spacing", o->row_spacing_m,
                  "Put the plant in a greenhouse row: a neighbour plant this many metres "
                  "away on each side (default 0: alone; docs/trials.md)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--sector-radius", o->trial.sector_radius_m,
                  "Distance of the views from the stem in metres (0.4; a plant over 1 m: "
                  "docs/plants.md, \"Tall models\")");
  cmd->add_option("--seed", o->trial.seed, "Seed of the trial (default 0)")
      ->check(unsignedInteger());
  cmd->add_option("--threads", o->trial.threads, "Threads (default: all cores)")
      ->transform(threadCount("--threads"));
  cmd->add_option("-o,--output", o->output_dir, "Output directory")->required();
  cmd->add_option(
      "--frames-out", o->frames_out,
      "Write every view's frame to this new frames folder (docs/real-robot.md); "
      "the trial then integrates depth rounded as the PNGs store it");
  cmd->add_option("--depth-scale", o->trial.depth_scale,
                  "Depth units per metre the trial rounds to (default 0: none; 1000 with "
                  "--frames-out)");
  addSensorOptions(*cmd, o->sensor, "the config's, else l515-640", "--seed");
  addRoiSourceOptions(*cmd, o->trial.roi, "--seed", RoiSourceInput::simulation);
  cmd->add_option("--snapshot", o->snapshot,
                  "Also render a PNG: the scored voxels coloured by outcome against "
                  "ground truth, the attention ROI, the numbered views (needs X; "
                  "without a display the tool re-runs itself under xvfb-run)")
      ->check(pngPath());
  cmd->callback([o]() { runReconstruct(*o); });
}

} // namespace app
} // namespace plantnbv
