/// \file bench_metrics.cpp
/// \brief Chamfer distance and precision / recall / F1 of two clouds, ours side by side
/// with what users would write instead: a PCL KdTreeFLANN loop, Open3D's
/// PointCloud::ComputePointCloudDistance and plain nanoflann. And the same tree behind
/// pcl::search (search::MortonKdTree) against pcl::search::KdTree: rows search/...
///
/// Data: surface samples of a plant-like mesh (the reference T) and a copy with 1 mm
/// Gaussian noise per coordinate (the reconstruction R), 50k and 300k points each.
/// Every method starts from the two clouds: the timing includes building both trees,
/// both nearest-neighbour directions and the sums. Open3D's clouds are converted to its
/// format beforehand (untimed). After timing, each method's per-point distances are
/// checked against ours: counter max_diff_m is the largest difference in metres.
///
/// The search/ rows time what a PCL user does with a pcl::search::Search<PointXYZ>:
/// setInputCloud(T), then nearestKSearch(p, 1, ...) for every point p of R in cloud order
/// (the samples' order, spatially random), in an OpenMP loop. Counter build_ms is the
/// setInputCloud part; max_diff_m compares sqrt of the returned float squared distances
/// with our metrics' exact distances.
///
/// Open3D 0.16 sizes its loops by utility::EstimateMaxThreads(): all cores unless
/// OMP_NUM_THREADS is set, omp_get_max_threads() when it is. So run with OMP_NUM_THREADS
/// set (any value) to get Open3D rows for 1 and 2 threads; without it there is one Open3D
/// row, on all cores. Every row reports the thread count used. Run:
///   OMP_NUM_THREADS=2 bench_metrics --benchmark_repetitions=5
///       --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>
#include <nanoflann.hpp>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include <plantnbv/common/random.h>
#include <plantnbv/metrics/morton_kdtree.h>
#include <plantnbv/metrics/reconstruction_metrics.h>
#include <plantnbv/sampling/mesh_sampler.h>

#include "synthetic_plant.h"

#ifdef PLANTNBV_BENCH_OPEN3D
#include <open3d/geometry/PointCloud.h>
#include <open3d/utility/Parallel.h>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <memory>
#include <omp.h>
#include <string>
#include <vector>

