/// \file bench_planning.cpp
/// \brief One NBV planning step's information gain: ours (plantnbv::InformationGain, a
/// bricked snapshot of the map, rays culled and clipped to the ROI) side by side with the
/// straightforward octree walk (plantnbv::referenceInformationGain: OctoMap's
/// computeRayKeys, a tree search per voxel, a hash set of keys), at 1 and 2 threads.
///
/// Data: the oldest default tomato plant (defaultPlantConfig(9), about 245k triangles)
/// posed at the paper's (1.0, 0, 0.8) in the default scene (floor and support), seen by
/// the simulated L515 at 640 x 480 from the paper's v0 and then from candidates 13, 6,
/// 20, 0 and 26 of the sampler's draw with seed 1, into a 3 mm OccupancyMap with the
/// paper's parameters: maps after 1, 3 and 6 views. Candidates: the 27 of the paper's
/// cylindrical sector (3 x 3 cells, 3 each) drawn with seed 42. ROIs: whole plant, main
/// stem, leaf nodes (plant_rois.h). Gain: the paper's (GainConfig::paper(), 48 x 36
/// rays; docs/performance.md and docs/planning.md were measured with it), and 64 x 48
/// rays (the grid of shared/notes/performance-findings.md) for comparison.
///
/// gain/ours/...: one iteration = InformationGain::update() (the snapshot of the
/// changed map) + compute() of the 27 candidates, the planning step's gain cost; counters
/// update_ms and gain_ms split it. gain/reference/...: the 27 reference gains (OpenMP
/// over candidates; at 64 x 48 rays only for the 3-view map, whole plant, 2 threads: it
/// takes seconds). Counters of both: best_gain (bits) and best (index) of the arg max;
/// for ours, max_rel_diff (largest relative difference to the reference over the 27),
/// voxels_differ (candidates whose voxels_seen differs) and same_choice (1 if the arg
/// max is the reference's).
///
/// snapshot/{new,after_insert}/...: the snapshot of the map after `views` views (3 or
/// 6), with the paper's gain: built anew from the whole tree (`new`), or brought up to
/// date from the snapshot of the map before the last view, reading only the bricks that
/// the last view's insert changed (`after_insert`, the NBV loop's case). The time is the
/// update's alone (manual time; the map's copy and the insert are not timed). Counters:
/// incremental (1 if the update read only the changed bricks), leaves (octree leaves
/// read), bricks.
///
/// ray_count/...: the study behind GainConfig's default ray grid. For each ROI, over the
/// maps after 1, 3 and 6 views and 20 candidate sets each (27 candidates, seeds
/// 100-119): 60 choices with each ray grid from 16 x 12 to 160 x 120, judged by the
/// finest grid, 256 x 192. Counters: same_choice (fraction of the 60 where the arg max
/// is the finest grid's), gain_loss (mean of 1 - G_finest(chosen) / G_finest(the finest
/// grid's choice): what the coarser choice loses, measured finely), gain_loss_max,
/// rank_corr (mean Spearman correlation of the 27 gains with the finest grid's), step_ms
/// (update + compute of the 27 benchmark candidates on the 3-view map, 2 threads; the
/// benchmark's time is the same).
///
/// Run (machine quiet: no compiler running):
///   bench_planning --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
/// and only the study: --benchmark_filter=ray_count (one repetition is enough for its
/// choice counters, which are deterministic).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <omp.h>
#include <string>
#include <tuple>
#include <vector>

#include <benchmark/benchmark.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/experiment/plant_scene.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/octree/occupancy_map_snapshot.h>
#include <plantnbv/planning/cylindrical_sector_sampler.h>
#include <plantnbv/planning/information_gain.h>
#include <plantnbv/plant/plant_rois.h>
#include <plantnbv/plant/tomato_plant_generator.h>
#include <plantnbv/sensor/simulated_depth_sensor.h>

