// OccupancyMap, the candidate samplers, the planners and the active-vision session.

#include <cmath>
#include <filesystem>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/camera/optical_frame.h>
#include <plantnbv/common/error.h>
#include <plantnbv/io/frames_folder.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/planning/cylindrical_sector_sampler.h>
#include <plantnbv/planning/view_planner.h>
#include <plantnbv/session/active_vision_session.h>
#include <plantnbv/session/leaf_node_prior.h>

#include "arrays.h"
#include "bindings.h"

namespace plantnbv {
namespace python {

namespace {

using namespace pybind11::literals;
using Path = std::filesystem::path;

/// Sets the attributes of `config` (a bound Config) named by the keyword arguments; an
/// unknown name is a TypeError naming it and the known ones.
void applyKeywords(py::object config, const py::kwargs& kwargs, const char* who)
{
  for (auto item : kwargs) {
    const std::string key = py::str(item.first);
    if (key.rfind("_", 0) == 0 || !py::hasattr(config, key.c_str())) {
      std::string known;
      for (py::handle name : py::module_::import("builtins").attr("dir")(config))
        if (name.cast<std::string>().rfind("_", 0) != 0)
          known += (known.empty() ? "" : ", ") + name.cast<std::string>();
      throw py::type_error(std::string(who) + ": unknown argument '" + key +
                           "' (expected " + known + ")");
    }
    try {
      config.attr(key.c_str()) = item.second;
    } catch (py::error_already_set& e) {
      if (!e.matches(PyExc_TypeError))
        throw;
      const py::object now = config.attr(key.c_str());
      throw py::type_error(
          std::string(who) + ": " + key + ": expected " +
          py::str(py::type::handle_of(now).attr("__name__")).cast<std::string>() +
          ", got " +
          py::str(py::type::handle_of(item.second).attr("__name__")).cast<std::string>());
    }
  }
}

py::dict insertStatsDict(const OccupancyMap::InsertStats& s)
{
  return py::dict("points"_a = s.points, "non_finite"_a = s.non_finite,
                  "beyond_range"_a = s.beyond_range, "outside_map"_a = s.outside_map,
                  "free_voxels"_a = s.free_voxels,
                  "occupied_voxels"_a = s.occupied_voxels, "total_ms"_a = s.total_ms);
}

/// One value per (N, 3) point of `points`, from `f(point)`.
template <typename T, typename F>
py::array_t<T> perPoint(const py::handle& points, F&& f)
{
  const std::vector<Eigen::Vector3f> p = readPointVector(points, "points");
  py::array_t<T> out(py::ssize_t(p.size()));
  T* o = out.mutable_data();
  Locked lock;
  for (const Eigen::Vector3f& q : p)
    *o++ = f(q.cast<double>());
  return out;
}

void integrateDepth(OccupancyMap& map, const py::handle& depth,
                    const CameraIntrinsics& intrinsics, const py::handle& T_W_O)
{
  const DepthImage d = readDepth(depth, "depth");
  const Pose pose = readPose(T_W_O, "T_W_O");
  const CameraIntrinsics camera = intrinsics; // Python may change its own meanwhile
  ReleasedAndLocked lock;
  CloudXYZ cloud;
  integrateDepthFrame(map, d, camera, pose, cloud);
}

void bindMap(py::module_& m)
{
  py::class_<OccupancyMap::Config>(m, "MapConfig",
                                   "The occupancy map's parameters; defaults: the "
                                   "paper's (Table 1).")
      .def(py::init<>())
      .def_readwrite("resolution_m", &OccupancyMap::Config::resolution_m)
      .def_readwrite("prob_hit", &OccupancyMap::Config::prob_hit)
      .def_readwrite("prob_miss", &OccupancyMap::Config::prob_miss)
      .def_readwrite("clamp_min", &OccupancyMap::Config::clamp_min)
      .def_readwrite("clamp_max", &OccupancyMap::Config::clamp_max)
      .def_readwrite("occupancy_threshold", &OccupancyMap::Config::occupancy_threshold)
      .def_readwrite("max_range_m", &OccupancyMap::Config::max_range_m)
      .def("validate", &OccupancyMap::Config::validate);

  py::class_<OccupancyMap, std::shared_ptr<OccupancyMap>> map(
      m, "OccupancyMap",
      "The probabilistic occupancy map (OctoMap's OcTree, log-odds update; exactly "
      "OctoMap's insertPointCloud). Keyword arguments are MapConfig's fields.");
  map.def(py::init([](const py::kwargs& kwargs) {
       py::object config = py::cast(OccupancyMap::Config());
       applyKeywords(config, kwargs, "OccupancyMap");
       return std::make_shared<OccupancyMap>(config.cast<OccupancyMap::Config>());
     }))
      .def_property_readonly("config", &OccupancyMap::getConfig)
      .def_property_readonly(
          "resolution_m",
          [](const OccupancyMap& m) { return m.getConfig().resolution_m; })
      .def_property("threads", &OccupancyMap::getNumberOfThreads,
                    [](OccupancyMap& map, int threads) {
                      Locked lock;
                      map.setNumberOfThreads(threads);
                    })
      .def("integrate", &integrateDepth, "depth"_a, "intrinsics"_a, "T_W_O"_a,
           "Integrates an (H, W) depth image (metres; NaN or 0: no return) seen from the "
           "optical pose T_W_O (z forward, x right, y down).")
      .def(
          "insert",
          [](OccupancyMap& map, const py::handle& points, const py::handle& origin) {
            CloudXYZ cloud;
            readPoints(points, "points", cloud);
            const Eigen::Vector3d o = readVector3(origin, "origin");
            ReleasedAndLocked lock;
            map.insert(cloud, o);
          },
          "points"_a, "origin"_a,
          "Integrates (N, 3) world points seen from the sensor origin (3,).")
      .def_property_readonly("last_insert_stats",
                             [](const OccupancyMap& map) {
                               Locked lock;
                               return insertStatsDict(map.getLastInsertStats());
                             })
      .def(
          "occupied_centres",
          [](const OccupancyMap& map) {
            CloudXYZ cloud;
            {
              ReleasedAndLocked lock;
              map.getOccupiedVoxelCentres(cloud);
            }
            return pointsArray(cloud);
          },
          "The centres of the occupied voxels, (N, 3) float32: the reconstruction.")
      .def(
          "probability",
          [](const OccupancyMap& map, const py::handle& points) {
            return perPoint<double>(
                points, [&](const Eigen::Vector3d& p) { return map.probability(p); });
          },
          "points"_a,
          "The occupancy probability of the voxel of each (N, 3) point (0.5: unknown).")
      .def(
          "state",
          [](const OccupancyMap& map, const py::handle& points) {
            return perPoint<std::uint8_t>(points, [&](const Eigen::Vector3d& p) {
              return std::uint8_t(map.state(p));
            });
          },
          "points"_a, "Each point's voxel: 0 unknown, 1 free, 2 occupied (uint8).")
      .def(
          "counts",
          [](const OccupancyMap& map) {
            OccupancyMap::VoxelCounts c;
            {
              ReleasedAndLocked lock;
              c = map.countVoxels();
            }
            return py::dict("occupied"_a = c.occupied, "free"_a = c.free);
          },
          "Voxel counts at the finest resolution.")
      .def("clear",
           [](OccupancyMap& map) {
             Locked lock;
             map.clear();
           })
      .def_property_readonly("revision",
                             [](const OccupancyMap& map) {
                               Locked lock;
                               return map.revision();
                             })
      .def(
          "write",
          [](const OccupancyMap& map, const Path& path) {
            ReleasedAndLocked lock;
            map.write(path.string());
          },
          "path"_a,
          "Writes .ot (every voxel's log-odds) or .bt (occupied / free), by extension.")
      .def_static(
          "read",
          [](const Path& path, const py::kwargs& kwargs) {
            py::object config = py::cast(OccupancyMap::Config());
            applyKeywords(config, kwargs, "OccupancyMap.read");
            const auto c = config.cast<OccupancyMap::Config>();
            py::gil_scoped_release release;
            return std::shared_ptr<OccupancyMap>(OccupancyMap::read(path.string(), c));
          },
          "path"_a,
          "A map from an OctoMap file (.ot, or .bt with no uncertainty left); the "
          "resolution is the file's, other parameters MapConfig's or the keywords'.")
      .def("__repr__", [](const OccupancyMap& map) {
        Locked lock;
        const OccupancyMap::VoxelCounts c = map.countVoxels();
        return "OccupancyMap(resolution_m=" +
               std::to_string(map.getConfig().resolution_m) + ", " +
               std::to_string(c.occupied) + " occupied, " + std::to_string(c.free) +
               " free voxels)";
      });
  m.attr("UNKNOWN") = std::uint8_t(VoxelState::unknown);
  m.attr("FREE") = std::uint8_t(VoxelState::free);
  m.attr("OCCUPIED") = std::uint8_t(VoxelState::occupied);
}

void bindSamplers(py::module_& m)
{
  py::class_<CylindricalSector>(
      m, "CylindricalSector",
      "The paper's cylindrical sector around the stem where candidates lie (Table 1).")
      .def(py::init([](const py::handle& axis_base, double radius_m, double height_m,
                       double bottom_m, double angle_deg,
                       std::optional<double> facing_deg) {
             CylindricalSector s;
             s.axis_base = readVector3(axis_base, "axis_base");
             s.radius_m = radius_m;
             s.height_m = height_m;
             s.bottom_m = bottom_m;
             s.angle_rad = angle_deg * M_PI / 180.0;
             if (facing_deg)
               s.facing_rad = *facing_deg * M_PI / 180.0;
             s.validate();
             return s;
           }),
           "axis_base"_a = std::vector<double>{1.0, 0.0, 0.8}, "radius_m"_a = 0.4,
           "height_m"_a = 0.7, "bottom_m"_a = 0.0, "angle_deg"_a = 90.0,
           "facing_deg"_a = py::none())
      .def_property_readonly(
          "axis_base",
          [](const CylindricalSector& s) { return vectorArray(s.axis_base); })
      .def_readonly("radius_m", &CylindricalSector::radius_m)
      .def_readonly("height_m", &CylindricalSector::height_m)
      .def_readonly("bottom_m", &CylindricalSector::bottom_m)
      .def_property_readonly("angle_deg", [](const CylindricalSector& s) {
        return s.angle_rad * 180.0 / M_PI;
      });

  py::class_<ViewpointSampler, std::shared_ptr<ViewpointSampler>>(
      m, "ViewpointSampler", "Where a planner's candidates come from.")
      .def(
          "sample",
          [](const ViewpointSampler& s, std::uint64_t seed) {
            Rng rng(seed);
            std::vector<Viewpoint> views;
            s.sample(rng, views);
            return poseArray(views);
          },
          "seed"_a = 0, "Candidates drawn with a fresh Rng(seed): (K, 7) body poses.");
  py::class_<CylindricalSectorSampler, ViewpointSampler,
             std::shared_ptr<CylindricalSectorSampler>>(
      m, "SectorSampler",
      "Candidates on the sector, k draws per cell of a rows x cols grid (9 / 27 / 45 "
      "on 3 x 3), each looking horizontally at the stem axis.")
      .def(py::init([](const CylindricalSector& sector, int rows, int cols,
                       int samples_per_cell) {
             auto s = std::make_shared<CylindricalSectorSampler>(sector);
             s->setGrid(rows, cols);
             s->setSamplesPerCell(samples_per_cell);
             return s;
           }),
           "sector"_a = CylindricalSector(), "rows"_a = 3, "cols"_a = 3,
           "samples_per_cell"_a = 3)
      .def_property_readonly("sector", &CylindricalSectorSampler::getSector)
      .def(
          "grid_cell_centres",
          [](const CylindricalSectorSampler& s) {
            return poseArray(s.gridCellCentres());
          },
          "The rows x cols cell centres as (K, 7) body poses.")
      .def(
          "viewpoint_at",
          [](const CylindricalSectorSampler& s, double azimuth_rad, double z) {
            return poseArray(s.viewpointAt(azimuth_rad, z));
          },
          "azimuth_rad"_a, "z"_a,
          "The body pose at (azimuth, height) looking at the axis.");
  py::class_<ViewpointListSampler, ViewpointSampler,
             std::shared_ptr<ViewpointListSampler>>(
      m, "ViewpointListSampler", "The same given candidates at every step.")
      .def(py::init([](const py::handle& poses) {
             return std::make_shared<ViewpointListSampler>(readPoses(poses, "poses"));
           }),
           "poses"_a, "(K, 7) or (K, 4, 4) body poses (x forward, y left, z up).");
}

/// A planning step's candidates as arrays, ranked (the chosen first).
class PlanningStep {
public:
  explicit PlanningStep(NextBestView next) : next_(std::move(next)) {}

