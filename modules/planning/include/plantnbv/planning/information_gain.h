#pragma once
/// \file information_gain.h
/// \brief The expected information gain of candidate views on an occupancy map (the
/// paper's section 2.1-2.3, equations (1)-(3); docs/planning.md).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <plantnbv/common/box.h>
#include <plantnbv/common/pose.h>

namespace plantnbv {

class OccupancyMap;

/// \brief Shannon entropy (bits) of an occupancy probability (paper eq. (1)); 0 at p in
/// {0, 1}, 1 at 0.5. NaN for p outside [0, 1] or NaN.
double occupancyEntropy(double p);

/// \brief How candidate views are ray-traced (paper section 2.2, Stage III; Table 1).
struct GainConfig {
  /// Ray grid across the frustum: rays_x columns x rays_y rows, each in [1, 4096].
  /// Default 48 x 36, chosen by the study in docs/planning.md ("Ray count"): coarser
  /// grids miss small leaf-node boxes, finer ones cost time for little gain; 48 x 36
  /// keeps about 10 rays on a paper-sized leaf-node box 0.4 m away.
  int rays_x = 48;
  int rays_y = 36; ///< see rays_x
  /// Field of view (rad), each in (0, pi). Defaults: the L515's as the sensor models it
  /// (70 deg horizontally; 2 atan(0.75 tan(35 deg)) = 55.4 deg vertically, square
  /// pixels at 4:3).
  double horizontal_fov_rad = 70.0 * M_PI / 180.0;
  /// Vertical field of view (rad); see horizontal_fov_rad.
  double vertical_fov_rad = 2.0 * std::atan(0.75 * std::tan(35.0 * M_PI / 180.0));
  /// Length of every ray from the camera (metres, finite, > 0). Default 0.75, Table 1.
  double raycast_range_m = 0.75;
  /// Optional, beyond the paper: weight each voxel's entropy by the probability that
  /// it is visible, the product of (1 - p_occ) over the voxels before it on the ray (a
  /// voxel seen by several rays takes its largest visibility); rays then do not stop at
  /// occupied voxels but at the range. Default false (the paper's gain).
  bool visibility_weighted = false;
  /// Beyond the paper: count only voxels never observed (unknown, 1 bit each); an
  /// observed voxel adds nothing, however uncertain. The paper's gain counts
  /// every voxel's entropy, and with its sensor model a voxel seen free once keeps 0.97
  /// bits and a free voxel at the clamping bound 0.53 bits for ever, so it keeps
  /// rewarding views that look again at known free space (docs/planning.md, "What the
  /// gain counts"); with visibility_weighted, each unknown voxel counts its visibility.
  /// Default true, chosen by the main study (docs/planning.md); false is the paper's.
  bool unknown_only = true;
  /// Beyond the paper: a ray counts at most its first `unknown_depth` unknown voxels in
  /// the ROI (known ones still count); deeper ones are likely hidden behind the
  /// surface the ray would meet first. Without it, a ray that grazes a large unknown
  /// ROI counts hundreds of voxels, and the gain favours views along the ROI's long
  /// axis over views that would see new surface (docs/planning.md). With unknown_only
  /// a ray ends at its unknown_depth-th (nothing behind it can add to the gain), so
  /// ViewGain::voxels_seen leaves out the known voxels behind it. Default 3, chosen by
  /// the main study; 0 (the paper's): no limit.
  int unknown_depth = 3;

  /// \brief The paper's gain: every voxel's entropy, no depth limit (unknown_only false,
  /// unknown_depth 0), the rest as the defaults.
  static GainConfig paper();

