#pragma once
/// \file occupancy_map.h
/// \brief OccupancyMap: the probabilistic occupancy map of the NBV loop, an
/// octomap::OcTree with the paper's parameters and a fast, exact frame insertion.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <plantnbv/common/pcl_fwd.h>
#include <plantnbv/octree/octree_conversion.h>
#include <plantnbv/octree/update_region.h>

namespace octomap {
class OcTree;
class OcTreeKey;
} // namespace octomap

namespace plantnbv {

namespace detail {
struct OccupancyMapScratch;
} // namespace detail

/// \brief What the map knows about a voxel.
enum class VoxelState : std::uint8_t {
  unknown,  ///< never observed (no node in the tree)
  free,     ///< occupancy probability <= the occupancy threshold
  occupied, ///< occupancy probability > the occupancy threshold (OctoMap's rule)
};

/// \brief Occupancy map of the NBV loop (paper sections 2.1 and 2.2, Stage I; Table 1):
/// an octomap::OcTree updated with the log-odds rule, one depth frame at a time.
///
/// `insert` gives exactly the map of OctoMap's own
/// `OcTree::insertPointCloud(cloud, origin, max_range_m)` (not discretized, lazy_eval
/// false): per frame the voxels a ray passes through (its end voxel excluded) form a set
/// of free voxels and the end voxels of points within range a set of occupied voxels; a
/// voxel in both is occupied only; every voxel of the two sets is updated once with the
/// hit or miss log-odds and clamped; the tree is pruned and its inner nodes hold the
/// maximum of their children. Node for node, the tree and its log-odds are identical to
/// OctoMap's (tested on random and camera-like frames; 0 voxels differ on the benchmark's
/// plant frames). It is faster (figures: docs/performance.md, "Occupancy map") because:
/// - the ray voxels come from a copy of OctoMap's traversal (Amanatides & Woo, the same
///   float / double operations, hence the same voxels), on several threads, into a
///   bitset of 64^3-voxel blocks instead of two hash sets; an organized cloud's rays in
///   tiles of its image, whose neighbouring rays cross the same voxels;
/// - the tree is updated in one walk in octree order, each node visited once per frame
///   instead of one descent per voxel, and an octree node whose voxels all get the same
///   update is updated as one node (where OctoMap creates its voxels, then prunes them);
///   the blocks' subtrees are updated on several threads.
///
/// Memory: besides the tree, 64 KiB per 64^3-voxel block that a frame's rays touch
/// (kept for the next frame), 32 bytes per point of the largest frame and 64 KiB per
/// thread.
///
/// Thread safety: const methods may run concurrently with each other; `insert`, `clear`
/// and the setters must not run concurrently with anything else on the same map. If
/// `insert` throws std::bad_alloc the map stays valid but may hold part of the frame.
class OccupancyMap {
public:
  using Ptr = std::shared_ptr<OccupancyMap>;            ///< shared map
  using ConstPtr = std::shared_ptr<const OccupancyMap>; ///< shared, read-only map

  /// \brief The map's parameters; defaults are the paper's (Table 1, data/paper.yaml).
  struct Config {
    /// Edge of a voxel in metres, in [kMinMapResolutionM, kMaxMapResolutionM] (0.1 mm
    /// to 10 m). Default 0.003.
    double resolution_m = 0.003;
    /// Occupancy probability of a hit, in (0.5, 1). Default 0.7.
    double prob_hit = 0.7;
    /// Occupancy probability of a miss, in (0, 0.5). Default 0.4.
    double prob_miss = 0.4;
    /// Lower clamping bound of a voxel's occupancy probability, in (0, 0.5). Default
    /// 0.12.
    double clamp_min = 0.12;
    /// Upper clamping bound of a voxel's occupancy probability, in (0.5, 1). Default
    /// 0.97.
    double clamp_max = 0.97;
    /// A voxel is occupied when its probability is > this, in (0, 1). Default 0.5.
    double occupancy_threshold = 0.5;
    /// Points farther than this from the sensor (metres, > 0) add free space up to this
    /// distance only and no occupied voxel (OctoMap's maxrange). At most 8192 voxels
    /// (this bounds the scratch memory of one insertion). Default 0.75.
    double max_range_m = 0.75;

    /// \brief Checks every field. \throws InvalidArgumentError naming the first bad
    /// field, its value and the expected range.
    void validate() const;
  };

  /// \brief Voxel counts at the finest resolution (a pruned node counts all its voxels).
  struct VoxelCounts {
    std::size_t occupied = 0; ///< voxels whose probability is above the threshold
    std::size_t free = 0;     ///< known voxels at or below the threshold
    /// \brief Voxels observed at least once: occupied + free.
    std::size_t known() const { return occupied + free; }
  };

