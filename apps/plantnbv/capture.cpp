// plantnbv capture: render one depth view of a placed plant with the simulated sensor;
// optionally the depth image and a fresh occupancy map with the view inserted.

#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/stopwatch.h>
#include <plantnbv/experiment/plant_scene.h>
#include <plantnbv/io/cloud_io.h>
#include <plantnbv/io/depth_image_io.h>
#include <plantnbv/io/file_kind.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/sensor/simulated_depth_sensor.h>

#include "commands.h"
#include "plant_options.h"

namespace plantnbv {
namespace app {

namespace {

struct CaptureOptions {
  PlantOptions plant;
  /// The paper's v0 (Table 1): x, y, z, qx, qy, qz, qw.
  std::vector<double> pose{0.646, 0.353, 1.383, 0.0, 0.0, -0.383, 0.924};
  std::string intrinsics = "l515-640";
  bool noise = false;
  std::uint64_t noise_seed = 0;
  bool no_background = false;
  double resolution_m = OccupancyMap::Config().resolution_m;
  std::string output;
  std::string depth;
  std::string map;
};

void runCapture(const CaptureOptions& o)
{
  if (o.pose.size() != 7)
    throw InvalidArgumentError("--pose needs 7 numbers x,y,z,qx,qy,qz,qw, got " +
                               std::to_string(o.pose.size()));
  Pose T_W_C;
  try {
    T_W_C = Pose::fromXyzQuat(o.pose[0], o.pose[1], o.pose[2], o.pose[3], o.pose[4],
                              o.pose[5], o.pose[6]);
  } catch (const InvalidArgumentError& e) {
    throw InvalidArgumentError(std::string("--pose: ") + e.what());
  }
  // Output formats are checked before the work, so that nothing is rendered in vain.
  const std::string cloud_ext = io::extensionOf(o.output);
  if (cloud_ext != ".pcd" && cloud_ext != ".ply")
    throw FormatError("-o '" + o.output + "': expected a .pcd or .ply file");
  const std::string map_ext = io::extensionOf(o.map);
  if (!o.map.empty() && map_ext != ".bt" && map_ext != ".ot")
    throw FormatError("--map '" + o.map + "': expected a .bt or .ot file");
  OccupancyMap::Config map_config;
  map_config.resolution_m = o.resolution_m;
  if (!o.map.empty())
    map_config.validate(); // before the work, not after

  SimulatedDepthSensor sensor(parseCameraIntrinsics(o.intrinsics));
  if (o.noise) {
    NoiseConfig noise;
    noise.enabled = true;
    noise.seed = o.noise_seed;
    sensor.setNoise(noise);
  }
  const scenario::PlacedPlant placed = placePlant(o.plant);
  Stopwatch scene_clock;
  PlantSceneConfig scene_config;
  scene_config.floor = scene_config.support = !o.no_background;
  sensor.setScene(makePlantScene(placed.plant, scene_config));
  const double scene_ms = scene_clock.ms();

  Stopwatch capture_clock;
  CloudXYZL cloud;
  DepthImage depth;
  sensor.capture(T_W_C, cloud, o.depth.empty() ? nullptr : &depth);
  const double capture_ms = capture_clock.ms();

  std::size_t returns = 0, background = 0;
  for (const pcl::PointXYZL& p : cloud.points)
    if (std::isfinite(p.x)) {
      ++returns;
      background += p.label == std::uint32_t(PartLabel::background);
    }
  const CameraIntrinsics& K = sensor.getIntrinsics();
  std::cout << std::fixed << std::setprecision(1) << placed.plant.name << " ("
            << placed.description << "), " << K.width << "x" << K.height << " view: "
            << returns << " returns (" << returns - background << " on the plant, "
            << background << " on floor and support) of " << cloud.size()
            << " pixels; scene " << scene_ms << " ms, capture " << capture_ms << " ms\n";

  io::saveCloud(o.output, cloud);
  std::cout << "wrote " << o.output << " (organized " << cloud.width << "x"
            << cloud.height << ", NaN where no return, label per point)\n";
  if (!o.depth.empty()) {
    io::saveDepthPng(o.depth, depth.width, depth.height, depth.depth_m);
    std::cout << "wrote " << o.depth << " (16-bit, millimetres, 0 = no return)\n";
  }
  if (!o.map.empty()) {
    OccupancyMap map(map_config);
    map.insert(cloud, opticalFrame(T_W_C).position);
    const auto& stats = map.getLastInsertStats();
    const auto counts = map.countVoxels();
    map.write(o.map);
    std::cout << "wrote " << o.map << ": " << counts.occupied << " occupied, "
              << counts.free << " free voxels of " << map_config.resolution_m * 1000.0
              << " mm (" << stats.beyond_range << " returns beyond "
              << std::setprecision(2) << map_config.max_range_m
              << " m carved free space only); inserted in " << std::setprecision(1)
              << stats.total_ms << " ms\n";
  }
}

} // namespace

void addCaptureCommand(CLI::App& app)
{
  auto o = std::make_shared<CaptureOptions>();
  CLI::App* cmd = app.add_subcommand(
      "capture", "Render one depth view of a plant (organized labelled cloud in the world "
                 "frame); optionally its depth image and an occupancy map of it");
  addPlantOptions(*cmd, o->plant, "--plant");
  cmd->add_option("--pose", o->pose,
                  "Camera body pose x,y,z,qx,qy,qz,qw (x forward, z up; default: the "
                  "paper's v0)")
      ->delimiter(',')
      ->expected(7);
  cmd->add_option("--intrinsics", o->intrinsics,
                  "l515 (1024x768), l515-640, l515-320, or WxH:fx,fy,cx,cy")
      ->capture_default_str();
  cmd->add_flag("--noise", o->noise, "L515-like depth noise (off: the paper's sensor)");
  cmd->add_option("--noise-seed", o->noise_seed, "Seed of the noise")
      ->capture_default_str()
      ->needs("--noise");
  cmd->add_flag("--no-background", o->no_background,
                "Leave out the floor and the support under the plant");
  cmd->add_option("-o,--output", o->output, "Cloud file (.pcd or .ply)")->required();
  cmd->add_option("--depth", o->depth, "Also write the depth image (16-bit PNG, mm)");
  cmd->add_option("--map", o->map, "Also insert the view into a new map, write .bt or .ot");
  cmd->add_option("--resolution", o->resolution_m, "Map voxel size in metres")
      ->capture_default_str();
  cmd->callback([o]() { runCapture(*o); });
}

} // namespace app
} // namespace plantnbv
