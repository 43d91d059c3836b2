/// \file bench_session.cpp
/// \brief What the real-robot loop costs next to a trial's own steps
/// (docs/performance.md, "Real-robot loop"): integrating a depth frame (PNG decoding,
/// back-projection, the map's insertion) against the trial's insertion of the sensor's
/// cloud, and planning on a map read from a file against the trial's planning step.
///
/// Data: default tomato plant 3 at the paper's (1.0, 0, 0.8) in the default scene; the 10
/// views of an NBV (whole plant) trial with the paper's Table 1 (L515 at 640 x 480, 3 mm,
/// 27 candidates); the frames are the simulated sensor's, rounded to millimetres as a
/// frames folder stores them. An insertion iteration puts the 10 frames into a new map;
/// times are per frame. Run (machine quiet):
///   bench_session --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/stopwatch.h>
#include <plantnbv/experiment/plant_scene.h>
#include <plantnbv/experiment/trial.h>
#include <plantnbv/io/depth_image_io.h>
#include <plantnbv/plant/plant_rois.h>
#include <plantnbv/plant/tomato_plant_generator.h>
#include <plantnbv/sensor/simulated_depth_sensor.h>
#include <plantnbv/session/active_vision_session.h>

namespace {

using namespace plantnbv;

constexpr double kDepthScale = 1000.0;
constexpr int kThreads = 2;

struct Frames {
  CameraIntrinsics camera;
  std::vector<Viewpoint> views;
  std::vector<CloudXYZL> clouds;  ///< the sensor's, as a trial inserts them
  std::vector<DepthImage> depths; ///< rounded to millimetres
  std::vector<std::string> pngs;  ///< the same depths as 16-bit PNGs
  Roi roi;
  CylindricalSector sector;
  std::string map_path; ///< the map of all 10 frames, .ot
};

const Frames& frames()
{
  static const Frames f = [] {
    Frames f;
    auto plant =
        std::make_shared<Plant>(TomatoPlantGenerator(defaultPlantConfig(3)).generate());
    posePlant(*plant, paperPlantBase(), 0.0);
    f.roi = wholePlantRoi(*plant);
    TrialConfig config;
    config.threads = kThreads;
    config.seed = 1;
    Trial trial(config);
    trial.setPlant(plant);
    trial.setAttentionRoi(f.roi);
    TrialResult result;
    trial.run(result);
    f.camera = config.camera;
    f.sector = trial.getSector();
    SimulatedDepthSensor sensor(config.camera);
    sensor.setNumberOfThreads(kThreads);
    sensor.setScene(makePlantScene(*plant, config.scene, kThreads));
    const std::string dir =
        (std::filesystem::temp_directory_path() / "plantnbv_bench_session").string();
    std::filesystem::create_directories(dir);
    for (const TrialStep& step : result.steps) {
      f.views.push_back(step.view);
      f.clouds.emplace_back();
      f.depths.emplace_back();
      sensor.capture(step.view, f.clouds.back(), &f.depths.back());
      roundDepthToUnits(f.depths.back(), kDepthScale);
      f.pngs.push_back(dir + "/" + std::to_string(step.index) + ".png");
      const DepthImage& d = f.depths.back();
      io::saveDepthPng(f.pngs.back(), d.width, d.height, d.depth_m, kDepthScale);
    }
    f.map_path = dir + "/map.ot";
    trial.getMap().write(f.map_path);
    return f;
  }();
  return f;
}

/// method: 0 = the trial's insertion of the sensor's cloud, 1 = ActiveVisionSession::
/// integrate of the depth image (back-projection + insertion), 2 = back-projection alone,
/// 3 = PNG decoding alone.
void BM_Integrate(benchmark::State& state)
{
  const Frames& f = frames();
  const int method = int(state.range(0));
  const std::size_t n = f.views.size();
  CloudXYZ cloud;
  DepthImage depth;
  for (auto _ : state) {
    ActiveVisionSession::Config config;
    config.threads = kThreads;
    ActiveVisionSession session(config);
    Stopwatch clock;
    for (std::size_t i = 0; i < n; ++i) {
      const Pose T_W_O = opticalFrame(f.views[i]);
      switch (method) {
      case 0:
        session.integrate(f.clouds[i], f.views[i].position);
        break;
      case 1:
        session.integrate(f.depths[i], f.camera, T_W_O);
        break;
      case 2:
        depthToCloud(f.depths[i], f.camera, T_W_O, cloud);
        break;
      default:
        io::loadDepthPng(f.pngs[i], depth, kDepthScale);
      }
    }
    state.SetIterationTime(clock.ms() / 1000.0 / double(n));
  }
}

/// from_file: 0 = a planning step on the map in memory (a new planner: one snapshot
/// build and the candidates' gains, as a trial's step after an insertion), 1 = the same
/// on the map read from its .ot file (what `plantnbv plan` does besides printing).
void BM_Plan(benchmark::State& state)
{
  const Frames& f = frames();
  const bool from_file = state.range(0) == 1;
  ActiveVisionSession::Config config;
  config.threads = kThreads;
  config.sector = f.sector;
  config.seed = 5;
  std::shared_ptr<OccupancyMap> map = OccupancyMap::read(f.map_path, config.map);
  double read_ms = 0.0, snapshot_ms = 0.0;
  for (auto _ : state) {
    Stopwatch clock;
    ActiveVisionSession session(config);
    session.setCamera(f.camera);
    session.setRoi(f.roi);
    if (from_file) {
      Stopwatch read_clock;
      session.readMap(f.map_path);
      read_ms = read_clock.ms();
    } else {
      session.setMap(map);
    }
    NextBestView next;
    session.nextBestView(next);
    snapshot_ms = next.result.update_ms;
    state.SetIterationTime(clock.ms() / 1000.0);
  }
  state.counters["read_ms"] = read_ms;
  state.counters["snapshot_ms"] = snapshot_ms;
}

BENCHMARK(BM_Integrate)
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->Arg(3)
    ->ArgNames({"method"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Plan)
    ->Arg(0)
    ->Arg(1)
    ->ArgNames({"from_file"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

} // namespace

BENCHMARK_MAIN();
