/// \file bench_occupancy_map.cpp
/// \brief Inserting depth frames into a 3 mm occupancy map: OctoMap's own
/// OcTree::insertPointCloud (plain and discretized) side by side with
/// plantnbv::OccupancyMap::insert, at 1 and 2 threads.
///
/// Data: surface samples (3M, seed 1) of the synthetic plant (tests/support), seen by a
/// 640x480 pinhole camera (fx = fy = 457 px, about 70 x 55 deg, an L515-like depth
/// camera) from 10 viewpoints 0.4 m from the stem, yaw -45..45 deg, height 0.2..0.45 m,
/// looking horizontally at the stem. Each pixel keeps its nearest sample (z-buffer).
/// Two scenes: "plant": pixels without a plant sample have no return (NaN, dropped by
/// every method); "plant_bg": they see a background 1.5 m away, beyond the 0.75 m range,
/// so every pixel carves free space up to 0.75 m (all 307,200 rays).
///
/// One iteration inserts the 10 frames in sequence into a new map (the map's
/// construction and destruction are not timed); counters give the mean per frame
/// (frame_ms) and the first frame (first_ms). OctoMap gets the finite points as an
/// octomap::Pointcloud (the conversion is timed: a user must do it). Its OpenMP loop runs
/// with keyrays.size() threads (OcTree sizes it to 1; a subclass resizes it for 2).
///
/// After timing, the map of each method is compared with the map of OctoMap's plain
/// insertPointCloud on one thread (built once per scene), voxel by voxel at 3 mm:
/// diff_log_odds counts voxels whose log-odds (or known-ness) differ, diff_state those
/// whose state (unknown / free / occupied) differs; known_voxels is the reference's
/// number of known voxels. Run:
///   bench_occupancy_map --benchmark_repetitions=5
///   --benchmark_report_aggregates_only=true

#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <octomap/OcTree.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/sampling/mesh_sampler.h>

#include "synthetic_plant.h"

namespace {

using plantnbv::CloudXYZ;
using plantnbv::OccupancyMap;

constexpr int kWidth = 640;
constexpr int kHeight = 480;
constexpr double kFocalPx = 457.0;
constexpr int kFrames = 10;
constexpr double kBackgroundDepthM = 1.5;

struct Frame {
  CloudXYZ cloud; ///< organized 640x480, world frame
  Eigen::Vector3d origin;
  std::size_t plant_pixels = 0;
};

/// The 10 frames of a scene (cached).
const std::vector<Frame>& frames(bool background)
{
  static std::map<bool, std::vector<Frame>> cache;
  auto& out = cache[background];
  if (!out.empty())
    return out;
  static const CloudXYZ samples = [] {
    plantnbv::MeshSampler sampler;
    sampler.setInputMesh(std::make_shared<const plantnbv::TriangleMesh>(
        plantnbv::test::makeSyntheticPlant()));
    sampler.setNumberOfPoints(3000000);
    sampler.setSeed(1);
    CloudXYZ cloud;
    sampler.sample(cloud);
    return cloud;
  }();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const double pi = std::acos(-1.0);
  for (int f = 0; f < kFrames; ++f) {
    const double yaw = (-45.0 + 10.0 * f) * pi / 180.0;
    const double height = 0.2 + 0.25 * f / (kFrames - 1.0);
    Frame frame;
    frame.origin = Eigen::Vector3d(0.4 * std::cos(yaw), 0.4 * std::sin(yaw), height);
    // Optical frame: z towards the stem (horizontal), x right, y down.
    const Eigen::Vector3d z_axis = -Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0.0);
    const Eigen::Vector3d y_axis(0.0, 0.0, -1.0);
    const Eigen::Vector3d x_axis = y_axis.cross(z_axis);
    std::vector<float> depth(kWidth * kHeight, std::numeric_limits<float>::infinity());
    std::vector<std::int32_t> nearest(kWidth * kHeight, -1);
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const Eigen::Vector3d p(samples[i].x, samples[i].y, samples[i].z);
      const Eigen::Vector3d d = p - frame.origin;
      const double z = d.dot(z_axis);
      if (z <= 0.01)
        continue;
      const long u = std::lround(kFocalPx * d.dot(x_axis) / z + (kWidth - 1) / 2.0);
      const long v = std::lround(kFocalPx * d.dot(y_axis) / z + (kHeight - 1) / 2.0);
      if (u < 0 || v < 0 || u >= kWidth || v >= kHeight)
        continue;
      const std::size_t pixel = static_cast<std::size_t>(v * kWidth + u);
      if (z < depth[pixel]) {
        depth[pixel] = static_cast<float>(z);
        nearest[pixel] = static_cast<std::int32_t>(i);
      }
    }
    frame.cloud.width = kWidth;
    frame.cloud.height = kHeight;
    frame.cloud.is_dense = background;
    frame.cloud.resize(static_cast<std::size_t>(kWidth) * kHeight);
    for (int v = 0; v < kHeight; ++v)
      for (int u = 0; u < kWidth; ++u) {
        const std::size_t pixel = static_cast<std::size_t>(v * kWidth + u);
        pcl::PointXYZ& q = frame.cloud[pixel];
        if (nearest[pixel] >= 0) {
          q = samples[static_cast<std::size_t>(nearest[pixel])];
          ++frame.plant_pixels;
        } else if (background) {
          const Eigen::Vector3d ray = (u - (kWidth - 1) / 2.0) / kFocalPx * x_axis +
                                      (v - (kHeight - 1) / 2.0) / kFocalPx * y_axis +
                                      z_axis;
          const Eigen::Vector3d p = frame.origin + kBackgroundDepthM * ray;
          q = pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                            static_cast<float>(p.z()));
        } else {
          q = pcl::PointXYZ(nan, nan, nan);
        }
      }
    out.push_back(std::move(frame));
  }
  return out;
}