namespace {

using plantnbv::CloudXYZ;
constexpr double kRho = 0.003; // the paper's rho (map resolution)

struct Scores {
  double chamfer = 0.0, precision = 0.0, recall = 0.0, f1 = 0.0;
};

/// Per-point distances of both directions, and the metrics summed from them.
struct Distances {
  std::vector<double> r_to_t, t_to_r;
};

Scores summarize(const Distances& d)
{
  Scores s;
  double sum_r = 0.0, sum_t = 0.0;
  std::size_t in_r = 0, in_t = 0;
  for (double v : d.r_to_t) {
    sum_r += v;
    in_r += v < kRho;
  }
  for (double v : d.t_to_r) {
    sum_t += v;
    in_t += v < kRho;
  }
  s.chamfer = sum_r / double(d.r_to_t.size()) + sum_t / double(d.t_to_r.size());
  s.precision = double(in_r) / double(d.r_to_t.size());
  s.recall = double(in_t) / double(d.t_to_r.size());
  s.f1 = 2.0 * s.precision * s.recall / (s.precision + s.recall);
  return s;
}

struct Data {
  CloudXYZ::Ptr reference, reconstruction;
  Distances ours; ///< our per-point distances, the reference of the checks
  Scores ours_scores;
#ifdef PLANTNBV_BENCH_OPEN3D
  open3d::geometry::PointCloud o3d_reference, o3d_reconstruction;
#endif
};

const Data& data(std::size_t n)
{
  static std::map<std::size_t, std::unique_ptr<Data>> cache;
  auto& d = cache[n];
  if (d)
    return *d;
  d = std::make_unique<Data>();
  static const auto mesh = std::make_shared<const plantnbv::TriangleMesh>(
      plantnbv::test::makeSyntheticPlant());
  plantnbv::MeshSampler sampler;
  sampler.setInputMesh(mesh);
  sampler.setNumberOfPoints(n);
  sampler.setSeed(1);
  d->reference = std::make_shared<CloudXYZ>();
  sampler.sample(*d->reference);
  d->reconstruction = std::make_shared<CloudXYZ>(*d->reference);
  plantnbv::Rng rng(2);
  for (auto& p : *d->reconstruction) {
    p.x += float(0.001 * rng.normal());
    p.y += float(0.001 * rng.normal());
    p.z += float(0.001 * rng.normal());
  }
  plantnbv::ReconstructionMetrics metrics;
  metrics.setThreshold(kRho);
  metrics.setReference(d->reference);
  metrics.setReconstruction(d->reconstruction);
  metrics.computeDistances(d->ours.r_to_t, d->ours.t_to_r);
  d->ours_scores = summarize(d->ours);
#ifdef PLANTNBV_BENCH_OPEN3D
  for (const auto& p : *d->reference)
    d->o3d_reference.points_.emplace_back(p.x, p.y, p.z);
  for (const auto& p : *d->reconstruction)
    d->o3d_reconstruction.points_.emplace_back(p.x, p.y, p.z);
#endif
  return *d;
}

/// The counters every row shows: the metrics, and the largest per-point difference to
/// ours (when the method's distances are given).
void report(benchmark::State& state, const Scores& s, int threads,
            const Distances* distances, const Data& d)
{
  state.counters["threads"] = threads;
  state.counters["chamfer_m"] = s.chamfer;
  state.counters["precision"] = s.precision;
  state.counters["recall"] = s.recall;
  state.counters["f1"] = s.f1;
  if (!distances)
    return;
  double max_diff = 0.0;
  for (std::size_t i = 0; i < d.ours.r_to_t.size(); ++i)
    max_diff = std::max(max_diff, std::abs(distances->r_to_t[i] - d.ours.r_to_t[i]));
  for (std::size_t i = 0; i < d.ours.t_to_r.size(); ++i)
    max_diff = std::max(max_diff, std::abs(distances->t_to_r[i] - d.ours.t_to_r[i]));
  state.counters["max_diff_m"] = max_diff;
  state.counters["chamfer_diff_m"] = std::abs(s.chamfer - d.ours_scores.chamfer);
  state.counters["prf_differ"] = s.precision != d.ours_scores.precision ||
                                 s.recall != d.ours_scores.recall ||
                                 s.f1 != d.ours_scores.f1;
}

void benchOurs(benchmark::State& state, std::size_t n, int threads)
{
  const Data& d = data(n);
  plantnbv::MetricsResult m;
  for (auto _ : state) {
    plantnbv::ReconstructionMetrics metrics;
    metrics.setNumberOfThreads(threads);
    metrics.setThreshold(kRho);
    metrics.setReference(d.reference);
    metrics.setReconstruction(d.reconstruction);
    m = metrics.compute();
    benchmark::DoNotOptimize(m);
  }
  report(state, {m.chamfer, m.precision, m.recall, m.f1}, threads, nullptr, d);
  state.counters["chamfer_diff_m"] = std::abs(m.chamfer - d.ours_scores.chamfer);
}

void pclDirection(const CloudXYZ& queries, const pcl::KdTreeFLANN<pcl::PointXYZ>& tree,
                  int threads, std::vector<double>& out)
{
  out.resize(queries.size());
  const auto n = static_cast<long long>(queries.size());
#pragma omp parallel num_threads(threads)
  {
    std::vector<int> index(1);
    std::vector<float> sqr_dists(1);
#pragma omp for schedule(dynamic, 1024)
    for (long long i = 0; i < n; ++i) {
      tree.nearestKSearch(queries[i], 1, index, sqr_dists);
      out[i] = std::sqrt(double(sqr_dists[0]));
    }
  }
}

void benchPclKdTreeFlann(benchmark::State& state, std::size_t n, int threads)
{
  const Data& d = data(n);
  Distances dist;
  Scores s;
  for (auto _ : state) {
    pcl::KdTreeFLANN<pcl::PointXYZ> reference_tree, reconstruction_tree;
    reference_tree.setInputCloud(d.reference);
    reconstruction_tree.setInputCloud(d.reconstruction);
    pclDirection(*d.reconstruction, reference_tree, threads, dist.r_to_t);
    pclDirection(*d.reference, reconstruction_tree, threads, dist.t_to_r);
    s = summarize(dist);
    benchmark::DoNotOptimize(s);
  }
  report(state, s, threads, &dist, d);
}

/// nanoflann over a PCL cloud, float coordinates, double distances.
struct NanoflannCloud {
  const CloudXYZ& cloud;
  std::size_t kdtree_get_point_count() const { return cloud.size(); }
  float kdtree_get_pt(std::size_t i, std::size_t dim) const { return cloud[i].data[dim]; }
  template <typename Box>
  bool kdtree_get_bbox(Box&) const
  {
    return false;
  }
};
using NanoflannTree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<float, NanoflannCloud, double>, NanoflannCloud, 3,
    std::uint32_t>;

void nanoflannDirection(const CloudXYZ& queries, const NanoflannTree& tree, int threads,
                        std::vector<double>& out)
{
  out.resize(queries.size());
  const auto n = static_cast<long long>(queries.size());
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1024)
  for (long long i = 0; i < n; ++i) {
    std::uint32_t index;
    double sqr_dist;
    tree.knnSearch(queries[i].data, 1, &index, &sqr_dist);
    out[i] = std::sqrt(sqr_dist);
  }
}

