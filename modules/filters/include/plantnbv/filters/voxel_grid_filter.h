#pragma once
/// \file voxel_grid_filter.h
/// \brief Down-sampling to one point per occupied voxel of a cubic grid.

#include <pcl/filters/filter.h>

namespace plantnbv {

/// \brief A voxel grid whose voxels are aligned with the world origin: voxel i along an
/// axis spans [i * leaf, (i + 1) * leaf), i = floor(p / leaf), the same lattice as
/// OctoMap's keys, so ground truth and a map's occupied voxels at the same resolution
/// fall on the same cells.
///
/// Output per occupied voxel: the centroid of its points (pcl::VoxelGrid's behaviour, the
/// default) or the voxel centre (`setOutputVoxelCentres(true)`, what an occupancy map
/// reports: (i + 0.5) * leaf, computed in double, stored as float).
///
/// Centroid mode runs pcl::VoxelGrid, which computes i = floor(p * (1 / leaf)) in float.
/// Where pcl::VoxelGrid would overflow its 32-bit voxel indices (small leaves over large
/// extents; it would warn and hand back the input unfiltered), this filter uses its own
/// 64-bit sorted grid instead, with the same voxels and centroids (summed in double).
/// Centre mode always uses our grid, which computes i exactly as OctoMap's coordToKey
/// does (floor(double(p) * (1.0 / leaf))): its voxels are OctoMap's keys bit for bit. A
/// point within float rounding of a voxel face may therefore fall in the neighbouring
/// voxel in centroid mode (pcl's float arithmetic) but not in centre mode.
///
/// Non-finite points are dropped; the output is unorganized (height 1) and dense.
/// setIndices() is honoured. Output order: voxels in increasing (z, y, x) index (x
/// fastest), the order of pcl::VoxelGrid. Labels (PointXYZL): the most frequent label of
/// the voxel's points, the smallest one on a tie, in every mode (pcl::VoxelGrid's
/// majority vote; labels are never averaged). Other fields (none for PointXYZ,
/// PointXYZL): pcl::VoxelGrid's in centroid mode, the voxel's first point's on our grid.
///
/// Compiled for pcl::PointXYZ and pcl::PointXYZL. Not thread-safe (one filter per
/// thread).
template <typename PointT>
class VoxelGridFilter : public pcl::Filter<PointT> {
  using PointCloud = typename pcl::Filter<PointT>::PointCloud;

public:
  using Ptr = std::shared_ptr<VoxelGridFilter<PointT>>;            ///< shared filter
  using ConstPtr = std::shared_ptr<const VoxelGridFilter<PointT>>; ///< shared, read-only

  VoxelGridFilter() { this->filter_name_ = "VoxelGridFilter"; }

  /// \param[in] leaf edge length of a voxel in metres (default 0.003);
  /// \throws InvalidArgumentError unless finite, > 0 and a finite, non-zero float.
  void setLeafSize(double leaf);
  /// \brief The voxel edge length in metres.
  double getLeafSize() const { return leaf_; }

  /// \param[in] centres true: one point at each occupied voxel's centre; false (default):
  /// the centroid of the voxel's points.
  void setOutputVoxelCentres(bool centres) { centres_ = centres; }
  /// \brief True if the output is voxel centres, false if centroids.
  bool getOutputVoxelCentres() const { return centres_; }

  /// \brief True if the last filter() call could not use pcl::VoxelGrid (its indices
  /// would have overflowed) and ran our 64-bit grid instead; false in centre mode.
  bool usedOverflowFallback() const { return used_fallback_; }

protected:
  /// \brief The filter itself, called by pcl::Filter::filter(output) (see the class
  /// description).
  void applyFilter(PointCloud& output) override;

private:
  /// Our sorted 64-bit grid, used for voxel centres and where pcl::VoxelGrid would
  /// overflow. \param[in] indices finite points of the input.
  void applyOwnGrid(const pcl::Indices& indices, PointCloud& output) const;

  double leaf_ = 0.003;
  bool centres_ = false;
  bool used_fallback_ = false;
};

} // namespace plantnbv
