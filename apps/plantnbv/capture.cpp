// plantnbv capture: render one depth view of a placed plant with the simulated sensor;
// optionally the depth image and a fresh occupancy map with the view inserted.

#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/memory_cap.h>
#include <plantnbv/common/stopwatch.h>
#include <plantnbv/experiment/plant_scene.h>
#include <plantnbv/io/cloud_io.h>
#include <plantnbv/io/depth_image_io.h>
#include <plantnbv/io/file_kind.h>
#include <plantnbv/io/frames_folder.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/sensor/simulated_depth_sensor.h>
#include <plantnbv/session/memory_estimate.h>
#include <plantnbv/viz/snapshot.h>

#include "cli_checks.h"
#include "commands.h"
#include "frames_out.h"
#include "map_file.h"
#include "plant_options.h"
#include "sensor_options.h"

namespace plantnbv {
namespace app {

namespace {

struct CaptureOptions {
  PlantOptions plant;
  /// The paper's v0 (Table 1): x, y, z, qx, qy, qz, qw.
  std::vector<double> pose{0.646, 0.353, 1.383, 0.0, 0.0, -0.383, 0.924};
  std::vector<double> optical_pose; ///< if given: the optical frame, instead of `pose`
  SensorOptions sensor;
  std::uint64_t noise_seed = 0;
  double resolution_m = OccupancyMap::Config().resolution_m;
  std::string output;
  std::string depth;
  std::string map;
  std::string snapshot;
  std::string frames_out;
  std::optional<double> depth_scale;
  std::optional<double> stamp;
};

/// The view over the plant: its returns on the plant coloured by part (those on the
/// floor and support would fill the picture), the plant faded, the camera's frustum.
void renderSnapshot(const scenario::PlacedPlant& placed, const CloudXYZL& cloud,
                    const Pose& T_W_C, const CameraIntrinsics& camera,
                    const std::string& png)
{
  std::vector<Eigen::Vector3f> points;
  std::vector<PartLabel> labels;
  std::size_t background = 0;
  for (const pcl::PointXYZL& p : cloud.points)
    if (!std::isfinite(p.x)) {
      continue;
    } else if (p.label != std::uint32_t(PartLabel::background)) {
      points.push_back(p.getVector3fMap());
      labels.push_back(static_cast<PartLabel>(p.label));
    } else {
      ++background;
    }
  viz::SceneSnapshot::Config config;
  config.width = 1200;
  config.height = 1200;
  std::ostringstream title;
  title << placed.plant.name << ": a " << camera.width << "x" << camera.height
        << " view\n"
        << points.size() << " returns on the plant\n"
        << background << " on floor and support, not shown";
  config.title = title.str();
  viz::SceneSnapshot snapshot(config);
  if (!placed.plant.mesh.empty())
    snapshot.addMesh(placed.plant.mesh, 0.25);
  snapshot.addPoints(points, labels, 2.0f);
  viz::addPartLegend(labels, snapshot);
  const viz::Rgb frustum{0.25f, 0.25f, 0.25f};
  snapshot.addCameraFrustum(T_W_C, camera.horizontalFov(), camera.verticalFov(), 0.05,
                            frustum);
  snapshot.addLegendEntry("camera", frustum);
  snapshot.render(png);
}

void runCapture(const CaptureOptions& o)
{
  if (!o.snapshot.empty())
    requireDisplayOrReexec();
  const bool optical = !o.optical_pose.empty();
  const std::vector<double>& v = optical ? o.optical_pose : o.pose;
  const char* option = optical ? "--optical-pose" : "--pose";
  if (v.size() != 7)
    throw InvalidArgumentError(std::string(option) +
                               " needs 7 numbers x,y,z,qx,qy,qz,qw, got " +
                               std::to_string(v.size()));
  Pose T_W_C;
  try {
    T_W_C = Pose::fromXyzQuat(v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
  } catch (const InvalidArgumentError& e) {
    throw InvalidArgumentError(std::string(option) + ": " + e.what());
  }
  if (optical)
    T_W_C = bodyFrame(T_W_C);
  // Output formats are checked before the work, so that nothing is rendered in vain.
  if (o.output.empty() && o.frames_out.empty() && o.depth.empty() && o.map.empty() &&
      o.snapshot.empty())
    throw InvalidArgumentError("nothing to write: give -o CLOUD, --frames-out FRAMES, "
                               "--depth PNG, --map MAP or --snapshot PNG");
  const std::string cloud_ext = io::extensionOf(o.output);
  if (!o.output.empty() && cloud_ext != ".pcd" && cloud_ext != ".ply")
    throw FormatError("-o '" + o.output + "': expected a .pcd or .ply file");
  if (!o.map.empty())
    requireMapExtension(o.map, "--map");
  OccupancyMap::Config map_config;
  map_config.resolution_m = o.resolution_m;
  if (!o.map.empty())
    map_config.validate(); // before the work, not after

  // What the view and the map will take, before anything is allocated.
  const CameraIntrinsics camera =
      intrinsicsOf(o.sensor).value_or(CameraIntrinsics::l515(L515Mode::vga_640x480));
  std::ostringstream what;
  what << "--intrinsics " << camera.width << "x" << camera.height;
  if (!o.map.empty())
    what << " and --resolution " << o.resolution_m << " m (map range "
         << map_config.max_range_m << " m)";
  requireWithinMemoryCap(o.map.empty() ? estimatedFrameMemoryBytes(camera)
                                       : estimatedViewMemoryBytes(map_config, camera),
                         kDefaultMemoryCapBytes, what.str());

  SimulatedDepthSensor sensor(camera);
  std::optional<io::FramesFolderWriter> frames;
  if (!o.frames_out.empty())
    frames.emplace(o.frames_out,
                   framesCamera(o.frames_out, sensor.getIntrinsics(), o.depth_scale));
  if (o.sensor.noise) {
    NoiseConfig noise;
    noise.enabled = true;
    noise.seed = o.noise_seed;
    sensor.setNoise(noise);
  }
  const scenario::PlacedPlant placed = placePlant(o.plant);
  Stopwatch scene_clock;
  PlantSceneConfig scene_config;
  scene_config.floor = scene_config.support = !o.sensor.no_background;
  sensor.setScene(makePlantScene(placed.plant, scene_config));
  const double scene_ms = scene_clock.ms();

  Stopwatch capture_clock;
  CloudXYZL cloud;
  DepthImage depth;
  sensor.capture(T_W_C, cloud, o.depth.empty() && !frames ? nullptr : &depth);
  const double capture_ms = capture_clock.ms();

  std::size_t returns = 0, background = 0;
  for (const pcl::PointXYZL& p : cloud.points)
    if (std::isfinite(p.x)) {
      ++returns;
      background += p.label == std::uint32_t(PartLabel::background);
    }
  const CameraIntrinsics& K = sensor.getIntrinsics();
  std::cout << std::fixed << std::setprecision(1) << placed.plant.name << " ("
            << placed.description << "), " << K.width << "x" << K.height
            << " view: " << returns << " returns (" << returns - background
            << " on the plant, " << background << " on floor and support) of "
            << cloud.size() << " pixels; scene " << scene_ms << " ms, capture "
            << capture_ms << " ms\n";

  if (!o.output.empty()) {
    io::saveCloud(o.output, cloud);
    std::cout << "wrote " << o.output << " (organized " << cloud.width << "x"
              << cloud.height << ", NaN where no return, label per point)\n";
  }
  if (!o.depth.empty()) {
    io::saveDepthPng(o.depth, depth.width, depth.height, depth.depth_m);
    std::cout << "wrote " << o.depth << " (16-bit, millimetres, 0 = no return)\n";
  }
  if (frames) {
    frames->append(depth, opticalFrame(T_W_C),
                   o.stamp ? *o.stamp : std::numeric_limits<double>::quiet_NaN());
    std::cout << "appended frame " << frames->frameCount() - 1 << " to '" << o.frames_out
              << "' (stamp " << std::setprecision(6) << frames->lastStamp()
              << " s, optical pose in groundtruth.txt)\n";
  }
  if (!o.snapshot.empty()) {
    renderSnapshot(placed, cloud, T_W_C, K, o.snapshot);
    std::cout << "wrote " << o.snapshot << "\n";
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
      "capture",
      "Render one depth view of a plant (organized labelled cloud in the world "
      "frame); optionally its depth image and an occupancy map of it");
  addPlantOptions(*cmd, o->plant, "--plant");
  cmd->add_option("--pose", o->pose,
                  "Camera body pose x,y,z,qx,qy,qz,qw (x forward, z up; default: the "
                  "paper's v0)")
      ->delimiter(',')
      ->expected(7);
  cmd->add_option("--optical-pose", o->optical_pose,
                  "Camera optical pose x,y,z,qx,qy,qz,qw instead (z forward, y down; as "
                  "groundtruth.txt and `plan` give it)")
      ->delimiter(',')
      ->expected(7)
      ->excludes("--pose");
  addSensorOptions(*cmd, o->sensor, "l515-640", "--noise-seed");
  cmd->add_option("--noise-seed", o->noise_seed, "Seed of the noise")
      ->check(unsignedInteger())
      ->capture_default_str()
      ->needs("--noise");
  cmd->add_option("-o,--output", o->output, "Cloud file (.pcd or .ply)");
  cmd->add_option("--depth", o->depth, "Also write the depth image (16-bit PNG, mm)")
      ->check(pngPath());
  cmd->add_option("--snapshot", o->snapshot,
                  "Also render a PNG: the returns coloured by part over the faded plant, "
                  "the camera (needs X; without a display the tool re-runs itself "
                  "under xvfb-run)")
      ->check(pngPath());
  cmd->add_option("--map", o->map,
                  "Also insert the view into a new map, write .bt or .ot");
  cmd->add_option("--frames-out", o->frames_out,
                  "Append the frame to this frames folder (depth PNG, pose, camera.yaml; "
                  "docs/real-robot.md)");
  cmd->add_option(
         "--depth-scale", o->depth_scale,
         "Depth PNG units per metre of --frames-out (default: the folder's, else "
         "1000)")
      ->needs("--frames-out");
  cmd->add_option("--stamp", o->stamp,
                  "Timestamp of the frame in seconds (default: the folder's last + 1)")
      ->needs("--frames-out");
  cmd->add_option("--resolution", o->resolution_m, "Map voxel size in metres")
      ->capture_default_str();
  cmd->callback([o]() { runCapture(*o); });
}

} // namespace app
} // namespace plantnbv