namespace {

using namespace plantnbv;

const Pose kV0 = Pose::fromXyzQuat(0.646, 0.353, 1.383, 0.0, 0.0, -0.383, 0.924);

const Plant& benchPlant()
{
  static const Plant plant = [] {
    Plant p = TomatoPlantGenerator(defaultPlantConfig(9)).generate();
    posePlant(p, Eigen::Vector3d(1.0, 0.0, 0.8), 0.0);
    return p;
  }();
  return plant;
}

/// The six views' poses and frames, made once.
struct BenchView {
  Viewpoint pose;
  CloudXYZL frame;
};
const std::vector<BenchView>& benchViews()
{
  static const std::vector<BenchView> views = [] {
    SimulatedDepthSensor sensor(CameraIntrinsics::l515(L515Mode::vga_640x480));
    sensor.setScene(makePlantScene(benchPlant()));
    std::vector<Viewpoint> drawn;
    Rng rng(1);
    CylindricalSectorSampler().sample(rng, drawn);
    std::vector<BenchView> out;
    for (const Viewpoint& pose :
         {kV0, drawn[13], drawn[6], drawn[20], drawn[0], drawn[26]}) {
      out.push_back({pose, CloudXYZL()});
      sensor.capture(pose, out.back().frame);
    }
    return out;
  }();
  return views;
}

/// The map after `views` views (1 to 6), built once.
std::shared_ptr<const OccupancyMap> benchMap(int views)
{
  static std::map<int, std::shared_ptr<OccupancyMap>> cache;
  auto& map = cache[views];
  if (map)
    return map;
  map = std::make_shared<OccupancyMap>();
  for (int v = 0; v < views; ++v) {
    const BenchView& view = benchViews()[static_cast<std::size_t>(v)];
    map->insert(view.frame, view.pose.position);
  }
  return map;
}

const std::vector<Viewpoint>& candidates()
{
  static const std::vector<Viewpoint> views = [] {
    std::vector<Viewpoint> out;
    Rng rng(42);
    CylindricalSectorSampler().sample(rng, out);
    return out;
  }();
  return views;
}

Roi benchRoi(RoiKind kind)
{
  return plantRoi(benchPlant(), kind);
}

/// The reference gains (27 candidates), cached per map and ROI.
const std::vector<ViewGain>&
referenceGains(int views, RoiKind kind, const GainConfig& config = GainConfig::paper())
{
  static std::map<std::tuple<int, int, int, int>, std::vector<ViewGain>> cache;
  auto& out = cache[{views, static_cast<int>(kind), config.rays_x, config.rays_y}];
  if (out.empty()) {
    const auto map = benchMap(views);
    const Roi roi = benchRoi(kind);
    out.resize(candidates().size());
#pragma omp parallel for schedule(dynamic, 1)
    for (std::size_t i = 0; i < out.size(); ++i)
      out[i] = referenceInformationGain(*map, roi, config, candidates()[i]);
  }
  return out;
}

std::size_t argMax(const std::vector<ViewGain>& gains)
{
  std::size_t best = 0;
  for (std::size_t i = 1; i < gains.size(); ++i)
    if (gains[i].gain > gains[best].gain)
      best = i;
  return best;
}

GainConfig gridConfig(int rays_x)
{
  GainConfig config = GainConfig::paper();
  config.rays_x = rays_x;
  config.rays_y = rays_x * 3 / 4;
  return config;
}

void benchOurs(benchmark::State& state, int views, RoiKind kind, int threads, int rays_x)
{
  const auto map = benchMap(views);
  InformationGain gain;
  gain.setInputMap(map);
  gain.setRoi(benchRoi(kind));
  gain.setNumberOfThreads(threads);
  gain.setConfig(gridConfig(rays_x));
  std::vector<ViewGain> out;
  gain.compute(candidates(), out); // warm: buffers allocated, pages touched
  double update_ms = 0.0, gain_ms = 0.0;
  for (auto _ : state) {
    gain.update();
    gain.compute(candidates(), out);
    update_ms += gain.getLastStats().update_ms;
    gain_ms += gain.getLastStats().gain_ms;
  }
  const auto n = static_cast<double>(state.iterations());
  state.counters["update_ms"] = update_ms / n;
  state.counters["gain_ms"] = gain_ms / n;
  state.counters["threads"] = threads;
  const std::vector<ViewGain>& ref = referenceGains(views, kind, gridConfig(rays_x));
  double max_rel = 0.0;
  std::size_t voxels_differ = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double d = std::abs(out[i].gain - ref[i].gain);
    max_rel = std::max(max_rel, ref[i].gain > 0.0 ? d / ref[i].gain : d);
    voxels_differ += out[i].voxels_seen != ref[i].voxels_seen ? 1 : 0;
  }
  state.counters["best"] = static_cast<double>(argMax(out));
  state.counters["best_gain"] = out[argMax(out)].gain;
  state.counters["max_rel_diff"] = max_rel;
  state.counters["voxels_differ"] = static_cast<double>(voxels_differ);
  state.counters["same_choice"] = argMax(out) == argMax(ref) ? 1 : 0;
  state.counters["bricks"] = static_cast<double>(gain.getLastStats().bricks);
  state.counters["rays_cast"] = static_cast<double>(gain.getLastStats().rays_cast);
}