  /// \brief Checks every field. \throws InvalidArgumentError naming the first bad field,
  /// its value and the expected range.
  void validate() const;
};

/// \brief What one candidate would see.
struct ViewGain {
  double gain = 0.0;            ///< G_v (bits), paper eq. (2)/(3)
  std::size_t voxels_seen = 0;  ///< |X_v| inside the ROI (all of X_v when no ROI)
  std::size_t unknown_seen = 0; ///< of those, unknown
  std::size_t rays_cast = 0;    ///< rays that could meet the ROI (others skipped)
};

/// \brief The expected information gain of candidate views on an OccupancyMap (paper
/// sections 2.2-2.3).
///
/// For a candidate v, rays_x * rays_y rays leave the camera through the centres of a
/// grid over its image plane (pinhole, the fields of view of GainConfig; body frame x
/// forward, y left, z up; optical frame z forward, x right, y down; ray (i, j) of column
/// i from the left and row j from the top is number j * rays_x + i), each up to
/// raycast_range_m. A ray's voxels are OctoMap's computeRayKeys(origin, end) (end voxel
/// excluded; origin and end in single precision as OctoMap has them) followed by the end
/// voxel; walked in order, each joins X_v (an unknown voxel of the ROI only among the
/// ray's first unknown_depth), and an occupied voxel (probability > the map's
/// threshold) stops the ray after it, as does, with unknown_only, its unknown_depth-th
/// unknown voxel of the ROI. Then
///   G_v = sum over distinct voxels x of X_v whose centre lies in the ROI of H(p(x)),
/// H = occupancyEntropy, p = the map's probability (unknown: 0.5, 1 bit). An empty ROI
/// counts every voxel (the paper's plain NBV). With visibility_weighted each term is
/// multiplied by the voxel's visibility (see GainConfig); with unknown_only H is 1 for an
/// unknown voxel and 0 for a known one.
///
/// The result equals referenceInformationGain() (the straightforward octree walk) to
/// floating-point rounding (the same voxels, summed in another order), but is computed
/// on a snapshot of the map: the map's voxels that can matter (inside the ROI, and the
/// occupied ones, which stop rays, elsewhere; every known voxel without ROI or with
/// visibility weighting) in 8^3-voxel bricks, with a table of the distinct log-odds
/// values. Rays whose segment misses the ROI's boxes (grown by one voxel) are skipped,
/// a ray stops once past its last box, and bricks that hold neither ROI nor occupied
/// voxels are jumped over exactly (ray_traversal::advanceWhileBelow); each candidate
/// dedupes its voxels in a per-thread bitset. docs/planning.md gives the details,
/// docs/performance.md ("Planning") the timings against the reference.
///
/// The snapshot is rebuilt by update(), and by compute() whenever the map's revision()
/// changed, the map or ROI was replaced, or visibility_weighted or unknown_only changed;
/// its cost is in getLastStats().update_ms. After a single insert into the same map,
/// with the same ROI boxes, only the bricks of 8^3 voxels that the insert changed are
/// read again (OccupancyMap::getChangedBricks), with the same gains as a snapshot built
/// anew.
///
/// Thread safety: compute() and update() must not run concurrently with anything else on
/// the same object; they read the map, which must not change meanwhile. Both run on
/// setNumberOfThreads() OpenMP threads. compute() runs in parallel over the candidates;
/// each candidate's gain is computed by one thread in a fixed order. The snapshot
/// (update(), or compute()'s rebuild) is built in parallel over disjoint subtrees of the
/// octree, each thread's part merged in the order of a one-thread walk, so the snapshot
/// is the same. Results never depend on the number of threads.
class InformationGain {
public:
  using Ptr = std::shared_ptr<InformationGain>; ///< shared gain computer

  /// \brief Timings and sizes of the last update() and compute().
  struct Stats {
    double update_ms = 0.0; ///< the last snapshot rebuild (update() or compute())
    bool rebuilt = false;   ///< whether the last compute() rebuilt the snapshot
    /// Whether the last rebuild read only the bricks that the map's last insert changed
    /// (OccupancyMap::getChangedBricks), not the whole map.
    bool incremental = false;
    double gain_ms = 0.0;           ///< last compute(), without the rebuild
    std::size_t candidates = 0;     ///< of the last compute()
    std::size_t rays_cast = 0;      ///< total over its candidates
    std::size_t bricks = 0;         ///< 8^3-voxel bricks stored in the snapshot
    std::size_t values = 0;         ///< distinct log-odds values in the snapshot
    std::size_t leaves = 0;         ///< octree leaves the last rebuild read
    std::uint64_t map_revision = 0; ///< the map's revision() the snapshot was built at
  };

