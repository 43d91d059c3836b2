#include <algorithm>
#include <cmath>
#include <sstream>

#include <octomap/OcTree.h>
#include <pcl/common/io.h>
#include <pcl/filters/filter.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/memory_cap.h>
#include <plantnbv/filters/voxel_grid_filter.h>
#include <plantnbv/io/cloud_io.h>
#include <plantnbv/io/file_kind.h>
#include <plantnbv/io/mesh_io.h>
#include <plantnbv/octree/octree_conversion.h>
#include <plantnbv/sampling/mesh_sampler.h>
#include <plantnbv/scenario/geometry_input.h>

namespace plantnbv {
namespace scenario {

void loadGeometryAsCloud(const std::string& path, const std::string& what,
                         const GeometryInputOptions& options, CloudXYZ& cloud,
                         std::string& summary)
{
  std::ostringstream s;
  switch (io::fileKind(path)) {
  case io::FileKind::cloud: {
    CloudXYZ raw;
    io::loadCloud(path, raw);
    pcl::Indices finite;
    pcl::removeNaNFromPointCloud(raw, cloud, finite);
    s << "cloud, " << raw.size() << " points";
    if (cloud.size() != raw.size())
      s << " (" << raw.size() - cloud.size() << " non-finite dropped)";
    if (cloud.empty())
      throw FormatError(what + " '" + path + "' holds no finite point");
    break;
  }
  case io::FileKind::mesh: {
    auto mesh = std::make_shared<TriangleMesh>(io::loadMesh(path));
    MeshSampler sampler;
    sampler.setInputMesh(mesh);
    const std::size_t n =
        options.mesh_points
            ? options.mesh_points
            : groundTruthSampleCount(sampler.getSurfaceArea(), options.resolution);
    requireWithinMemoryCap(
        sampledCloudMemoryBytes(static_cast<double>(n), sizeof(pcl::PointXYZ)),
        kDefaultMemoryCapBytes,
        "the " + std::to_string(n) + " surface samples of '" + path + "'");
    sampler.setNumberOfPoints(n);
    sampler.setSeed(options.seed);
    auto samples = std::make_shared<CloudXYZ>();
    sampler.sample(*samples);
    VoxelGridFilter<pcl::PointXYZ> voxel_grid;
    voxel_grid.setLeafSize(options.resolution);
    voxel_grid.setOutputVoxelCentres(
        true); // ground truth as a map has it (docs/trials.md)
    voxel_grid.setInputCloud(samples);
    voxel_grid.filter(cloud);
    s << "mesh, " << mesh->size() << " triangles, " << n << " samples, " << cloud.size()
      << " voxel centres of " << options.resolution << " m";
    break;
  }
  case io::FileKind::octree: {
    const auto tree = readOcTree(path);
    try {
      occupiedVoxelCentres(*tree, cloud);
    } catch (const InvalidArgumentError& e) { // over the memory cap: name the file
      throw InvalidArgumentError("'" + path + "': " + e.what());
    }
    s << "octree at " << tree->getResolution() << " m, " << cloud.size()
      << " occupied voxels";
    break;
  }
  }
  summary = s.str();
}

} // namespace scenario
} // namespace plantnbv
