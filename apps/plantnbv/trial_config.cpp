#include "trial_config.h"

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <vector>

#include <yaml-cpp/yaml.h>

#include <plantnbv/common/error.h>

namespace plantnbv {
namespace app {

namespace {

/// Reads the keys of one YAML map with a handler per key; any other key is an error.
class KeyReader {
public:
  KeyReader(const std::string& path, std::string prefix) : path_(path), prefix_(std::move(prefix)) {}

  template <typename T>
  void read(const YAML::Node& node, const std::string& key, T& value) const
  {
    try {
      value = node.as<T>();
    } catch (const YAML::Exception&) {
      throw FormatError(where(key) + ": '" + YAML::Dump(node) + "' is not a valid value");
    }
  }

  void readVector(const YAML::Node& node, const std::string& key, std::size_t n,
                  std::vector<double>& out) const
  {
    read(node, key, out);
    if (out.size() != n)
      throw FormatError(where(key) + ": expected a list of " + std::to_string(n) +
                        " numbers");
  }

  void forEach(const YAML::Node& map,
               const std::map<std::string, std::function<void(const YAML::Node&)>>& handlers) const
  {
    if (!map.IsMap())
      throw FormatError(where("") + ": expected a map of keys");
    for (const auto& item : map) {
      // Keys are names; YAML also allows lists and maps as keys (found by fuzzing).
      if (!item.first.IsScalar())
        throw FormatError(where("") + ": a key must be a name, not a list or a map");
      const std::string key = item.first.Scalar();
      const auto handler = handlers.find(key);
      if (handler == handlers.end()) {
        std::string known;
        for (const auto& h : handlers)
          known += (known.empty() ? "" : ", ") + h.first;
        throw FormatError(where(key) + ": unknown key (expected one of " + known + ")");
      }
      handler->second(item.second);
    }
  }

