#include <cmath>
#include <sstream>
#include <vector>

#include <plantnbv/common/error.h>
#include <plantnbv/common/number_text.h>
#include <plantnbv/io/yaml_reader.h>
#include <plantnbv/scenario/trial_config_file.h>

namespace plantnbv {
namespace scenario {

namespace {

using io::YamlReader;
using Handlers = std::map<std::string, YamlReader::Handler>;

/// A handler that reads the value into `field`.
template <typename T>
YamlReader::Handler into(const YamlReader& r, T& field, const char* expected)
{
  return [&r, &field, expected](const YAML::Node& n, const std::string& k) {
    field = r.read<T>(n, k, expected);
  };
}

/// A handler that reads a name and converts it with `parse` (whose InvalidArgumentError
/// is reported at the key).
template <typename T, typename Parse>
YamlReader::Handler parsed(const YamlReader& r, T& field, const char* expected,
                           Parse parse)
{
  return [&r, &field, expected, parse](const YAML::Node& n, const std::string& k) {
    const std::string name = r.read<std::string>(n, k, expected);
    try {
      field = parse(name);
    } catch (const InvalidArgumentError& e) {
      r.fail(k, e.what());
    }
  };
}

void readInitialView(const YamlReader& r, const YAML::Node& node, const std::string& path,
                     Viewpoint& view)
{
  std::vector<double> p{view.position.x(), view.position.y(), view.position.z()};
  const Eigen::Quaterniond& q0 = view.orientation;
  std::vector<double> q{q0.x(), q0.y(), q0.z(), q0.w()};
  r.forEach(node, path,
            {{"position", [&](const YAML::Node& n,
                              const std::string& k) { p = r.readNumbers(n, k, 3); }},
             {"orientation", [&](const YAML::Node& n, const std::string& k) {
                q = r.readNumbers(n, k, 4);
              }}});
  try {
    view = Pose::fromXyzQuat(p[0], p[1], p[2], q[0], q[1], q[2], q[3]);
  } catch (const InvalidArgumentError& e) {
    r.fail(path, e.what());
  }
}

bool sameCamera(const CameraIntrinsics& a, const CameraIntrinsics& b)
{
  return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy &&
         a.cx == b.cx && a.cy == b.cy && a.min_range_m == b.min_range_m &&
         a.max_range_m == b.max_range_m;
}

std::string cameraSpec(const CameraIntrinsics& camera)
{
  for (const char* preset : {"l515", "l515-640", "l515-320"})
    if (sameCamera(camera, parseCameraIntrinsics(preset)))
      return preset;
  return std::to_string(camera.width) + "x" + std::to_string(camera.height) + ":" +
         shortestText(camera.fx) + "," + shortestText(camera.fy) + "," +
         shortestText(camera.cx) + "," + shortestText(camera.cy);
}

const char* boolText(bool b)
{
  return b ? "true" : "false";
}

} // namespace

void readTrialConfig(const YamlReader& r, const YAML::Node& root, const std::string& path,
                     TrialConfig& c)
{
  if (root.IsNull())
    return; // an empty map changes nothing
  const char* number = "a number";
  const char* integer = "an integer";
  const char* boolean = "true or false";
  r.forEach(
      root, path,
      {{"camera", parsed(r, c.camera, "a camera", parseCameraIntrinsics)},
       {"noise", into(r, c.noise.enabled, boolean)},
       {"depth_scale", into(r, c.depth_scale, number)},
       {"views", into(r, c.views, integer)},
       {"planner", parsed(r, c.planner, "a planner", plannerKindFromName)},
       {"pattern", into(r, c.pattern, integer)},
       {"roi_source",
        parsed(r, c.roi_source.kind, "an ROI source", roiSourceKindFromName)},
       {"roi_sigma", into(r, c.roi_source.sigma_m, number)},
       {"roi_scale", into(r, c.roi_source.scale, number)},
       {"detector_recall", into(r, c.roi_source.detector_recall, number)},
       {"detector_false_positives",
        into(r, c.roi_source.detector_false_positives, number)},
       {"detector_box_jitter", into(r, c.roi_source.detector_box_jitter_px, number)},
       {"detector_mask_dilation",
        into(r, c.roi_source.detector_mask_dilation_px, integer)},
       {"detector_masks", into(r, c.roi_source.detector_masks, boolean)},
       {"prior_internode", into(r, c.roi_source.prior_internode_m, number)},
       {"detections_explore_views",
        into(r, c.roi_source.detections_explore_views, integer)},
       {"stop_gain_bits", into(r, c.stop_gain_bits, number)},
       {"explore_share", into(r, c.explore_share, number)},
       {"view_spacing", into(r, c.view_spacing_m, number)},
       {"seed", into(r, c.seed, "a seed (integer >= 0)")},
       {"time_limit_s", into(r, c.time_limit_s, number)},
       {"memory_cap_gib",
        [&](const YAML::Node& n, const std::string& k) {
          c.memory_cap_bytes = r.read<double>(n, k, number) * 1024 * 1024 * 1024;
        }},
       {"initial_view",
        [&](const YAML::Node& n, const std::string& k) {
          readInitialView(r, n, k, c.initial_view);
        }},
       {"sector",
        [&](const YAML::Node& n, const std::string& k) {
          double angle_deg = c.sector.angle_rad * 180.0 / M_PI;
          r.forEach(n, k,
                    {{"radius", into(r, c.sector.radius_m, number)},
                     {"height", into(r, c.sector.height_m, number)},
                     {"bottom", into(r, c.sector.bottom_m, number)},
                     {"angle_deg", into(r, angle_deg, number)},
                     {"rows", into(r, c.grid_rows, integer)},
                     {"cols", into(r, c.grid_cols, integer)},
                     {"samples_per_cell", into(r, c.samples_per_cell, integer)}});
          c.sector.angle_rad = angle_deg * M_PI / 180.0;
        }},
       {"map",
        [&](const YAML::Node& n, const std::string& k) {
          OccupancyMap::Config& m = c.map;
          r.forEach(n, k,
                    {{"resolution", into(r, m.resolution_m, number)},
                     {"prob_hit", into(r, m.prob_hit, number)},
                     {"prob_miss", into(r, m.prob_miss, number)},
                     {"clamp_min", into(r, m.clamp_min, number)},
                     {"clamp_max", into(r, m.clamp_max, number)},
                     {"occupancy_threshold", into(r, m.occupancy_threshold, number)},
                     {"max_range", into(r, m.max_range_m, number)}});
        }},
       {"gain",
        [&](const YAML::Node& n, const std::string& k) {
          GainConfig& g = c.gain;
          r.forEach(n, k,
                    {{"rays_x", into(r, g.rays_x, integer)},
                     {"rays_y", into(r, g.rays_y, integer)},
                     {"raycast_range", into(r, g.raycast_range_m, number)},
                     {"visibility_weighted", into(r, g.visibility_weighted, boolean)},
                     {"unknown_only", into(r, g.unknown_only, boolean)},
                     {"unknown_depth", into(r, g.unknown_depth, integer)}});
        }},
       {"scene", [&](const YAML::Node& n, const std::string& k) {
          r.forEach(n, k,
                    {{"floor", into(r, c.scene.floor, boolean)},
                     {"support", into(r, c.scene.support, boolean)}});
        }}});
}

std::string trialConfigText(const TrialConfig& c)
{
  const auto n = &shortestText;
  const Eigen::Vector3d& p = c.initial_view.position;
  const Eigen::Quaterniond& q = c.initial_view.orientation;
  const OccupancyMap::Config& m = c.map;
  const GainConfig& g = c.gain;
  std::ostringstream s;
  s << "camera: " << cameraSpec(c.camera) << "\n"
    << "noise: " << boolText(c.noise.enabled) << "\n"
    << "views: " << c.views << "\n"
    << "depth_scale: " << n(c.depth_scale) << "\n"
    << "planner: " << plannerKindName(c.planner) << "\n"
    << "pattern: " << c.pattern << "\n"
    << "roi_source: " << roiSourceKindName(c.roi_source.kind) << "\n"
    << "roi_sigma: " << n(c.roi_source.sigma_m) << "\n"
    << "roi_scale: " << n(c.roi_source.scale) << "\n"
    << "detector_recall: " << n(c.roi_source.detector_recall) << "\n"
    << "detector_false_positives: " << n(c.roi_source.detector_false_positives) << "\n"
    << "detector_box_jitter: " << n(c.roi_source.detector_box_jitter_px) << "\n"
    << "detector_mask_dilation: " << c.roi_source.detector_mask_dilation_px << "\n"
    << "detector_masks: " << (c.roi_source.detector_masks ? "true" : "false") << "\n"
    << "prior_internode: " << n(c.roi_source.prior_internode_m) << "\n"
    << "detections_explore_views: " << c.roi_source.detections_explore_views << "\n"
    << "stop_gain_bits: " << n(c.stop_gain_bits) << "\n"
    << "explore_share: " << n(c.explore_share) << "\n"
    << "view_spacing: " << n(c.view_spacing_m) << "\n"
    << "seed: " << c.seed << "\n"
    << "time_limit_s: " << n(c.time_limit_s) << "\n"
    << "memory_cap_gib: " << n(c.memory_cap_bytes / (1024.0 * 1024.0 * 1024.0)) << "\n"
    << "initial_view: {position: [" << n(p.x()) << ", " << n(p.y()) << ", " << n(p.z())
    << "], orientation: [" << n(q.x()) << ", " << n(q.y()) << ", " << n(q.z()) << ", "
    << n(q.w()) << "]}\n"
    << "sector: {radius: " << n(c.sector.radius_m) << ", height: " << n(c.sector.height_m)
    << ", bottom: " << n(c.sector.bottom_m)
    << ", angle_deg: " << n(c.sector.angle_rad * 180.0 / M_PI)
    << ", rows: " << c.grid_rows << ", cols: " << c.grid_cols
    << ", samples_per_cell: " << c.samples_per_cell << "}\n"
    << "map: {resolution: " << n(m.resolution_m) << ", prob_hit: " << n(m.prob_hit)
    << ", prob_miss: " << n(m.prob_miss) << ", clamp_min: " << n(m.clamp_min)
    << ", clamp_max: " << n(m.clamp_max)
    << ", occupancy_threshold: " << n(m.occupancy_threshold)
    << ", max_range: " << n(m.max_range_m) << "}\n"
    << "gain: {rays_x: " << g.rays_x << ", rays_y: " << g.rays_y
    << ", raycast_range: " << n(g.raycast_range_m)
    << ", visibility_weighted: " << boolText(g.visibility_weighted)
    << ", unknown_only: " << boolText(g.unknown_only)
    << ", unknown_depth: " << g.unknown_depth << "}\n"
    << "scene: {floor: " << boolText(c.scene.floor)
    << ", support: " << boolText(c.scene.support) << "}\n";
  return s.str();
}

void loadTrialConfig(const std::string& path, TrialConfig& config)
{
  const YamlReader reader(path);
  const YAML::Node root = reader.parse(YamlReader::readText(path));
  readTrialConfig(reader, root, "", config);
  config.validate();
}

} // namespace scenario
} // namespace plantnbv
