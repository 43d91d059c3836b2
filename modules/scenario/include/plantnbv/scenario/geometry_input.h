#pragma once
// Loads any geometry file a tool accepts (cloud, mesh or octree) as a point cloud.

#include <cstdint>
#include <string>

#include <plantnbv/common/pcl_fwd.h>

namespace plantnbv {
namespace scenario {

/// \brief How loadGeometryAsCloud turns a mesh into points.
struct GeometryInputOptions {
  double resolution = 0.003;   ///< voxel size for meshes, metres
  std::size_t mesh_points = 0; ///< surface samples for meshes; 0 = automatic (see below)
  std::uint64_t seed = 0;      ///< sampling seed for meshes
};

/// \brief Reads `path` as points: a cloud as it is with non-finite points dropped, a mesh
/// sampled (seeded) then voxelized at the resolution (voxel centres on the map's lattice,
/// the ground truth of trials), an octree's occupied voxel centres. `what` names the
/// input in messages ("reference"); `summary` receives a one-line description of what was
/// done. An octree without occupied voxels gives an empty cloud (an empty
/// reconstruction). \throws plantnbv::Error subclasses on unreadable files and on a cloud
/// file without finite points.
void loadGeometryAsCloud(const std::string& path, const std::string& what,
                         const GeometryInputOptions& options, CloudXYZ& cloud,
                         std::string& summary);

} // namespace scenario
} // namespace plantnbv