std::unique_ptr<OccupancyMap> makeOurs(int threads)
{
  auto map = std::make_unique<OccupancyMap>(); // the paper's parameters
  map->setNumberOfThreads(threads);
  return map;
}

/// An OcTree whose OpenMP loop in insertPointCloud uses `threads` KeyRay buffers.
class ThreadedOcTree : public octomap::OcTree {
public:
  ThreadedOcTree(int threads) : octomap::OcTree(OccupancyMap::Config().resolution_m)
  {
    const OccupancyMap::Config c;
    setProbHit(c.prob_hit);
    setProbMiss(c.prob_miss);
    setClampingThresMin(c.clamp_min);
    setClampingThresMax(c.clamp_max);
    setOccupancyThres(c.occupancy_threshold);
    keyrays.resize(static_cast<std::size_t>(threads));
  }
};

void octomapInsert(octomap::OcTree& tree, const Frame& frame, bool discretize)
{
  octomap::Pointcloud scan;
  scan.reserve(frame.cloud.size());
  for (const auto& p : frame.cloud)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
      scan.push_back(p.x, p.y, p.z);
  const octomap::point3d origin(static_cast<float>(frame.origin.x()),
                                static_cast<float>(frame.origin.y()),
                                static_cast<float>(frame.origin.z()));
  tree.insertPointCloud(scan, origin, OccupancyMap::Config().max_range_m,
                        /*lazy_eval=*/false, discretize);
}

struct Diff {
  std::uint64_t log_odds = 0, state = 0;
};

/// Voxel-level difference of two trees; a pruned leaf stands for all its voxels.
void diffNodes(const octomap::OcTree& ta, const octomap::OcTreeNode* a,
               const octomap::OcTree& tb, const octomap::OcTreeNode* b, unsigned depth,
               Diff& out)
{
  const bool a_inner = a && ta.nodeHasChildren(a);
  const bool b_inner = b && tb.nodeHasChildren(b);
  if (!a_inner && !b_inner) {
    const std::uint64_t voxels = std::uint64_t{1} << (3 * (16 - depth));
    if (!a && !b)
      return;
    if (!a || !b) {
      out.log_odds += voxels;
      out.state += voxels;
      return;
    }
    out.log_odds += a->getLogOdds() != b->getLogOdds() ? voxels : 0;
    out.state += ta.isNodeOccupied(a) != tb.isNodeOccupied(b) ? voxels : 0;
    return;
  }
  for (unsigned i = 0; i < 8; ++i) {
    const octomap::OcTreeNode* ca =
        a_inner ? (ta.nodeChildExists(a, i) ? ta.getNodeChild(a, i) : nullptr) : a;
    const octomap::OcTreeNode* cb =
        b_inner ? (tb.nodeChildExists(b, i) ? tb.getNodeChild(b, i) : nullptr) : b;
    diffNodes(ta, ca, tb, cb, depth + 1, out);
  }
}

