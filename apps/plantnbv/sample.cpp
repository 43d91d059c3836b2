// plantnbv sample: surface samples of a mesh, optionally noisy and voxelized.

#include <cmath>
#include <iostream>

#include <CLI/CLI.hpp>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/memory_cap.h>
#include <plantnbv/common/random.h>
#include <plantnbv/common/stopwatch.h>
#include <plantnbv/filters/voxel_grid_filter.h>
#include <plantnbv/io/cloud_io.h>
#include <plantnbv/io/file_kind.h>
#include <plantnbv/io/mesh_io.h>
#include <plantnbv/sampling/mesh_sampler.h>

#include "cli_checks.h"
#include "commands.h"

namespace plantnbv {
namespace app {

namespace {

struct SampleOptions {
  std::string mesh;
  std::size_t points = 100000;
  bool points_given = false; ///< else, with --voxel: the trials' ground-truth count
  bool centroids = false;    ///< --voxel keeps centroids instead of voxel centres
  double voxel = 0.0;
  double noise = 0.0;
  std::uint64_t seed = 0;
  bool labels = false;
  std::string output;
};

/// Adds isotropic Gaussian noise of standard deviation sigma to every coordinate.
template <typename PointT>
void addNoise(pcl::PointCloud<PointT>& cloud, double sigma, std::uint64_t seed)
{
  Rng rng(deriveSeed(seed, 1)); // independent of the sampling draws
  for (auto& p : cloud) {
    p.x += static_cast<float>(sigma * rng.normal());
    p.y += static_cast<float>(sigma * rng.normal());
    p.z += static_cast<float>(sigma * rng.normal());
  }
}

template <typename PointT>
void sampleAndSave(const SampleOptions& o, const std::shared_ptr<TriangleMesh>& mesh)
{
  Stopwatch clock;
  MeshSampler sampler;
  sampler.setInputMesh(mesh);
  // Ground truth at a resolution, as trials and `eval` make it: this many samples.
  const std::size_t points =
      o.voxel > 0.0 && !o.points_given
          ? groundTruthSampleCount(sampler.getSurfaceArea(), o.voxel)
          : o.points;
  sampler.setNumberOfPoints(points);
  sampler.setSeed(o.seed);
  auto cloud = std::make_shared<pcl::PointCloud<PointT>>();
  sampler.sample(*cloud);
  std::cout << "sampled " << cloud->size() << " points on " << mesh->size()
            << " triangles (area " << sampler.getSurfaceArea() << " m^2) in "
            << clock.ms() << " ms\n";
  if (o.noise > 0.0) {
    addNoise(*cloud, o.noise, o.seed);
    std::cout << "added Gaussian noise, sigma " << o.noise << " m\n";
  }
  if (o.voxel > 0.0) {
    Stopwatch voxel_clock;
    VoxelGridFilter<PointT> grid;
    grid.setLeafSize(o.voxel);
    grid.setOutputVoxelCentres(!o.centroids);
    grid.setInputCloud(cloud);
    auto voxelized = std::make_shared<pcl::PointCloud<PointT>>();
    grid.filter(*voxelized);
    std::cout << "voxelized at " << o.voxel << " m: " << voxelized->size()
              << (o.centroids ? " centroids" : " voxel centres") << " in "
              << voxel_clock.ms() << " ms\n";
    cloud = voxelized;
  }
  io::saveCloud(o.output, *cloud);
  std::cout << "wrote " << o.output << "\n";
}

void runSample(const SampleOptions& o)
{
  if (o.points == 0)
    throw InvalidArgumentError("--points must be > 0");
  if (!(o.voxel >= 0.0) || !std::isfinite(o.voxel))
    throw InvalidArgumentError("--voxel must be a finite size >= 0 in metres, got " +
                               std::to_string(o.voxel));
  if (!(o.noise >= 0.0) || !std::isfinite(o.noise))
    throw InvalidArgumentError("--noise must be a finite sigma >= 0 in metres, got " +
                               std::to_string(o.noise));
  const std::string ext = io::extensionOf(o.output);
  if (ext != ".pcd" && ext != ".ply")
    throw InvalidArgumentError("--output '" + o.output + "' must end in .pcd or .ply");
  requireWithinMemoryCap(
      sampledCloudMemoryBytes(static_cast<double>(o.points),
                              o.labels ? sizeof(pcl::PointXYZL) : sizeof(pcl::PointXYZ)),
      kDefaultMemoryCapBytes, "--points " + std::to_string(o.points));
  Stopwatch clock;
  auto mesh = std::make_shared<TriangleMesh>(io::loadMesh(o.mesh));
  std::cout << "loaded " << o.mesh << ": " << mesh->vertices.size() << " vertices, "
            << mesh->size() << " triangles in " << clock.ms() << " ms\n";
  if (o.labels)
    sampleAndSave<pcl::PointXYZL>(o, mesh);
  else
    sampleAndSave<pcl::PointXYZ>(o, mesh);
}

} // namespace

void addSampleCommand(CLI::App& app)
{
  auto o = std::make_shared<SampleOptions>();
  CLI::App* cmd = app.add_subcommand(
      "sample", "Sample points uniformly on a mesh surface (area-weighted, seeded)");
  cmd->add_option("--mesh", o->mesh, "Mesh file (.ply .obj .stl .dae .wrl)")->required();
  CLI::Option* points =
      cmd->add_option(
             "--points", o->points,
             "Number of surface samples (default 100000; with --voxel, the "
             "trials' ground-truth count: 8 per voxel^2 of surface, 10^4 to 2 10^7)")
          ->check(unsignedInteger());
  CLI::Option* voxel =
      cmd->add_option(
             "--voxel", o->voxel,
             "Voxelize at this size in metres: the centre of every voxel the samples "
             "fall in, on the map's lattice (ground truth as trials make it); 0 = off")
          ->capture_default_str();
  cmd->add_flag("--centroids", o->centroids,
                "With --voxel: keep each voxel's centroid of samples (pcl::VoxelGrid) "
                "instead of its centre")
      ->needs(voxel);
  cmd->add_option("--noise", o->noise,
                  "Gaussian noise sigma in metres added to each coordinate; 0 = off")
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "Random seed")
      ->check(unsignedInteger())
      ->capture_default_str();
  cmd->add_flag("--labels", o->labels, "Write part labels (pcl::PointXYZL)");
  cmd->add_option("-o,--output", o->output, "Output cloud (.pcd or .ply)")->required();
  cmd->callback([o, points]() {
    o->points_given = points->count() > 0;
    runSample(*o);
  });
}

} // namespace app
} // namespace plantnbv