void benchReference(benchmark::State& state, int views, RoiKind kind, int threads,
                    int rays_x)
{
  const auto map = benchMap(views);
  const Roi roi = benchRoi(kind);
  const GainConfig config = gridConfig(rays_x);
  std::vector<ViewGain> out(candidates().size());
  for (auto _ : state) {
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
    for (std::size_t i = 0; i < out.size(); ++i)
      out[i] = referenceInformationGain(*map, roi, config, candidates()[i]);
  }
  state.counters["threads"] = threads;
  state.counters["best"] = static_cast<double>(argMax(out));
  state.counters["best_gain"] = out[argMax(out)].gain;
}

/// 27 candidates drawn with `seed` (the study's candidate sets).
std::vector<Viewpoint> candidateSet(std::uint64_t seed)
{
  std::vector<Viewpoint> out;
  Rng rng(seed);
  CylindricalSectorSampler().sample(rng, out);
  return out;
}

constexpr int kStudySeeds = 20;
constexpr int kFinestX = 256;

/// Gains of candidate set `seed` at rays_x x (3/4 rays_x), cached.
const std::vector<ViewGain>& studyGains(int views, RoiKind kind, int seed, int rays_x)
{
  static std::map<std::tuple<int, int, int, int>, std::vector<ViewGain>> cache;
  auto& out = cache[{views, static_cast<int>(kind), seed, rays_x}];
  if (out.empty()) {
    InformationGain gain;
    gain.setInputMap(benchMap(views));
    gain.setRoi(benchRoi(kind));
    GainConfig config = GainConfig::paper();
    config.rays_x = rays_x;
    config.rays_y = rays_x * 3 / 4;
    gain.setConfig(config);
    gain.compute(candidateSet(static_cast<std::uint64_t>(seed) + 100), out);
  }
  return out;
}

/// Ranks (0 = smallest) of the gains, ties averaged.
std::vector<double> ranks(const std::vector<ViewGain>& g)
{
  std::vector<std::size_t> order(g.size());
  for (std::size_t i = 0; i < g.size(); ++i)
    order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return g[a].gain < g[b].gain; });
  std::vector<double> r(g.size());
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i;
    while (j + 1 < order.size() && g[order[j + 1]].gain == g[order[i]].gain)
      ++j;
    for (std::size_t k = i; k <= j; ++k)
      r[order[k]] = 0.5 * static_cast<double>(i + j);
    i = j + 1;
  }
  return r;
}

/// Spearman's rank correlation of two gain vectors.
double rankCorrelation(const std::vector<ViewGain>& a, const std::vector<ViewGain>& b)
{
  const std::vector<double> ra = ranks(a), rb = ranks(b);
  const double n = static_cast<double>(ra.size()), mean = 0.5 * (n - 1.0);
  double sab = 0.0, saa = 0.0, sbb = 0.0;
  for (std::size_t i = 0; i < ra.size(); ++i) {
    sab += (ra[i] - mean) * (rb[i] - mean);
    saa += (ra[i] - mean) * (ra[i] - mean);
    sbb += (rb[i] - mean) * (rb[i] - mean);
  }
  return saa > 0.0 && sbb > 0.0 ? sab / std::sqrt(saa * sbb) : 1.0;
}

/// The ray-count study: over the maps after 1, 3 and 6 views and kStudySeeds candidate
/// sets each, the choice with one ray grid against the finest grid's.
void benchRayCount(benchmark::State& state, RoiKind kind, int rays_x)
{
  GainConfig config = GainConfig::paper();
  config.rays_x = rays_x;
  config.rays_y = rays_x * 3 / 4;
  InformationGain gain;
  gain.setInputMap(benchMap(3));
  gain.setRoi(benchRoi(kind));
  gain.setNumberOfThreads(2);
  gain.setConfig(config);
  const std::vector<Viewpoint> views0 = candidates();
  std::vector<ViewGain> out;
  gain.compute(views0, out); // warm: buffers allocated, pages touched
  double step_ms = 0.0;
  for (auto _ : state) {
    gain.update();
    gain.compute(views0, out);
    step_ms += gain.getLastStats().update_ms + gain.getLastStats().gain_ms;
  }
  double same = 0.0, loss = 0.0, loss_max = 0.0, corr = 0.0, n = 0.0;
  for (const int views : {1, 3, 6})
    for (int seed = 0; seed < kStudySeeds; ++seed) {
      const std::vector<ViewGain>& g = studyGains(views, kind, seed, rays_x);
      const std::vector<ViewGain>& f = studyGains(views, kind, seed, kFinestX);
      const std::size_t best = argMax(g), best_f = argMax(f);
      same += best == best_f ? 1.0 : 0.0;
      const double l = f[best_f].gain > 0.0 ? 1.0 - f[best].gain / f[best_f].gain : 0.0;
      loss += l;
      loss_max = std::max(loss_max, l);
      corr += rankCorrelation(g, f);
      n += 1.0;
    }
  state.counters["same_choice"] = same / n;
  state.counters["gain_loss"] = loss / n;
  state.counters["gain_loss_max"] = loss_max;
  state.counters["rank_corr"] = corr / n;
  state.counters["step_ms"] = step_ms / static_cast<double>(state.iterations());
}