  /// \brief What the last `insert` did and how long its steps took.
  struct InsertStats {
    std::size_t points = 0;       ///< points in the input cloud
    std::size_t non_finite = 0;   ///< points dropped because a coordinate is NaN / inf
    std::size_t beyond_range = 0; ///< finite points farther than max_range_m
    std::size_t outside_map = 0;  ///< finite points whose ray end is outside the octree
    std::size_t free_voxels = 0;  ///< distinct voxels updated as free
    std::size_t occupied_voxels = 0; ///< distinct voxels updated as occupied
    /// Tree updates made: a cube of voxels that all get the same update and that
    /// OctoMap's pruning would merge is updated as one node.
    std::size_t tree_updates = 0;
    /// With an update region: hits whose voxel lies outside it (the region did not hold
    /// every voxel that can become occupied; see setUpdateRegion).
    std::size_t hits_outside_region = 0;
    double rays_ms = 0.0;     ///< ray ends, keys and bounds (parallel)
    double traverse_ms = 0.0; ///< ray traversal into the bitset (parallel)
    double update_ms = 0.0;   ///< tree update, inner nodes and pruning (parallel)
    double total_ms = 0.0;    ///< the whole insert
  };

  /// \brief An empty map with the paper's parameters.
  OccupancyMap();
  /// \brief An empty map. \throws InvalidArgumentError if `config` is invalid.
  explicit OccupancyMap(const Config& config);
  ~OccupancyMap();
  OccupancyMap(const OccupancyMap&) = delete;
  OccupancyMap& operator=(const OccupancyMap&) = delete;

  /// \brief The parameters the map was made with.
  const Config& getConfig() const { return config_; }

  /// \brief Threads of `insert` (the ray traversal, and the tree update below the
  /// 64^3-voxel blocks); 0 (default) uses OpenMP's default (omp_get_max_threads(),
  /// OMP_NUM_THREADS). Frames of fewer than 4096 points per thread use fewer threads.
  /// The map does not depend on it.
  /// \throws InvalidArgumentError if `threads` < 0.
  void setNumberOfThreads(int threads);
  /// \brief The threads of insert; 0 = OpenMP's default.
  int getNumberOfThreads() const { return threads_; }

  /// \brief Integrates one frame. Each finite point within max_range_m of the sensor is
  /// a hit on its voxel and the voxels of the segment from the sensor to it are misses;
  /// a point beyond max_range_m gives misses on the segment towards it cut at
  /// max_range_m, and no hit.
  ///
  /// Exactly OctoMap's `insertPointCloud(cloud, origin, max_range_m)`: the segment's
  /// voxels are those of OctoMap's computeRayKeys (Amanatides & Woo), which include the
  /// sensor's voxel and exclude the end voxel; a voxel both hit and missed in a frame is
  /// hit only; each voxel is updated once per frame, whatever the number of its points.
  /// Points and the origin are used in single precision, as OctoMap does. Non-finite
  /// points are dropped (they never reach OctoMap); a point whose (cut) end lies outside
  /// the octree (+-32768 voxels around the world origin) adds nothing. A sensor reports
  /// a ray whose return lies beyond max_range_m (e.g. the background) as a point beyond
  /// max_range_m: `insert` then carves free space along it; a ray with no return at all
  /// is a NaN point and adds nothing.
  /// \param[in] points_W the frame's points in the world frame (organized or not).
  /// \param[in] sensor_origin_W the sensor's optical centre in the world frame.
  /// \throws InvalidArgumentError if the origin is not finite or outside the octree.
  void insert(const CloudXYZ& points_W, const Eigen::Vector3d& sensor_origin_W);
  /// \brief As above; the labels are ignored.
  void insert(const CloudXYZL& points_W, const Eigen::Vector3d& sensor_origin_W);

  /// \brief Statistics and step timings of the last `insert`.
  const InsertStats& getLastInsertStats() const { return last_stats_; }

  /// \brief Restricts the exactness of `insert` to `region` (null: the whole map, the
  /// default): every voxel of the region then gets exactly the updates of a full
  /// insertion, while rays jump over runs of bricks outside it, whose voxels may stay
  /// unknown or be updated less often than in the full map (each frame's rays first
  /// jump to where a RegionHorizon says they may enter the region). For a caller that
  /// reads only the region's voxels and the occupied ones: when every hit falls in the
  /// region (InsertStats::hits_outside_region stays 0), a voxel outside it is never
  /// occupied, as in the full map. Kept by `clear`.
  /// \throws InvalidArgumentError if the region's resolution is not the map's.
  void setUpdateRegion(std::shared_ptr<const UpdateRegion> region);
  /// \brief The update region (null: none).
  const std::shared_ptr<const UpdateRegion>& getUpdateRegion() const { return region_; }

