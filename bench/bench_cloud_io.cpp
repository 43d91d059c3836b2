/// \file bench_cloud_io.cpp
/// \brief Reading and writing point clouds: io::loadCloud / io::saveCloud (our PCD and
/// PLY readers and writers) against PCL's io library (pcl::io::loadPCDFile, loadPLYFile,
/// PCDWriter), which plantnbv used before (docs/performance.md, "Point cloud files").
///
/// Data: 1,000,000 random XYZL points (a few frames' worth) in each layout. The files
/// are written once to a temporary folder; each iteration reads or writes one file.
/// Run (machine quiet):
///   bench_cloud_io --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <filesystem>
#include <string>

#include <benchmark/benchmark.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/random.h>
#include <plantnbv/io/cloud_io.h>

namespace {

using namespace plantnbv;

constexpr std::size_t kPoints = 1000000;

struct Files {
  std::string dir;
  CloudXYZL cloud;
  std::string pcd_binary, pcd_ascii, pcd_compressed, ply_binary;
};

const Files& files()
{
  static const Files f = [] {
    Files f;
    f.dir = (std::filesystem::temp_directory_path() / "plantnbv_bench_cloud_io").string();
    std::filesystem::create_directories(f.dir);
    Rng rng(1);
    f.cloud.reserve(kPoints);
    for (std::size_t i = 0; i < kPoints; ++i) {
      pcl::PointXYZL p;
      p.x = static_cast<float>(rng.uniform(-1.0, 1.0));
      p.y = static_cast<float>(rng.uniform(-1.0, 1.0));
      p.z = static_cast<float>(rng.uniform(0.0, 2.0));
      p.label = static_cast<std::uint32_t>(rng.index(7));
      f.cloud.push_back(p);
    }
    f.pcd_binary = f.dir + "/binary.pcd";
    f.pcd_ascii = f.dir + "/ascii.pcd";
    f.pcd_compressed = f.dir + "/compressed.pcd";
    f.ply_binary = f.dir + "/binary.ply";
    pcl::PCDWriter writer;
    writer.writeBinary(f.pcd_binary, f.cloud);
    writer.writeASCII(f.pcd_ascii, f.cloud, 9);
    writer.writeBinaryCompressed(f.pcd_compressed, f.cloud);
    io::saveCloud(f.ply_binary, f.cloud, true);
    return f;
  }();
  return f;
}

const std::string& fileOf(int layout)
{
  const Files& f = files();
  return layout == 0   ? f.pcd_binary
         : layout == 1 ? f.pcd_ascii
         : layout == 2 ? f.pcd_compressed
                       : f.ply_binary;
}

const char* const kLayouts[] = {"pcd_binary", "pcd_ascii", "pcd_compressed",
                                "ply_binary"};

void BM_LoadOurs(benchmark::State& state)
{
  const std::string& path = fileOf(static_cast<int>(state.range(0)));
  state.SetLabel(kLayouts[state.range(0)]);
  CloudXYZL cloud;
  for (auto _ : state) {
    io::loadCloud(path, cloud);
    benchmark::DoNotOptimize(cloud.points.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kPoints));
}
BENCHMARK(BM_LoadOurs)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

void BM_LoadPcl(benchmark::State& state)
{
  const std::string& path = fileOf(static_cast<int>(state.range(0)));
  state.SetLabel(kLayouts[state.range(0)]);
  CloudXYZL cloud;
  for (auto _ : state) {
    const int status = state.range(0) == 3 ? pcl::io::loadPLYFile(path, cloud)
                                           : pcl::io::loadPCDFile(path, cloud);
    if (status != 0)
      state.SkipWithError("PCL could not read the file");
    benchmark::DoNotOptimize(cloud.points.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kPoints));
}
BENCHMARK(BM_LoadPcl)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

void BM_SaveOurs(benchmark::State& state)
{
  const bool binary = state.range(0) == 0;
  state.SetLabel(binary ? "pcd_binary" : "pcd_ascii");
  const std::string path = files().dir + "/ours_out.pcd";
  for (auto _ : state)
    io::saveCloud(path, files().cloud, binary);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kPoints));
}
BENCHMARK(BM_SaveOurs)->DenseRange(0, 1)->Unit(benchmark::kMillisecond);

void BM_SavePcl(benchmark::State& state)
{
  const bool binary = state.range(0) == 0;
  state.SetLabel(binary ? "pcd_binary" : "pcd_ascii");
  const std::string path = files().dir + "/pcl_out.pcd";
  pcl::PCDWriter writer;
  for (auto _ : state)
    binary ? writer.writeBinary(path, files().cloud)
           : writer.writeASCII(path, files().cloud, 9);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(kPoints));
}
BENCHMARK(BM_SavePcl)->DenseRange(0, 1)->Unit(benchmark::kMillisecond);

} // namespace

BENCHMARK_MAIN();