void benchSnapshot(benchmark::State& state, int views, RoiKind kind, int threads,
                   bool after_insert)
{
  const OccupancyMapSnapshot before(*benchMap(after_insert ? views - 1 : views));
  const BenchView& last = benchViews()[static_cast<std::size_t>(views - 1)];
  InformationGain gain;
  gain.setConfig(GainConfig::paper());
  gain.setRoi(benchRoi(kind));
  gain.setNumberOfThreads(threads);
  for (auto _ : state) {
    const std::shared_ptr<OccupancyMap> map = before.restore();
    gain.setInputMap(map);
    gain.update(); // anew: a new map
    if (after_insert) {
      map->insert(last.frame, last.pose.position);
      gain.update();
    }
    state.SetIterationTime(gain.getLastStats().update_ms / 1000.0);
  }
  state.counters["incremental"] = gain.getLastStats().incremental ? 1 : 0;
  state.counters["leaves"] = static_cast<double>(gain.getLastStats().leaves);
  state.counters["bricks"] = static_cast<double>(gain.getLastStats().bricks);
}

const char* roiName(RoiKind kind)
{
  return roiKindName(kind);
}

} // namespace

int main(int argc, char** argv)
{
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  const RoiKind kinds[] = {RoiKind::whole_plant, RoiKind::main_stem, RoiKind::leaf_nodes};
  // The default grid (48 x 36) throughout; 64 x 48 (the grid of the figures in
  // shared/notes/performance-findings.md) for ours, and for the reference on one case.
  const int default_x = GainConfig().rays_x;
  for (const int rays_x : {default_x, 64})
    for (const int views : {1, 3, 6})
      for (const RoiKind kind : kinds)
        for (const int threads : {1, 2}) {
          const std::string suffix =
              std::string("/") + roiName(kind) + "/views:" + std::to_string(views) +
              "/rays:" + std::to_string(rays_x) + "x" + std::to_string(rays_x * 3 / 4) +
              "/threads:" + std::to_string(threads);
          benchmark::RegisterBenchmark(("gain/ours" + suffix).c_str(), benchOurs, views,
                                       kind, threads, rays_x)
              ->Unit(benchmark::kMillisecond)
              ->MinTime(0.5);
          if (rays_x == default_x ||
              (views == 3 && kind == RoiKind::whole_plant && threads == 2))
            benchmark::RegisterBenchmark(("gain/reference" + suffix).c_str(),
                                         benchReference, views, kind, threads, rays_x)
                ->Unit(benchmark::kMillisecond)
                ->Iterations(1);
        }
  for (const int views : {3, 6})
    for (const RoiKind kind : {RoiKind::whole_plant, RoiKind::leaf_nodes})
      for (const int threads : {1, 2})
        for (const bool after_insert : {false, true}) {
          const std::string name = std::string("snapshot/") +
                                   (after_insert ? "after_insert/" : "new/") +
                                   roiName(kind) + "/views:" + std::to_string(views) +
                                   "/threads:" + std::to_string(threads);
          benchmark::RegisterBenchmark(name.c_str(), benchSnapshot, views, kind, threads,
                                       after_insert)
              ->Unit(benchmark::kMillisecond)
              ->UseManualTime()
              ->Iterations(10);
        }
  for (const RoiKind kind : kinds)
    for (const int rays_x : {16, 24, 32, 48, 64, 96, 128, 160}) {
      const std::string name = std::string("ray_count/") + roiName(kind) +
                               "/rays:" + std::to_string(rays_x) + "x" +
                               std::to_string(rays_x * 3 / 4);
      benchmark::RegisterBenchmark(name.c_str(), benchRayCount, kind, rays_x)
          ->Unit(benchmark::kMillisecond)
          ->MinTime(1.0);
    }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
