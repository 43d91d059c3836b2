#pragma once
/// \file mesh_sampler.h
/// \brief Area-weighted uniform sampling of a triangle mesh's surface.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <plantnbv/common/pcl_fwd.h>
#include <plantnbv/common/triangle_mesh.h>

namespace plantnbv {

/// \brief Draws N points uniformly over the surface of a mesh: each point falls on a
/// triangle with probability proportional to its area, then uniformly inside it.
///
/// The result depends only on the mesh, N and the seed (portable draws from `Rng`), not
/// on the machine or the thread count. Zero-area triangles never receive points.
/// \code
/// MeshSampler sampler;
/// sampler.setInputMesh(mesh);
/// sampler.setNumberOfPoints(100000);
/// sampler.setSeed(7);
/// sampler.sample(cloud);
/// \endcode
/// Not thread-safe; one sampler per thread.
class MeshSampler {
public:
  using MeshConstPtr = std::shared_ptr<const TriangleMesh>; ///< shared, read-only mesh

  /// \brief The mesh to sample; its area table is built here, once.
  /// \throws InvalidArgumentError if the mesh is null or has zero total area.
  void setInputMesh(const MeshConstPtr& mesh);
  /// \brief The mesh sampled, or null before setInputMesh().
  const MeshConstPtr& getInputMesh() const { return mesh_; }

  /// \param[in] n number of points to draw (default 100000); \throws if n == 0.
  void setNumberOfPoints(std::size_t n);
  /// \brief The number of points each sample() draws.
  std::size_t getNumberOfPoints() const { return n_points_; }

  /// \param[in] seed the random seed (default 0).
  void setSeed(std::uint64_t seed) { seed_ = seed; }
  /// \brief The random seed: the same seed, mesh and count give the same points.
  std::uint64_t getSeed() const { return seed_; }
  /// \brief Threads that make the points (default 1; 0: OpenMP's default). The points
  /// do not depend on it. \throws InvalidArgumentError for a negative count.
  void setNumberOfThreads(int threads);
  /// \brief The threads that make the points; 0 = OpenMP's default.
  int getNumberOfThreads() const { return threads_; }

  /// \brief Total surface area in square metres (after setInputMesh).
  double getSurfaceArea() const { return total_area_; }

  /// \brief Fills `cloud` (unorganized, width N, height 1, dense).
  /// \throws InvalidArgumentError if no mesh was set.
  void sample(CloudXYZ& cloud) const;
  /// \brief As above, with each point labelled by its triangle's PartLabel (unknown when
  /// the mesh has no labels).
  void sample(CloudXYZL& cloud) const;

private:
  /// Draws the points; calls store(i, point i, its triangle index) for i in [0, N), on
  /// several threads at once.
  template <typename Store>
  void draw(Store&& store) const;
  /// The guide of the area table: equal slices of the total area, each with the first
  /// triangle whose cumulative area exceeds the slice's start (empty: none).
  void buildGuide();
  /// The first triangle whose cumulative area exceeds u (std::upper_bound's answer).
  std::size_t triangleAt(double u) const;

  MeshConstPtr mesh_;
  std::vector<double> cumulative_area_; ///< cumulative_area_[t] = sum of areas [0, t]
  double total_area_ = 0.0;
  std::vector<std::uint32_t> guide_; ///< buildGuide's table, one more entry than slices
  double slices_per_m2_ = 0.0;       ///< the guide's slices per m^2 of area
  std::size_t n_points_ = 100000;
  std::uint64_t seed_ = 0;
  int threads_ = 1;
};

/// \brief The memory of drawing `points` samples of `point_bytes` each (sizeof the
/// point type) and voxelizing them, in bytes: the samples, the voxel filter's output
/// and its 16-byte index entry per point, n (2 point_bytes + 16). For the memory cap
/// (plantnbv/common/memory_cap.h), before sampling.
double sampledCloudMemoryBytes(double points, std::size_t point_bytes);

/// \brief The number of surface samples that gives ground truth at a voxel size: 8 per
/// resolution^2 of surface, so that every voxel the surface crosses receives points; at
/// least 10,000, at most 20 million. \pre resolution > 0.
std::size_t groundTruthSampleCount(double area_m2, double resolution);

} // namespace plantnbv