void benchNanoflann(benchmark::State& state, std::size_t n, int threads)
{
  const Data& d = data(n);
  Distances dist;
  Scores s;
  for (auto _ : state) {
    const NanoflannCloud reference{*d.reference}, reconstruction{*d.reconstruction};
    // The constructor builds the index (nanoflann 1.4).
    const NanoflannTree reference_tree(3, reference),
        reconstruction_tree(3, reconstruction);
    nanoflannDirection(*d.reconstruction, reference_tree, threads, dist.r_to_t);
    nanoflannDirection(*d.reference, reconstruction_tree, threads, dist.t_to_r);
    s = summarize(dist);
    benchmark::DoNotOptimize(s);
  }
  report(state, s, threads, &dist, d);
}

/// Our tree builds on the row's threads (PCL's on one, always).
void setBuildThreads(plantnbv::search::MortonKdTree<pcl::PointXYZ>& search, int threads)
{
  search.setNumberOfThreads(threads);
}
void setBuildThreads(pcl::search::KdTree<pcl::PointXYZ>&, int) {}

/// k = 1 through a pcl::search::Search: build on T, then the nearest of each point of R.
template <typename Search>
void benchSearch(benchmark::State& state, std::size_t n, int threads)
{
  const Data& d = data(n);
  const CloudXYZ& queries = *d.reconstruction;
  const auto n_queries = static_cast<long long>(queries.size());
  std::vector<float> sqr_dists(queries.size());
  double build_s = 0.0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    Search search; // sorted results, the default of both
    setBuildThreads(search, threads);
    search.setInputCloud(d.reference);
    build_s +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
#pragma omp parallel num_threads(threads)
    {
      pcl::Indices index(1);
      std::vector<float> sqr_dist(1);
#pragma omp for schedule(dynamic, 1024)
      for (long long i = 0; i < n_queries; ++i) {
        search.nearestKSearch(queries[i], 1, index, sqr_dist);
        sqr_dists[i] = sqr_dist[0];
      }
    }
    benchmark::DoNotOptimize(sqr_dists.data());
  }
  state.counters["threads"] = threads;
  state.counters["build_ms"] = 1e3 * build_s / double(state.iterations());
  double max_diff = 0.0;
  for (std::size_t i = 0; i < queries.size(); ++i)
    max_diff =
        std::max(max_diff, std::abs(std::sqrt(double(sqr_dists[i])) - d.ours.r_to_t[i]));
  state.counters["max_diff_m"] = max_diff;
}

#ifdef PLANTNBV_BENCH_OPEN3D
/// threads = 0: Open3D's own choice.
void benchOpen3d(benchmark::State& state, std::size_t n, int threads)
{
  Data& d = const_cast<Data&>(data(n)); // ComputePointCloudDistance is not const
  const int saved = omp_get_max_threads();
  if (threads > 0)
    omp_set_num_threads(threads);
  const int used = open3d::utility::EstimateMaxThreads();
  Distances dist;
  Scores s;
  for (auto _ : state) {
    // Each call builds a KD-tree (FLANN) of its argument.
    dist.r_to_t = d.o3d_reconstruction.ComputePointCloudDistance(d.o3d_reference);
    dist.t_to_r = d.o3d_reference.ComputePointCloudDistance(d.o3d_reconstruction);
    s = summarize(dist);
    benchmark::DoNotOptimize(s);
  }
  omp_set_num_threads(saved);
  report(state, s, used, &dist, d);
}
#endif

} // namespace

int main(int argc, char** argv)
{
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  const auto add = [](const std::string& name, auto&&... args) {
    benchmark::RegisterBenchmark(name.c_str(), args...)
        ->UseRealTime()
        ->Unit(benchmark::kMillisecond);
  };
  for (const std::size_t n : {50000, 300000}) {
    const std::string size = std::to_string(n / 1000) + "k";
    for (const int threads : {1, 2}) {
      const std::string suffix = "/" + size + "/threads:" + std::to_string(threads);
      add("metrics/ours" + suffix, benchOurs, n, threads);
      add("metrics/pcl_kdtree_flann" + suffix, benchPclKdTreeFlann, n, threads);
      add("metrics/nanoflann" + suffix, benchNanoflann, n, threads);
#ifdef PLANTNBV_BENCH_OPEN3D
      if (std::getenv("OMP_NUM_THREADS"))
        add("metrics/open3d" + suffix, benchOpen3d, n, threads);
#endif
    }
#ifdef PLANTNBV_BENCH_OPEN3D
    if (!std::getenv("OMP_NUM_THREADS"))
      add("metrics/open3d/" + size + "/threads:all", benchOpen3d, n, 0);
#endif
  }
  for (const std::size_t n : {50000, 300000}) {
    const std::string size = std::to_string(n / 1000) + "k";
    for (const int threads : {1, 2}) {
      const std::string suffix = "/" + size + "/threads:" + std::to_string(threads);
      add("search/morton_kdtree" + suffix,
          benchSearch<plantnbv::search::MortonKdTree<pcl::PointXYZ>>, n, threads);
      add("search/pcl_kdtree" + suffix, benchSearch<pcl::search::KdTree<pcl::PointXYZ>>,
          n, threads);
    }
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