  py::array_t<double> viewpoints() const
  {
    return poses([](const RankedView& r) { return r.viewpoint; });
  }
  py::array_t<double> opticalPoses() const
  {
    return poses([](const RankedView& r) { return r.optical_pose; });
  }
  template <typename T, typename F>
  py::array_t<T> values(F&& f) const
  {
    std::vector<T> v;
    for (const RankedView& r : next_.ranking)
      v.push_back(f(r));
    return columnArray(v);
  }
  const NextBestView& next() const { return next_; }

private:
  template <typename F>
  py::array_t<double> poses(F&& f) const
  {
    std::vector<Pose> out;
    for (const RankedView& r : next_.ranking)
      out.push_back(f(r));
    return poseArray(out);
  }
  NextBestView next_;
};

void bindPlanners(py::module_& m)
{
  py::class_<ViewPlanner, std::shared_ptr<ViewPlanner>>(
      m, "ViewPlanner",
      "A planner: given to a Session, which sets its map, candidates, ROI and seed.")
      .def_property_readonly("name", &ViewPlanner::name);
  py::class_<AttentionNbvPlanner, ViewPlanner, std::shared_ptr<AttentionNbvPlanner>>(
      m, "NbvPlanner",
      "The attention-driven NBV planner (the paper's Algorithm 1): the candidate with "
      "the most expected information inside the ROI.")
      .def(py::init([](double stop_gain_bits, double travel_cost_weight,
                       double view_spacing_m) {
             auto p = std::make_shared<AttentionNbvPlanner>();
             p->setStopGain(stop_gain_bits);
             p->setTravelCostWeight(travel_cost_weight);
             p->setViewSpacing(view_spacing_m);
             return p;
           }),
           "stop_gain_bits"_a = 0.0, "travel_cost_weight"_a = 0.0,
           "view_spacing_m"_a = kDefaultViewSpacingM,
           "view_spacing_m: a candidate closer than this to a frame's position is chosen "
           "only if every candidate is (0: the paper's planner).");
  py::class_<PredefinedPlanner, ViewPlanner, std::shared_ptr<PredefinedPlanner>>(
      m, "PredefinedPlanner",
      "The pre-defined baseline: the grid-cell centres in one of four orders (1-4).")
      .def(py::init([](int pattern) {
             auto p = std::make_shared<PredefinedPlanner>();
             p->setPattern(pattern);
             return p;
           }),
           "pattern"_a = 1)
      .def("reset", [](PredefinedPlanner& p) {
        Locked lock;
        p.reset();
      });
  py::class_<RandomPlanner, ViewPlanner, std::shared_ptr<RandomPlanner>>(
      m, "RandomPlanner", "The random baseline: one of the freshly drawn candidates.")
      .def(py::init([] { return std::make_shared<RandomPlanner>(); }));

  py::class_<PlanningStep>(
      m, "NextBestView",
      "A planning step's candidates, ranked: the chosen one first, then by decreasing "
      "gain. Arrays have one row per candidate.")
      .def_property_readonly("viewpoints", &PlanningStep::viewpoints,
                             "(K, 7) body poses (x forward, y left, z up).")
      .def_property_readonly("optical_poses", &PlanningStep::opticalPoses,
                             "(K, 7) optical poses T_W_O: where to send the camera.")
      .def_property_readonly(
          "gains",
          [](const PlanningStep& s) {
            return s.values<double>([](const RankedView& r) { return r.gain.gain; });
          },
          "Expected information (bits); NaN where a baseline computed none.")
      .def_property_readonly("voxels_seen",
                             [](const PlanningStep& s) {
                               return s.values<std::uint64_t>([](const RankedView& r) {
                                 return r.gain.voxels_seen;
                               });
                             })
      .def_property_readonly(
          "indices",
          [](const PlanningStep& s) {
            return s.values<std::uint64_t>([](const RankedView& r) { return r.index; });
          },
          "Each candidate's index in the planner's draw.")
      .def_property_readonly("best_optical_pose",
                             [](const PlanningStep& s) {
                               return poseArray(s.next().ranking.at(0).optical_pose);
                             })
      .def_property_readonly("best_viewpoint",
                             [](const PlanningStep& s) {
                               return poseArray(s.next().ranking.at(0).viewpoint);
                             })
      .def_property_readonly(
          "gain", [](const PlanningStep& s) { return s.next().result.gain; },
          "The chosen view's gain (bits).")
      .def_property_readonly("stop",
                             [](const PlanningStep& s) { return s.next().result.stop; })
      .def_property_readonly("timings_ms",
                             [](const PlanningStep& s) {
                               const NextViewResult& r = s.next().result;
                               return py::dict(
                                   "sample"_a = r.sample_ms, "gain"_a = r.gain_ms,
                                   "update"_a = r.update_ms, "total"_a = r.total_ms);
                             })
      .def("__len__", [](const PlanningStep& s) { return s.next().ranking.size(); });
}

void bindSession(py::module_& m)
{
  using Config = ActiveVisionSession::Config;
  py::class_<Config>(m, "SessionConfig",
                     "A Session's map, candidates and planner parameters; defaults: the "
                     "paper's.")
      .def(py::init<>())
      .def_readwrite("map", &Config::map)
      .def_readwrite("sector", &Config::sector)
      .def_readwrite("grid_rows", &Config::grid_rows)
      .def_readwrite("grid_cols", &Config::grid_cols)
      .def_readwrite("samples_per_cell", &Config::samples_per_cell)
      .def_property(
          "rays_x", [](const Config& c) { return c.gain.rays_x; },
          [](Config& c, int v) { c.gain.rays_x = v; }, "Gain rays across (48).")
      .def_property(
          "rays_y", [](const Config& c) { return c.gain.rays_y; },
          [](Config& c, int v) { c.gain.rays_y = v; }, "Gain rays down (36).")
      .def_property(
          "raycast_range_m", [](const Config& c) { return c.gain.raycast_range_m; },
          [](Config& c, double v) { c.gain.raycast_range_m = v; })
      .def_property(
          "visibility_weighted",
          [](const Config& c) { return c.gain.visibility_weighted; },
          [](Config& c, bool v) { c.gain.visibility_weighted = v; })
      .def_property(
          "unknown_only", [](const Config& c) { return c.gain.unknown_only; },
          [](Config& c, bool v) { c.gain.unknown_only = v; },
          "Count only unknown voxels (True); False: the paper's entropy of every voxel.")
      .def_property(
          "unknown_depth", [](const Config& c) { return c.gain.unknown_depth; },
          [](Config& c, int v) { c.gain.unknown_depth = v; },
          "Unknown ROI voxels one ray may count (3; 0: no limit, the paper's).")
      .def_property(
          "resolution_m", [](const Config& c) { return c.map.resolution_m; },
          [](Config& c, double v) { c.map.resolution_m = v; }, "map.resolution_m")
      .def_property(
          "max_range_m", [](const Config& c) { return c.map.max_range_m; },
          [](Config& c, double v) { c.map.max_range_m = v; }, "map.max_range_m")
      .def_readwrite("seed", &Config::seed)
      .def_readwrite("threads", &Config::threads)
      .def("validate", &Config::validate);

  const auto setCamera = [](ActiveVisionSession& s, const CameraIntrinsics& camera) {
    Locked lock;
    s.setCamera(camera);
  };
  const auto setRoi = [](ActiveVisionSession& s, const py::object& roi) {
    Roi r = roi.is_none() ? Roi() : roi.cast<Roi>();
    Locked lock;
    s.setRoi(r);
  };
  py::class_<ActiveVisionSession>(
      m, "Session",
      "The active-vision loop of a robot: integrate depth frames with their poses, set "
      "the ROI, ask for the next-best view. Keyword arguments are SessionConfig's "
      "fields (or config=SessionConfig()). Defaults: the paper's map and sector, "
      "plantnbv's NBV planner (unknown voxels, views 0.2 m apart; unknown_only=False, "
      "unknown_depth=0 and NbvPlanner(view_spacing_m=0) give the paper's), the L515 at "
      "640 x 480, no ROI.")
      .def(py::init([](std::optional<Config> config, const py::kwargs& kwargs) {
             py::object c = py::cast(config ? *config : Config());
             applyKeywords(c, kwargs, "Session");
             return std::make_unique<ActiveVisionSession>(c.cast<Config>());
           }),
           "config"_a = py::none())
      .def_property_readonly("config", &ActiveVisionSession::getConfig)
      .def_property("camera", &ActiveVisionSession::getCamera, setCamera,
                    "The camera whose frusta the candidates have.")
      .def("set_camera", setCamera, "intrinsics"_a)
      .def_property("roi", &ActiveVisionSession::getRoi, setRoi,
                    "What the gain counts; None or an empty Roi: every voxel.")
      .def("set_roi", setRoi, "roi"_a, "As the roi property; may change at any time.")
      .def(
          "set_planner",
          [](ActiveVisionSession& s, ViewPlanner::Ptr planner) {
            Locked lock;
            s.setPlanner(std::move(planner));
          },
          "planner"_a, "NbvPlanner (the default), PredefinedPlanner or RandomPlanner.")
      .def(
          "set_candidates",
          [](ActiveVisionSession& s, const py::handle& poses, const std::string& frame) {
            std::vector<Pose> views = readPoses(poses, "poses");
            if (frame == "optical")
              for (Pose& p : views)
                p = bodyFrame(p);
            else if (frame != "body")
              throw InvalidArgumentError("frame: expected 'body' or 'optical', got '" +
                                         frame + "'");
            Locked lock;
            s.setCandidateSampler(
                std::make_shared<ViewpointListSampler>(std::move(views)));
          },
          "poses"_a, "frame"_a = "body",
          "Fixed candidates (e.g. a robot's reachable poses), (K, 7) or (K, 4, 4), in "
          "the body or the optical frame, instead of the sector's draws.")
      .def(
          "set_candidate_sampler",
          [](ActiveVisionSession& s, ViewpointSampler::ConstPtr sampler) {
            Locked lock;
            s.setCandidateSampler(std::move(sampler));
          },
          "sampler"_a)
      .def(
          "set_current_view",
          [](ActiveVisionSession& s, const py::handle& T_W_C) {
            const Pose pose = readPose(T_W_C, "T_W_C");
            Locked lock;
            s.setCurrentView(pose);
          },
          "T_W_C"_a, "The camera's body pose now (for a travel cost).")
      .def(
          "integrate",
          [](ActiveVisionSession& s, const py::handle& depth,
             const CameraIntrinsics& intrinsics, const py::handle& T_W_O) {
            const DepthImage d = readDepth(depth, "depth");
            const Pose pose = readPose(T_W_O, "T_W_O");
            const CameraIntrinsics camera = intrinsics;
            ReleasedAndLocked lock;
            s.integrate(d, camera, pose);
          },
          "depth"_a, "intrinsics"_a, "T_W_O"_a,
          "Integrates an (H, W) depth image (metres) taken at optical pose T_W_O.")
      .def(
          "integrate_points",
          [](ActiveVisionSession& s, const py::handle& points, const py::handle& origin) {
            CloudXYZ cloud;
            readPoints(points, "points", cloud);
            const Eigen::Vector3d o = readVector3(origin, "origin");
            ReleasedAndLocked lock;
            s.integrate(cloud, o);
          },
          "points"_a, "origin"_a, "Integrates (N, 3) world points seen from `origin`.")
      .def(
          "integrate_frames",
          [](ActiveVisionSession& s, const io::FramesFolder& frames) {
            ReleasedAndLocked lock;
            DepthImage depth;
            for (std::size_t i = 0; i < frames.frames().size(); ++i) {
              frames.loadDepth(i, depth);
              s.integrate(depth, frames.camera().intrinsics, frames.frames()[i].T_W_O);
            }
            return frames.frames().size();
          },
          "frames"_a, "Integrates every frame of a FramesFolder; returns their number.")
      .def(
          "next_best_view",
          [](ActiveVisionSession& s) {
            NextBestView next;
            {
              ReleasedAndLocked lock;
              s.nextBestView(next);
            }
            return PlanningStep(std::move(next));
          },
          "One planning step on the current map: the ranked candidates.")
      .def_property_readonly("map", &ActiveVisionSession::getMap,
                             "The map (shared: changes as the session integrates).")
      .def(
          "read_map",
          [](ActiveVisionSession& s, const Path& path) {
            ReleasedAndLocked lock;
            return s.readMap(path.string());
          },
          "path"_a,
          "Replaces the map by a file's; False if it was a .bt (no uncertainty).")
      .def(
          "write_map",
          [](const ActiveVisionSession& s, const Path& path) {
            ReleasedAndLocked lock;
            s.writeMap(path.string());
          },
          "path"_a, "Writes the map, .ot (log-odds) or .bt, by extension.");
}

void bindLeafNodePrior(py::module_& m)
{
  using Config = LeafNodePrior::Config;
  const auto anchors = [](const py::handle& points) { // doubles, as the boxes' centres
    std::vector<Eigen::Vector3d> out;
    if (!points.is_none())
      for (const py::handle& point : points)
        out.push_back(readVector3(point, "anchors"));
    return out;
  };
  py::class_<LeafNodePrior>(
      m, "LeafNodePrior",
      "Leaf-node boxes predicted one internode apart along the main stem, from the "
      "plant's base to its top in the map (the `prior` ROI source; "
      "session/leaf_node_prior.h gives the rules). Defaults: the generator's tomatoes.")
      .def(py::init([](double internode_m, double first_node_m, double top_radius_m,
                       bool anchor_on_found) {
             Config c;
             c.internode_m = internode_m;
             c.first_node_m = first_node_m;
             c.top_radius_m = top_radius_m;
             c.anchor_on_found = anchor_on_found;
             return LeafNodePrior(c);
           }),
           "internode_m"_a = Config().internode_m,
           "first_node_m"_a = Config().first_node_m,
           "top_radius_m"_a = Config().top_radius_m,
           "anchor_on_found"_a = Config().anchor_on_found)
      .def(
          "predict",
          [anchors](const LeafNodePrior& prior, const py::handle& occupied,
                    const CylindricalSector& sector, const py::handle& anchor_points,
                    const Roi& stem) {
            CloudXYZ cloud;
            readPoints(occupied, "occupied", cloud);
            const std::vector<Eigen::Vector3d> a = anchors(anchor_points);
            LeafNodePrior with_stem = prior;
            with_stem.setStemObservations(stem);
            py::gil_scoped_release release;
            return with_stem.predict(cloud, sector.axis_base, sector.height_m, a);
          },
          "occupied"_a, "sector"_a, "anchors"_a = py::none(), "stem"_a = Roi(),
          "The predicted boxes (a Roi) from a map's occupied voxel centres, (N, 3) "
          "world points (Session.map.occupied_centres()), on the sector's axis and up to "
          "its height; `anchors`, (K, 3): detected nodes to predict from; `stem`: a Roi "
          "of detected stem parts, through whose centres the stem runs (as plan "
          "--stem-roi).")
      .def(
          "predict_around",
          [](const LeafNodePrior& prior, const Roi& found, const py::handle& occupied,
             const CylindricalSector& sector, const Roi& stem) {
            CloudXYZ cloud;
            readPoints(occupied, "occupied", cloud);
            LeafNodePrior with_stem = prior;
            with_stem.setStemObservations(stem);
            py::gil_scoped_release release;
            return with_stem.predictAround(found, cloud, sector.axis_base,
                                           sector.height_m);
          },
          "found"_a, "occupied"_a, "sector"_a, "stem"_a = Roi(),
          "The `detections+prior` ROI: the `found` boxes (e.g. read_roi of `integrate "
          "--roi-out`), then the prediction (`stem` as in predict).");
}

} // namespace

void bindPlanning(py::module_& m)
{
  bindMap(m);
  bindSamplers(m);
  bindPlanners(m);
  bindSession(m);
  bindLeafNodePrior(m);
}

} // namespace python
} // namespace plantnbv