  InformationGain();
  ~InformationGain();
  InformationGain(const InformationGain&) = delete;
  InformationGain& operator=(const InformationGain&) = delete;

  /// \throws InvalidArgumentError as GainConfig::validate().
  void setConfig(const GainConfig& config);
  /// \brief How candidates are ray-traced.
  const GainConfig& getConfig() const { return config_; }

  /// \brief The map to read (shared, not copied). \throws InvalidArgumentError if null.
  void setInputMap(std::shared_ptr<const OccupancyMap> map);
  /// \brief The map read, or null before setInputMap().
  const std::shared_ptr<const OccupancyMap>& getInputMap() const { return map_; }

  /// \brief Empty ROI = everything counts (the paper's plain NBV).
  /// \throws InvalidArgumentError for a box whose centre or size is not finite or whose
  /// size is negative.
  void setRoi(const Roi& roi);
  /// \brief The attention ROI (empty: everything counts).
  const Roi& getRoi() const { return roi_; }

  /// \brief OpenMP threads of compute() and of the snapshot's rebuild (update()); 0
  /// (default) = OpenMP's default. Results never depend on it. \throws
  /// InvalidArgumentError if `threads` < 0.
  void setNumberOfThreads(int threads);
  /// \brief The OpenMP threads of compute() and update(); 0 = OpenMP's default.
  int getNumberOfThreads() const { return threads_; }

  /// \brief Rebuilds the snapshot of the map now (after a single insert, only the bricks
  /// it changed: see above). Called by compute() when the map's revision() changed (so
  /// calling it is optional); call it to take the cost out of the next compute(). \throws
  /// InvalidArgumentError if no map is set.
  void update();

  /// \brief Gains of all candidates (parallel over candidates), in the order given.
  /// ROI boxes out of every candidate's reach (farther than raycast_range_m plus two
  /// voxels) add nothing to any gain and are left out of the snapshot (so a far box
  /// costs nothing); when no box is within reach every gain is 0, without a snapshot.
  /// \param[out] out resized to candidates.size().
  /// \throws InvalidArgumentError if no map is set.
  void compute(const std::vector<Viewpoint>& candidates, std::vector<ViewGain>& out);
  /// \brief The gain of one candidate. \throws InvalidArgumentError if no map is set.
  ViewGain compute(const Viewpoint& candidate);

  /// \brief Timings and sizes of the last update() and compute().
  const Stats& getLastStats() const { return stats_; }

  /// Internal state (the snapshot, per-thread buffers); defined in the sources.
  struct Impl;

private:
  /// Builds the snapshot unless it is up to date and holds exactly these ROI boxes.
  void ensureSnapshot(const std::vector<std::size_t>& boxes);
  /// The snapshot of the map with these boxes of the ROI (indices into roi_).
  void buildSnapshot(const std::vector<std::size_t>& boxes);

  GainConfig config_;
  std::shared_ptr<const OccupancyMap> map_;
  Roi roi_;
  int threads_ = 0;
  bool dirty_ = true;
  Stats stats_;
  std::unique_ptr<Impl> impl_;
};

/// \brief The straightforward reference on the octree (kept for tests and the
/// benchmark): per ray, OctoMap's computeRayKeys + the end key, a tree search per voxel,
/// stop at the first occupied voxel (it counts), a std::unordered_set of keys for X_v,
/// then the sum of entropies of the keys whose voxel centre lies in the ROI
/// (Roi::contains on the centre; empty ROI: all; with unknown_only, the count of the
/// unknown ones). With visibility_weighted: no stop, a map from key to its largest
/// visibility. Rays are those of InformationGain (same ends,
/// same order); rays_cast counts every ray inside the octree. Single-threaded. \throws
/// InvalidArgumentError as GainConfig::validate().
ViewGain referenceInformationGain(const OccupancyMap& map, const Roi& roi,
                                  const GainConfig& config, const Viewpoint& view);

} // namespace plantnbv