  std::string where(const std::string& key) const
  {
    return "'" + path_ + "' " + prefix_ + key;
  }

private:
  const std::string& path_;
  std::string prefix_;
};

} // namespace

void readTrialConfig(const YAML::Node& root, const std::string& path,
                     const std::string& prefix, TrialConfig& c)
{
  if (root.IsNull())
    return; // an empty map changes nothing
  KeyReader top(path, prefix);
  std::vector<double> v;
  std::string s;
  top.forEach(root, {
      {"camera", [&](const YAML::Node& n) { top.read(n, "camera", s); c.camera = parseCameraIntrinsics(s); }},
      {"noise", [&](const YAML::Node& n) { top.read(n, "noise", c.noise.enabled); }},
      {"views", [&](const YAML::Node& n) { top.read(n, "views", c.views); }},
      {"planner", [&](const YAML::Node& n) { top.read(n, "planner", s); c.planner = plannerKindFromName(s); }},
      {"pattern", [&](const YAML::Node& n) { top.read(n, "pattern", c.pattern); }},
      {"stop_gain_bits", [&](const YAML::Node& n) { top.read(n, "stop_gain_bits", c.stop_gain_bits); }},
      {"seed", [&](const YAML::Node& n) { top.read(n, "seed", c.seed); }},
      {"time_limit_s", [&](const YAML::Node& n) { top.read(n, "time_limit_s", c.time_limit_s); }},
      {"memory_cap_gib", [&](const YAML::Node& n) { double gib = 0; top.read(n, "memory_cap_gib", gib); c.memory_cap_bytes = gib * 1024 * 1024 * 1024; }},
      {"initial_view", [&](const YAML::Node& n) {
         KeyReader r(path, prefix + "initial_view.");
         std::vector<double> p{c.initial_view.position.x(), c.initial_view.position.y(),
                               c.initial_view.position.z()};
         const Eigen::Quaterniond& q0 = c.initial_view.orientation;
         std::vector<double> q{q0.x(), q0.y(), q0.z(), q0.w()};
         r.forEach(n, {{"position", [&](const YAML::Node& m) { r.readVector(m, "position", 3, p); }},
                       {"orientation", [&](const YAML::Node& m) { r.readVector(m, "orientation", 4, q); }}});
         try {
           c.initial_view = Pose::fromXyzQuat(p[0], p[1], p[2], q[0], q[1], q[2], q[3]);
         } catch (const InvalidArgumentError& e) {
           throw InvalidArgumentError(top.where("initial_view") + ": " + e.what());
         }
       }},
      {"sector", [&](const YAML::Node& n) {
         KeyReader r(path, prefix + "sector.");
         double angle_deg = c.sector.angle_rad * 180.0 / M_PI;
         r.forEach(n, {{"radius", [&](const YAML::Node& m) { r.read(m, "radius", c.sector.radius_m); }},
                       {"height", [&](const YAML::Node& m) { r.read(m, "height", c.sector.height_m); }},
                       {"bottom", [&](const YAML::Node& m) { r.read(m, "bottom", c.sector.bottom_m); }},
                       {"angle_deg", [&](const YAML::Node& m) { r.read(m, "angle_deg", angle_deg); }},
                       {"rows", [&](const YAML::Node& m) { r.read(m, "rows", c.grid_rows); }},
                       {"cols", [&](const YAML::Node& m) { r.read(m, "cols", c.grid_cols); }},
                       {"samples_per_cell", [&](const YAML::Node& m) { r.read(m, "samples_per_cell", c.samples_per_cell); }}});
         c.sector.angle_rad = angle_deg * M_PI / 180.0;
       }},
      {"map", [&](const YAML::Node& n) {
         KeyReader r(path, prefix + "map.");
         OccupancyMap::Config& m = c.map;
         r.forEach(n, {{"resolution", [&](const YAML::Node& x) { r.read(x, "resolution", m.resolution_m); }},
                       {"prob_hit", [&](const YAML::Node& x) { r.read(x, "prob_hit", m.prob_hit); }},
                       {"prob_miss", [&](const YAML::Node& x) { r.read(x, "prob_miss", m.prob_miss); }},
                       {"clamp_min", [&](const YAML::Node& x) { r.read(x, "clamp_min", m.clamp_min); }},
                       {"clamp_max", [&](const YAML::Node& x) { r.read(x, "clamp_max", m.clamp_max); }},
                       {"occupancy_threshold", [&](const YAML::Node& x) { r.read(x, "occupancy_threshold", m.occupancy_threshold); }},
                       {"max_range", [&](const YAML::Node& x) { r.read(x, "max_range", m.max_range_m); }}});
       }},
      {"gain", [&](const YAML::Node& n) {
         KeyReader r(path, prefix + "gain.");
         GainConfig& g = c.gain;
         r.forEach(n, {{"rays_x", [&](const YAML::Node& x) { r.read(x, "rays_x", g.rays_x); }},
                       {"rays_y", [&](const YAML::Node& x) { r.read(x, "rays_y", g.rays_y); }},
                       {"raycast_range", [&](const YAML::Node& x) { r.read(x, "raycast_range", g.raycast_range_m); }},
                       {"visibility_weighted", [&](const YAML::Node& x) { r.read(x, "visibility_weighted", g.visibility_weighted); }}});
       }},
      {"scene", [&](const YAML::Node& n) {
         KeyReader r(path, prefix + "scene.");
         r.forEach(n, {{"floor", [&](const YAML::Node& x) { r.read(x, "floor", c.scene.floor); }},
                       {"support", [&](const YAML::Node& x) { r.read(x, "support", c.scene.support); }}});
       }},
  });
}

void loadTrialConfig(const std::string& path, TrialConfig& c)
{
  if (!std::ifstream(path))
    throw IoError("cannot read trial config '" + path + "'");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw FormatError("'" + path + "' is not valid YAML: " + e.what());
  }
  if (root.IsNull())
    return; // an empty file changes nothing
  readTrialConfig(root, path, "", c);
  c.validate();
}

} // namespace app
} // namespace plantnbv