  /// \brief Forgets everything (the configuration stays).
  void clear();

  /// \brief A counter that `insert` and `clear` increment (before they change the
  /// tree): caches built from the map (e.g. the planner's InformationGain) compare it to
  /// know whether they are stale. Starts at 0.
  std::uint64_t revision() const { return revision_; }

  /// \brief getChangedBricks() reports cubes of 2^kChangedBrickShift voxels a side.
  static constexpr int kChangedBrickShift = 3;
  /// \brief Where the last insert may have changed the map, for caches that would
  /// otherwise read the whole tree again (InformationGain's snapshot).
  /// \return true if the map's last change was an insert that took it from revision
  /// `since` to revision() (that is, revision() == since + 1): `bricks` then holds the
  /// cubes of 8^3 voxels (each as its voxel keys >> kChangedBrickShift, listed once) that
  /// contain every voxel the insert updated, and no voxel outside them changed. false,
  /// and `bricks` emptied, otherwise: after clear(), several changes, or an insert that
  /// threw.
  bool getChangedBricks(std::uint64_t since,
                        std::vector<std::array<int, 3>>& bricks) const;

  /// \brief The key of the voxel holding `point_W`. \return false if the point is not
  /// finite or lies outside the octree (key then unchanged).
  bool computeKey(const Eigen::Vector3d& point_W, octomap::OcTreeKey& key) const;

  /// \brief The voxel's state (one tree search, O(tree depth)).
  VoxelState state(const octomap::OcTreeKey& key) const;
  /// \brief The state of the voxel holding `point_W`; unknown outside the octree.
  VoxelState state(const Eigen::Vector3d& point_W) const;
  /// \brief The voxel's log-odds; 0 (probability 0.5, the prior) if unknown.
  float logOdds(const octomap::OcTreeKey& key) const;
  /// \brief The voxel's occupancy probability; 0.5 if unknown.
  double probability(const octomap::OcTreeKey& key) const;
  /// \brief The occupancy probability of the voxel holding `point_W`; 0.5 if unknown or
  /// outside the octree.
  double probability(const Eigen::Vector3d& point_W) const;
  /// \brief Whether the voxel has been observed.
  bool isKnown(const octomap::OcTreeKey& key) const;

  /// \brief The underlying octree (pruned, inner nodes up to date). Valid as long as the
  /// map lives; changed by `insert` and `clear`.
  const octomap::OcTree& getOcTree() const { return *tree_; }

  /// \brief Centres of the occupied voxels (plantnbv::occupiedVoxelCentres on the tree;
  /// its inner nodes hold their children's maximum, so free subtrees are not walked), on
  /// the map's threads (setNumberOfThreads) in place of options.threads.
  void getOccupiedVoxelCentres(CloudXYZ& cloud,
                               const OccupiedVoxelOptions& options = {}) const;

  /// \brief Voxel counts (walks all leaves, O(tree size)).
  VoxelCounts countVoxels() const;

  /// \brief A map read from an OctoMap file (readOcTree: .ot keeps every voxel's
  /// log-odds; .bt holds occupied / free only, at the clamping bounds, so a planner sees
  /// no uncertainty in it). The map takes `config` with the file's resolution; its inner
  /// nodes are recomputed (the maximum of their children) and it is pruned, as `insert`
  /// keeps them.
  /// \param[out] maximum_likelihood if not null, whether the file was a .bt.
  /// \throws IoError, FormatError as readOcTree; InvalidArgumentError if `config` with
  /// the file's resolution is invalid.
  static std::unique_ptr<OccupancyMap> read(const std::string& path, Config config,
                                            bool* maximum_likelihood = nullptr);

  /// \brief Writes the map as .bt (occupied / free only) or .ot (full log-odds), by
  /// extension, for octovis and OctoMap's tools (plantnbv::writeOcTree).
  /// \throws IoError, FormatError as writeOcTree.
  void write(const std::string& path) const;

private:
  friend class OccupancyMapSnapshot; // restores a tree into a new map

  template <typename PointT>
  void insertImpl(const pcl::PointCloud<PointT>& points_W,
                  const Eigen::Vector3d& sensor_origin_W);

  Config config_;
  int threads_ = 0;
  std::unique_ptr<octomap::OcTree> tree_;
  /// Per-frame buffers, kept between frames.
  std::unique_ptr<detail::OccupancyMapScratch> scratch_;
  InsertStats last_stats_;
  std::uint64_t revision_ = 0;
  /// The revision whose insert left its changed bricks in scratch_ (none: max).
  std::uint64_t changed_bricks_revision_ = ~std::uint64_t{0};
  std::shared_ptr<const UpdateRegion> region_;
};

} // namespace plantnbv