Diff diffTrees(const octomap::OcTree& a, const octomap::OcTree& b)
{
  Diff d;
  diffNodes(a, a.getRoot(), b, b.getRoot(), 0, d);
  return d;
}

/// OctoMap's plain insertPointCloud on one thread over the 10 frames: the reference.
const octomap::OcTree& reference(bool background)
{
  static std::map<bool, std::unique_ptr<octomap::OcTree>> cache;
  auto& tree = cache[background];
  if (!tree) {
    tree = std::make_unique<ThreadedOcTree>(1);
    for (const Frame& frame : frames(background))
      octomapInsert(*tree, frame, false);
  }
  return *tree;
}

std::uint64_t knownVoxels(const octomap::OcTree& tree)
{
  std::uint64_t n = 0;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it)
    n += std::uint64_t{1} << (3 * (16 - it.getDepth()));
  return n;
}

enum class Method { plain, discretize, ours };

void benchInsert(benchmark::State& state, Method method, bool background, int threads)
{
  const std::vector<Frame>& input = frames(background);
  const octomap::OcTree& ref = reference(background);
  using Clock = std::chrono::steady_clock;
  double first_ms = 0.0, rays_ms = 0.0, traverse_ms = 0.0, update_ms = 0.0;
  Diff diff;
  double total_s = 0.0;
  for (auto _ : state) {
    std::unique_ptr<OccupancyMap> ours;
    std::unique_ptr<ThreadedOcTree> tree;
    if (method == Method::ours)
      ours = makeOurs(threads);
    else
      tree = std::make_unique<ThreadedOcTree>(threads);
    double total = 0.0;
    rays_ms = traverse_ms = update_ms = 0.0;
    for (std::size_t f = 0; f < input.size(); ++f) {
      const auto start = Clock::now();
      if (ours)
        ours->insert(input[f].cloud, input[f].origin);
      else
        octomapInsert(*tree, input[f], method == Method::discretize);
      const double s = std::chrono::duration<double>(Clock::now() - start).count();
      total += s;
      if (f == 0)
        first_ms = 1e3 * s;
      if (ours) {
        rays_ms += ours->getLastInsertStats().rays_ms;
        traverse_ms += ours->getLastInsertStats().traverse_ms;
        update_ms += ours->getLastInsertStats().update_ms;
      }
    }
    state.SetIterationTime(total);
    total_s += total;
    state.PauseTiming();
    diff = diffTrees(ours ? ours->getOcTree() : *tree, ref);
    state.ResumeTiming();
  }
  const double frames_n = static_cast<double>(input.size());
  state.counters["frame_ms"] =
      1e3 * total_s / (frames_n * static_cast<double>(state.iterations()));
  state.counters["first_ms"] = first_ms;
  if (method == Method::ours) {
    state.counters["rays_ms"] = rays_ms / frames_n;
    state.counters["traverse_ms"] = traverse_ms / frames_n;
    state.counters["update_ms"] = update_ms / frames_n;
  }
  state.counters["threads"] = threads;
  state.counters["diff_log_odds"] = static_cast<double>(diff.log_odds);
  state.counters["diff_state"] = static_cast<double>(diff.state);
  state.counters["known_voxels"] = static_cast<double>(knownVoxels(ref));
  std::size_t plant_pixels = 0;
  for (const Frame& f : input)
    plant_pixels += f.plant_pixels;
  state.counters["plant_px"] = static_cast<double>(plant_pixels) / frames_n;
}

} // namespace

int main(int argc, char** argv)
{
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  for (const bool background : {false, true}) {
    const std::string scene = background ? "plant_bg" : "plant";
    for (const int threads : {1, 2})
      for (const auto& [name, method] :
           {std::pair<const char*, Method>{"octomap_plain", Method::plain},
            {"octomap_discretize", Method::discretize},
            {"ours", Method::ours}}) {
        const std::string full = std::string("occupancy_map/") + name + "/" + scene +
                                 "/threads:" + std::to_string(threads);
        benchmark::RegisterBenchmark(full.c_str(), benchInsert, method, background,
                                     threads)
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond)
            ->Iterations(background ? 1 : 3);
      }
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
