// plantnbv plan: the next-best view on a saved map: candidates on the cylindrical sector,
// their gains inside the ROI, the best view and the ranking (text or JSON).

#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <octomap/OcTree.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/camera/optical_frame.h>
#include <plantnbv/common/error.h>
#include <plantnbv/common/roi_kind.h>
#include <plantnbv/common/stopwatch.h>
#include <plantnbv/experiment/trial.h>
#include <plantnbv/io/file_kind.h>
#include <plantnbv/io/frames_folder.h>
#include <plantnbv/io/roi_io.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/plant/plant_rois.h>
#include <plantnbv/scenario/trial_config_file.h>
#include <plantnbv/scenario/trial_setup.h>
#include <plantnbv/session/active_vision_session.h>
#include <plantnbv/session/leaf_node_prior.h>

#include "cli_checks.h"
#include "commands.h"
#include "map_file.h"
#include "roi_source_options.h"

namespace plantnbv {
namespace app {

namespace {

struct PlanOptions {
  std::string map;
  std::optional<std::string> roi; ///< default: whole_plant
  std::string config_file;
  std::vector<double> sector_base;
  std::optional<double> sector_radius;
  std::optional<double> sector_height;
  std::optional<double> sector_angle_deg;
  std::optional<double> facing_deg;
  std::optional<int> candidates;
  std::vector<double> current_pose;
  std::optional<double> travel_cost;
  std::string visited;
  std::string stem_roi; ///< prior: boxes of detected stem parts
  std::string camera = "l515-640";
  std::optional<std::uint64_t> seed;
  std::optional<int> threads;
  scenario::RoiSourceOverrides roi_source;
  bool json = false;
  bool pose_only = false;
  int top = 0;
};

/// --roi: an ROI file, whole_plant or main_stem. \throws InvalidArgumentError naming it.
scenario::Attention parseRoiOption(const std::string& spec)
{
  try {
    return scenario::Attention::parse(spec);
  } catch (const InvalidArgumentError& e) {
    throw InvalidArgumentError(std::string("--roi: ") + e.what());
  }
}

/// A vertical stem at the sector's axis: what the boxes of plant_rois.h are placed
/// around when no plant is known.
Plant plantOnAxis(const Eigen::Vector3d& axis_base)
{
  Plant axis;
  axis.base_position = axis_base;
  axis.anatomy.stem_axis = {axis_base, axis_base + Eigen::Vector3d(0.0, 0.0, 1.0)};
  return axis;
}

/// The ROI: a file, or the paper's whole-plant / main-stem box on the sector's axis.
Roi planRoi(const scenario::Attention& attention, const std::string& spec,
            const Eigen::Vector3d& axis_base)
{
  if (!attention.kind)
    return io::loadRoi(attention.file);
  const Plant axis = plantOnAxis(axis_base);
  switch (*attention.kind) {
  case RoiKind::whole_plant:
    return wholePlantRoi(axis);
  case RoiKind::main_stem:
    return mainStemRoi(axis);
  default:
    throw InvalidArgumentError(
        "--roi " + spec +
        ": leaf nodes and fruit are where a plant's anatomy puts them; "
        "give them as an ROI file (YAML boxes, docs/real-robot.md), or whole_plant / "
        "main_stem for the boxes on the sector's axis");
  }
}

/// The --roi boxes the ROI source starts from, checked against the source before the map
/// is read: detections and detections+prior need a file of detections' boxes, and the
/// prior alone takes none.
Roi givenRoi(const PlanOptions& o, const RoiSource& source,
             const Eigen::Vector3d& axis_base)
{
  const std::string option =
      std::string("--roi-source ") + roiSourceKindName(source.kind);
  if (source.kind == RoiSourceKind::prior && o.roi)
    throw InvalidArgumentError(
        option + ": the prior predicts the ROI from the map, --roi " + *o.roi +
        " is not used (detections+prior adds a --roi file of "
        "detections to the prediction)");
  const std::string spec = o.roi.value_or("whole_plant");
  const scenario::Attention attention = parseRoiOption(spec);
  const Roi given = planRoi(attention, spec, axis_base);
  if (source.detects() && (!o.roi || attention.kind))
    throw InvalidArgumentError(option +
                               ": give the detections' 3D boxes as --roi FILE "
                               "(`plantnbv integrate FRAMES --roi-out ROI.yaml` fuses a "
                               "frames folder's)");
  return source.kind == RoiSourceKind::prior ? Roi() : given;
}

/// The attended ROI: oracle and noisy take the given boxes (the noisy draw seeded by
/// --seed); detections takes them as they are; prior predicts leaf nodes along the stem
/// in the map (or along the detected stem parts of --stem-roi), and detections+prior
/// adds the given boxes to that prediction.
Roi attendedRoi(const Roi& given, const Roi& stem, const TrialConfig& config,
                const OccupancyMap& map)
{
  const RoiSource& source = config.roi_source;
  if (!source.predicts())
    return source.kind == RoiSourceKind::detections
               ? given
               : source.apply(given, roiSourceSeed(config.seed));
  CloudXYZ occupied_W;
  map.getOccupiedVoxelCentres(occupied_W);
  LeafNodePrior prior(source.priorConfig());
  prior.setStemObservations(stem);
  return prior.predictAround(given, occupied_W, config.sector.axis_base,
                             config.sector.height_m);
}

Pose parsePose(const std::vector<double>& v, const char* what)
{
  if (v.size() != 7)
    throw InvalidArgumentError(std::string(what) + " needs 7 numbers x,y,z,qx,qy,qz,qw");
  try {
    return Pose::fromXyzQuat(v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
  } catch (const InvalidArgumentError& e) {
    throw InvalidArgumentError(std::string(what) + ": " + e.what());
  }
}

nlohmann::json poseJson(const Pose& p)
{
  const Eigen::Quaterniond& q = p.orientation;
  return {p.position.x(), p.position.y(), p.position.z(), q.x(), q.y(), q.z(), q.w()};
}

nlohmann::json viewJson(const RankedView& r)
{
  return {{"index", r.index},
          {"gain", std::isnan(r.gain.gain) ? nlohmann::json(nullptr)
                                           : nlohmann::json(r.gain.gain)},
          {"voxels_seen", r.gain.voxels_seen},
          {"unknown_seen", r.gain.unknown_seen},
          {"optical_pose", poseJson(r.optical_pose)},
          {"viewpoint", poseJson(r.viewpoint)}};
}

/// Whether any box of the ROI overlaps the map's known volume.
bool roiMeetsMap(const Roi& roi, const OccupancyMap& map)
{
  const octomap::OcTree& tree = map.getOcTree();
  if (tree.size() == 0)
    return false;
  double x0, y0, z0, x1, y1, z1;
  tree.getMetricMin(x0, y0, z0);
  tree.getMetricMax(x1, y1, z1);
  for (const Box& b : roi.boxes()) {
    const Eigen::Vector3d lo = b.min(), hi = b.max();
    if (lo.x() <= x1 && hi.x() >= x0 && lo.y() <= y1 && hi.y() >= y0 && lo.z() <= z1 &&
        hi.z() >= z0)
      return true;
  }
  return false;
}

void runPlan(const PlanOptions& o)
{
  requireMapExtension(o.map, "--map");
  if (o.top < 0)
    throw InvalidArgumentError("--top " + std::to_string(o.top) +
                               ": expected K >= 0 (0: every candidate)");
  TrialConfig config;
  if (!o.config_file.empty())
    scenario::loadTrialConfig(o.config_file, config);
  CylindricalSector& sector = config.sector;
  if (!o.sector_base.empty()) {
    if (o.sector_base.size() != 3)
      throw InvalidArgumentError("--sector-base needs 3 numbers x,y,z");
    sector.axis_base =
        Eigen::Vector3d(o.sector_base[0], o.sector_base[1], o.sector_base[2]);
  }
  if (o.sector_radius)
    sector.radius_m = *o.sector_radius;
  if (o.sector_height)
    sector.height_m = *o.sector_height;
  if (o.sector_angle_deg)
    sector.angle_rad = *o.sector_angle_deg * M_PI / 180.0;
  if (o.facing_deg)
    sector.facing_rad = *o.facing_deg * M_PI / 180.0;
  if (o.candidates)
    scenario::setCandidateCount(*o.candidates, "--candidates", config);
  if (o.seed)
    config.seed = *o.seed;
  if (o.threads)
    config.threads = *o.threads;
  sector.validate();
  const CameraIntrinsics camera = io::extensionOf(o.camera) == ".yaml"
                                      ? io::readCameraInfo(o.camera).intrinsics
                                      : parseCameraIntrinsics(o.camera);
  std::optional<Pose> current;
  if (!o.current_pose.empty())
    current = parsePose(o.current_pose, "--current-pose");
  o.roi_source.applyTo(config.roi_source, "--");
  const Roi given = givenRoi(o, config.roi_source, sector.axis_base);
  if (!o.stem_roi.empty() && !config.roi_source.predicts())
    throw InvalidArgumentError(
        "--stem-roi: only the prior and detections+prior ROI sources use it "
        "(--roi-source is " +
        std::string(roiSourceKindName(config.roi_source.kind)) + ")");
  const Roi stem = o.stem_roi.empty() ? Roi() : io::loadRoi(o.stem_roi);

  ActiveVisionSession session(sessionConfigOf(config));
  session.setCamera(camera);
  if (o.travel_cost) {
    if (!current)
      throw InvalidArgumentError("--travel-cost needs --current-pose");
    auto planner = std::make_shared<AttentionNbvPlanner>();
    planner->setTravelCostWeight(*o.travel_cost);
    session.setPlanner(planner);
  }
  if (current)
    session.setCurrentView(bodyFrame(*current));
  // A saved map keeps no poses: the view spacing and the detections' exploring views
  // need the frames' positions (--visited). Exploring ranks by the gain in the paper's
  // whole-plant box on the sector's axis, as a trial's planner does on its plant's.
  if (auto* nbv = dynamic_cast<AttentionNbvPlanner*>(&session.getPlanner())) {
    nbv->setViewSpacing(config.view_spacing_m);
    nbv->setExploration(config.explore_share,
                        wholePlantRoi(plantOnAxis(sector.axis_base)));
    nbv->setExplorationViews(config.roi_source.explorationViews());
    if (!o.visited.empty())
      for (const io::StampedPose& p : io::readTumTrajectory(o.visited))
        nbv->addVisitedPosition(p.pose.position);
  }
  Stopwatch read_clock;
  const bool has_probabilities = session.readMap(o.map);
  const double read_ms = read_clock.ms();
  if (!has_probabilities)
    std::cerr << "warning: '" << o.map
              << "' is a .bt map (occupied / free only): the planner sees no uncertainty "
                 "in it; `plantnbv integrate` writes .ot maps that keep it\n";
  const Roi roi = attendedRoi(given, stem, config, *session.getMap());
  const auto* nbv = dynamic_cast<const AttentionNbvPlanner*>(&session.getPlanner());
  const std::size_t views_taken = session.getPlanner().getVisitedPositions().size();
  const std::string explore_reason =
      nbv && nbv->exploresTheFirstViews()
          ? "--roi-source detections, " + std::to_string(views_taken) +
                (views_taken == 1 ? " view" : " views") + " taken (--visited)"
          : "the config's explore_share";
  session.setRoi(roi);
  const bool meets = roiMeetsMap(roi, *session.getMap());

  NextBestView next;
  try {
    session.nextBestView(next);
  } catch (const Error& e) { // e.g. a map too large to plan on: name it
    throw Error("--map '" + o.map + "': " + e.what());
  }
  const NextViewResult& r = next.result;
  const std::string roi_name = config.roi_source.kind == RoiSourceKind::prior
                                   ? "prior"
                                   : o.roi.value_or("whole_plant");
  bool all_zero = true;
  for (const RankedView& v : next.ranking)
    all_zero = all_zero && v.gain.gain == 0.0;
  const std::size_t shown =
      o.top > 0 ? std::min<std::size_t>(std::size_t(o.top), next.ranking.size())
                : next.ranking.size();
  const char* zero_note =
      "every candidate has gain 0 (no ray of any candidate reaches the ROI): the best "
      "view is the first candidate";

  if (o.pose_only) {
    const Pose& p = next.ranking.front().optical_pose;
    const Eigen::Quaterniond& q = p.orientation;
    std::cout << std::setprecision(17) << p.position.x() << "," << p.position.y() << ","
              << p.position.z() << "," << q.x() << "," << q.y() << "," << q.z() << ","
              << q.w() << "\n";
    return;
  }
  if (o.json) {
    nlohmann::json j;
    j["map"] = o.map;
    j["roi"] = roi_name;
    j["roi_source"] = roiSourceKindName(config.roi_source.kind);
    j["attended_roi"] = roiBoxesJson(roi);
    j["roi_meets_map"] = meets;
    j["explored"] = r.explored;
    j["all_gains_zero"] = all_zero;
    j["best"] = viewJson(next.ranking.front());
    j["candidates"] = nlohmann::json::array();
    for (std::size_t i = 0; i < shown; ++i) {
      nlohmann::json c = viewJson(next.ranking[i]);
      if (current)
        c["distance_m"] = (next.ranking[i].viewpoint.position - current->position).norm();
      j["candidates"].push_back(c);
    }
    j["timings_ms"] = {{"read_map", read_ms},
                       {"snapshot", r.update_ms},
                       {"gain", r.gain_ms},
                       {"plan", r.total_ms}};
    std::cout << j.dump(2) << "\n";
    return;
  }
  const auto printPose = [](const Pose& p) {
    const Eigen::Quaterniond& q = p.orientation;
    std::ostringstream s;
    s << std::fixed << std::setprecision(4) << p.position.x() << " " << p.position.y()
      << " " << p.position.z() << " " << q.x() << " " << q.y() << " " << q.z() << " "
      << q.w();
    return s.str();
  };
  std::cout << "map '" << o.map << "' ("
            << session.getMap()->getConfig().resolution_m * 1000.0 << " mm, read in "
            << std::fixed << std::setprecision(1) << read_ms << " ms), ROI " << roi_name
            << " (" << roi.boxes().size() << " boxes), " << r.candidates.size()
            << " candidates, planned in " << r.total_ms << " ms (snapshot " << r.update_ms
            << " ms)\n";
  if (!meets)
    std::cout << "note: the ROI lies outside the map's known volume\n";
  if (all_zero)
    std::cout << "note: " << zero_note << "\n";
  if (r.explored)
    std::cout << "note: exploring (" << explore_reason
              << "): the best view has the most gain in the whole plant's box; the gains "
                 "below are the ROI's\n";
  const RankedView& best = next.ranking.front();
  std::cout << "best view: candidate " << best.index << ", gain " << std::setprecision(1)
            << best.gain.gain << " bits, " << best.gain.voxels_seen
            << " ROI voxels seen\n"
            << "  optical pose (x y z qx qy qz qw, as groundtruth.txt): "
            << printPose(best.optical_pose) << "\n"
            << "  viewpoint (body frame, x forward, z up):             "
            << printPose(best.viewpoint) << "\n";
  std::cout << "rank  index  gain_bits  voxels_seen  optical pose (x y z qx qy qz qw)\n";
  for (std::size_t i = 0; i < shown; ++i) {
    const RankedView& v = next.ranking[i];
    std::cout << std::setw(4) << i << "  " << std::setw(5) << v.index << "  "
              << std::setw(9) << std::setprecision(1) << v.gain.gain << "  "
              << std::setw(11) << v.gain.voxels_seen << "  " << printPose(v.optical_pose)
              << "\n";
  }
}

} // namespace

void addPlanCommand(CLI::App& app)
{
  auto o = std::make_shared<PlanOptions>();
  CLI::App* cmd = app.add_subcommand(
      "plan", "The next-best view on a map: sample candidates on the sector, compute "
              "their gains inside the ROI, print the best view and the ranking");
  cmd->add_option("--map", o->map, "Map (.ot from `plantnbv integrate`)")->required();
  cmd->add_option("--roi", o->roi,
                  "ROI file (YAML boxes, world frame), or whole_plant / main_stem: the "
                  "paper's box on the sector's axis (default whole_plant)");
  cmd->add_option("--config", o->config_file,
                  "Trial config (YAML, e.g. data/paper.yaml): map, sector, gain");
  cmd->add_option("--sector-base", o->sector_base,
                  "The plant's base on the sector's axis x,y,z (default 1,0,0.8)")
      ->delimiter(',')
      ->expected(3);
  cmd->add_option("--sector-radius", o->sector_radius, "Sector radius in metres (0.4)");
  cmd->add_option("--sector-height", o->sector_height, "Sector height in metres (0.7)");
  cmd->add_option("--sector-angle-deg", o->sector_angle_deg,
                  "Sector opening angle in degrees (90)");
  cmd->add_option("--facing-deg", o->facing_deg,
                  "Azimuth of the sector's centre seen from the axis, degrees (default: "
                  "facing the world origin)");
  cmd->add_option("--candidates", o->candidates,
                  "Candidates: a multiple of the grid cells (27 on the 3x3 grid)");
  cmd->add_option("--current-pose", o->current_pose,
                  "The camera's optical pose now x,y,z,qx,qy,qz,qw (as groundtruth.txt)")
      ->delimiter(',')
      ->expected(7);
  cmd->add_option(
      "--travel-cost", o->travel_cost,
      "Bits per metre of travel from --current-pose subtracted from the gain");
  cmd->add_option("--visited", o->visited,
                  "Where the frames were taken from: a TUM trajectory (a frames folder's "
                  "groundtruth.txt); the best view is chosen at least the config's "
                  "view_spacing (0.2 m) from them when a candidate is");
  cmd->add_option("--camera", o->camera,
                  "The candidates' camera: camera.yaml, l515, l515-640, l515-320 or "
                  "WxH:fx,fy,cx,cy")
      ->capture_default_str();
  cmd->add_option("--seed", o->seed,
                  "Seed of the candidates' draw and of a noisy ROI (default 0)")
      ->check(unsignedInteger());
  cmd->add_option("--threads", o->threads, "Threads (default: all cores)")
      ->transform(threadCount("--threads"));
  addRoiSourceOptions(*cmd, o->roi_source, "--seed", RoiSourceInput::roi_file);
  cmd->add_option("--stem-roi", o->stem_roi,
                  "prior: your detector's main-stem finds as an ROI file (`integrate "
                  "--roi-out STEM.yaml --roi-class main_stem`): the stem runs through "
                  "their centres instead of the occupied voxels near the sector's axis");
  cmd->add_flag("--json", o->json, "One JSON object: best, candidates, timings");
  cmd->add_flag("--pose-only", o->pose_only,
                "Print only the best optical pose x,y,z,qx,qy,qz,qw (for scripts)")
      ->excludes("--json");
  cmd->add_option("--top", o->top, "Show only the K best candidates (0: all)")
      ->capture_default_str();
  cmd->callback([o]() { runPlan(*o); });
}

} // namespace app
} // namespace plantnbv
