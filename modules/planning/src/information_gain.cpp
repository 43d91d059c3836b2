// The fast information gain: a bricked snapshot of the map (gain_snapshot.h), OctoMap's
// exact ray traversal (plantnbv/octree/ray_traversal.h), rays culled and clipped to the
// ROI, and jumps over bricks that hold nothing that counts or stops a ray.
// Compiled with -ffp-contract=off (CMakeLists.txt): the traversal must round like
// OctoMap's.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <omp.h>
#include <sstream>
#include <unordered_set>
#include <vector>

#include <octomap/OcTree.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/stopwatch.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/octree/ray_traversal.h>
#include <plantnbv/planning/information_gain.h>

#include "gain_rays.h"
#include "gain_snapshot.h"

namespace plantnbv {

namespace rt = ray_traversal;
using namespace gain_detail;

// For the fast kernel's per-voxel and per-brick helpers: their state stays in registers.
#define PLANTNBV_ALWAYS_INLINE inline __attribute__((always_inline))

namespace {

/// setNumberOfThreads()'s value, 0 meaning OpenMP's default.
int threadsOrDefault(int threads)
{
  return threads > 0 ? threads : omp_get_max_threads();
}

/// One candidate's set of distinct voxels by key, in a box of bricks, with the largest
/// visibility per voxel when weighted. Reused: reset() clears only what was used. For
/// the general kernel (no ROI, or visibility weighting).
class VoxelSet {
public:
  void reset(const int b0[3], const int nb[3], bool weighted)
  {
    for (const std::uint32_t s : used_)
      table_[s] = 0;
    used_.clear();
    overflow_.clear();
    overflow_vis_.clear();
    weighted_ = weighted;
    std::size_t n = 1;
    for (int a = 0; a < 3; ++a) {
      b0_[a] = b0[a];
      nb_[a] = nb[a];
      n *= static_cast<std::size_t>(nb[a]);
    }
    if (table_.size() < n)
      table_.resize(n, 0); // the rest is already zero
  }

  /// Adds the voxel; true if it is new.
  bool insert(int kx, int ky, int kz)
  {
    std::uint64_t* w = words(kx, ky, kz);
    if (!w)
      return overflow_.insert(pack(kx, ky, kz)).second;
    const int local = brickLocal(kx, ky, kz);
    const std::uint64_t bit = std::uint64_t{1} << (local & 63);
    std::uint64_t& word = w[local >> 6];
    if (word & bit)
      return false;
    word |= bit;
    return true;
  }

  /// Adds the voxel with visibility `vis`, keeping the largest.
  void insertMax(int kx, int ky, int kz, double vis)
  {
    std::uint64_t* w = words(kx, ky, kz);
    if (!w) {
      const std::uint64_t key = pack(kx, ky, kz);
      if (overflow_.insert(key).second) {
        overflow_vis_.push_back({key, vis});
      } else {
        for (auto& kv : overflow_vis_)
          if (kv.first == key)
            kv.second = std::max(kv.second, vis);
      }
      return;
    }
    const std::size_t slot = static_cast<std::size_t>(w - bits_.data()) / 8;
    double& v =
        vis_[slot * kBrickVoxels + static_cast<std::size_t>(brickLocal(kx, ky, kz))];
    if (vis > v)
      v = vis; // starts at -1
  }

  /// Calls f(kx, ky, kz, vis) for every voxel in a fixed order (bricks in first-touch
  /// order, voxels by index); vis is 1 when not weighted.
  template <typename F>
  void forEach(F&& f) const
  {
    for (std::size_t slot = 0; slot < used_.size(); ++slot) {
      const std::size_t s = used_[slot];
      const std::size_t nx = static_cast<std::size_t>(nb_[0]),
                        ny = static_cast<std::size_t>(nb_[1]);
      const int base[3] = {(static_cast<int>(s % nx) + b0_[0]) << kBrickShift,
                           (static_cast<int>((s / nx) % ny) + b0_[1]) << kBrickShift,
                           (static_cast<int>(s / (nx * ny)) + b0_[2]) << kBrickShift};
      for (int local = 0; local < kBrickVoxels; ++local) {
        double vis = 1.0;
        if (weighted_) {
          vis = vis_[slot * kBrickVoxels + static_cast<std::size_t>(local)];
          if (vis < 0.0)
            continue;
        } else if (!((bits_[slot * 8 + static_cast<std::size_t>(local >> 6)] >>
                      (local & 63)) &
                     1u)) {
          continue;
        }
        f(base[0] + (local & kBrickMask), base[1] + ((local >> kBrickShift) & kBrickMask),
          base[2] + (local >> (2 * kBrickShift)), vis);
      }
    }
    // Voxels outside the box (never expected: it holds every voxel that counts).
    std::vector<std::pair<std::uint64_t, double>> rest = overflow_vis_;
    if (!weighted_)
      for (const std::uint64_t key : overflow_)
        rest.push_back({key, 1.0});
    std::sort(rest.begin(), rest.end());
    for (const auto& kv : rest)
      f(static_cast<int>(kv.first >> 32), static_cast<int>((kv.first >> 16) & 0xffffu),
        static_cast<int>(kv.first & 0xffffu), kv.second);
  }

private:
  static std::uint64_t pack(int kx, int ky, int kz)
  {
    return (static_cast<std::uint64_t>(kx) << 32) |
           (static_cast<std::uint64_t>(ky) << 16) | static_cast<std::uint64_t>(kz);
  }

  /// The bit words of the voxel's brick (made on first use); null outside the box.
  std::uint64_t* words(int kx, int ky, int kz)
  {
    const unsigned rx = static_cast<unsigned>((kx >> kBrickShift) - b0_[0]);
    const unsigned ry = static_cast<unsigned>((ky >> kBrickShift) - b0_[1]);
    const unsigned rz = static_cast<unsigned>((kz >> kBrickShift) - b0_[2]);
    if (rx >= static_cast<unsigned>(nb_[0]) || ry >= static_cast<unsigned>(nb_[1]) ||
        rz >= static_cast<unsigned>(nb_[2]))
      return nullptr;
    const std::size_t s =
        (static_cast<std::size_t>(rz) * static_cast<std::size_t>(nb_[1]) + ry) *
            static_cast<std::size_t>(nb_[0]) +
        rx;
    std::uint32_t e = table_[s];
    if (!e) {
      const std::size_t slot = used_.size();
      used_.push_back(static_cast<std::uint32_t>(s));
      e = static_cast<std::uint32_t>(slot + 1);
      table_[s] = e;
      if (bits_.size() < (slot + 1) * 8)
        bits_.resize((slot + 1) * 8);
      std::fill(bits_.begin() + static_cast<std::ptrdiff_t>(slot * 8),
                bits_.begin() + static_cast<std::ptrdiff_t>(slot * 8 + 8), 0);
      if (weighted_) {
        if (vis_.size() < (slot + 1) * kBrickVoxels)
          vis_.resize((slot + 1) * kBrickVoxels);
        std::fill(vis_.begin() + static_cast<std::ptrdiff_t>(slot * kBrickVoxels),
                  vis_.begin() + static_cast<std::ptrdiff_t>((slot + 1) * kBrickVoxels),
                  -1.0);
      }
    }
    return &bits_[(e - 1) * std::size_t{8}];
  }

  int b0_[3] = {0, 0, 0};
  int nb_[3] = {0, 0, 0};
  bool weighted_ = false;
  std::vector<std::uint32_t> table_; ///< 0, or 1 + slot
  std::vector<std::uint32_t> used_;  ///< table index per slot
  std::vector<std::uint64_t> bits_;  ///< 8 words per slot
  std::vector<double> vis_;          ///< 512 per slot (weighted)
  std::unordered_set<std::uint64_t> overflow_;
  std::vector<std::pair<std::uint64_t, double>> overflow_vis_;
};

/// One candidate's distinct ROI voxels: a bit per voxel of the ROI's bricks, cleared
/// brick by brick when first touched (a stamp per brick).
class RoiSeen {
public:
  void reset(const KeyBox& roi)
  {
    std::size_t n = 1;
    bool same = true;
    for (int a = 0; a < 3; ++a) {
      const int b0 = roi.lo[a] >> kBrickShift, nb = (roi.hi[a] >> kBrickShift) - b0 + 1;
      same = same && b0 == b0_[a] && nb == nb_[a];
      b0_[a] = b0;
      nb_[a] = nb;
      n *= static_cast<std::size_t>(nb);
    }
    if (!same || stamps_.size() != n || current_ == ~std::uint32_t{0}) {
      stamps_.assign(n, 0);
      bits_.resize(n * 8);
      current_ = 0;
    }
    ++current_;
  }
  /// The 8 bit words of the brick at brick coordinates b; null outside the ROI's bricks.
  /// Inlined: called at every brick a ray enters.
  PLANTNBV_ALWAYS_INLINE std::uint64_t* brick(int bx, int by, int bz)
  {
    const unsigned rx = static_cast<unsigned>(bx - b0_[0]);
    const unsigned ry = static_cast<unsigned>(by - b0_[1]);
    const unsigned rz = static_cast<unsigned>(bz - b0_[2]);
    if (rx >= static_cast<unsigned>(nb_[0]) || ry >= static_cast<unsigned>(nb_[1]) ||
        rz >= static_cast<unsigned>(nb_[2]))
      return nullptr;
    const std::size_t i =
        (static_cast<std::size_t>(rz) * static_cast<std::size_t>(nb_[1]) + ry) *
            static_cast<std::size_t>(nb_[0]) +
        rx;
    std::uint64_t* w = &bits_[i * 8];
    if (stamps_[i] != current_) {
      stamps_[i] = current_;
      std::fill(w, w + 8, 0);
    }
    return w;
  }

private:
  int b0_[3] = {0, 0, 0};
  int nb_[3] = {0, 0, 0};
  std::vector<std::uint32_t> stamps_;
  std::vector<std::uint64_t> bits_;
  std::uint32_t current_ = 0;
};

/// One thread's buffers.
struct ThreadScratch {
  VoxelSet voxels;
  RoiSeen seen;
  std::vector<std::uint32_t> counts; ///< per value
  std::vector<std::uint8_t> ray_marks;
};

/// A segment o + s d, s in [0, 1] (from the float origin and end), for clipping.
struct Segment {
  double o[3];
  double d[3];
  double inv[3]; ///< 1 / d (unused where d is 0)

  Segment(const float origin[3], const float end[3])
  {
    for (int a = 0; a < 3; ++a) {
      o[a] = origin[a];
      d[a] = static_cast<double>(end[a]) - o[a];
      inv[a] = d[a] != 0.0 ? 1.0 / d[a] : 0.0;
    }
  }
  double length() const { return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]); }
  /// The interval [s0, s1] of s inside the box; false if empty.
  bool clip(const ClipBox& box, double& s0, double& s1) const
  {
    s0 = 0.0;
    s1 = 1.0;
    for (int a = 0; a < 3; ++a) {
      if (d[a] == 0.0) {
        if (o[a] < box.lo[a] || o[a] > box.hi[a])
          return false;
        continue;
      }
      double t0 = (box.lo[a] - o[a]) * inv[a], t1 = (box.hi[a] - o[a]) * inv[a];
      if (t0 > t1)
        std::swap(t0, t1);
      s0 = std::max(s0, t0);
      s1 = std::min(s1, t1);
    }
    return s0 <= s1;
  }
};

/// Marks the rays whose image-plane cell may see a (grown) ROI box: its corners'
/// projection, one cell of margin; all rays of a box with a corner behind the camera.
void markRays(const Snapshot& snap, const GainConfig& config, const ImagePlane& plane,
              const Viewpoint& view, const Eigen::Matrix3d& R,
              std::vector<std::uint8_t>& marks)
{
  const int n_rays = config.rays_x * config.rays_y;
  marks.assign(static_cast<std::size_t>(n_rays), snap.roi_mode ? 0 : 1);
  if (!snap.roi_mode)
    return;
  const Eigen::Matrix3d Rt = R.transpose();
  for (const ClipBox& box : snap.clip_boxes) {
    const Eigen::Vector3d lo(box.lo[0], box.lo[1], box.lo[2]);
    const Eigen::Vector3d hi(box.hi[0], box.hi[1], box.hi[2]);
    double x_min = std::numeric_limits<double>::infinity(), x_max = -x_min;
    double y_min = x_min, y_max = -x_min;
    bool behind = false;
    for (int c = 0; c < 8 && !behind; ++c) {
      const Eigen::Vector3d corner((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(),
                                   (c & 4) ? hi.z() : lo.z());
      const Eigen::Vector3d v = Rt * (corner - view.position); // body frame
      if (!(v.x() > 1e-6)) {
        behind = true;
        break;
      }
      const double x_o = -v.y() / v.x(), y_o = -v.z() / v.x(); // optical image plane
      x_min = std::min(x_min, x_o);
      x_max = std::max(x_max, x_o);
      y_min = std::min(y_min, y_o);
      y_max = std::max(y_max, y_o);
    }
    int i0 = 0, i1 = config.rays_x - 1, j0 = 0, j1 = config.rays_y - 1;
    if (!behind) {
      // The column of image-plane x is ((x / tan_h + 1) rays_x - 1) / 2.
      auto cell = [](double v, double tan_half, int n) {
        return ((v / tan_half + 1.0) * n - 1.0) * 0.5;
      };
      const double ci0 = cell(x_min, plane.tan_half_h, config.rays_x);
      const double ci1 = cell(x_max, plane.tan_half_h, config.rays_x);
      const double cj0 = cell(y_min, plane.tan_half_v, config.rays_y);
      const double cj1 = cell(y_max, plane.tan_half_v, config.rays_y);
      if (ci1 < -1.0 || ci0 > config.rays_x || cj1 < -1.0 || cj0 > config.rays_y)
        continue; // out of view
      i0 = std::max(i0, static_cast<int>(std::floor(ci0)) - 1);
      i1 = std::min(i1, static_cast<int>(std::ceil(ci1)) + 1);
      j0 = std::max(j0, static_cast<int>(std::floor(cj0)) - 1);
      j1 = std::min(j1, static_cast<int>(std::ceil(cj1)) + 1);
    }
    for (int j = j0; j <= j1; ++j)
      std::fill(marks.begin() + j * config.rays_x + i0,
                marks.begin() + j * config.rays_x + i1 + 1, 1);
  }
}

/// Where the segment leaves the last grown ROI box (metres from the origin along it):
/// < 0 if it misses them all, +inf if it ends inside one (nothing is clipped then).
/// The boxes are grown by a voxel, so a voxel whose centre lies in the ROI is entered
/// and left by the ray well inside them: rounding cannot matter.
double clipDistance(const Snapshot& snap, const Segment& seg)
{
  double s_last = -1.0;
  for (const ClipBox& box : snap.clip_boxes) {
    double s0, s1;
    if (seg.clip(box, s0, s1))
      s_last = std::max(s_last, s1);
  }
  if (s_last < 0.0)
    return -1.0;
  if (s_last >= 1.0)
    return std::numeric_limits<double>::infinity();
  return s_last * seg.length();
}

/// The unknown ROI voxels one ray may count (GainConfig::unknown_depth; 0: all).
int unknownDepth(const GainConfig& config)
{
  return config.unknown_depth > 0 ? config.unknown_depth
                                  : std::numeric_limits<int>::max();
}

/// Whether a ray ends at the last unknown ROI voxel it may count: with unknown_only
/// nothing behind it adds to the gain (known voxels are worth 0 bits).
bool raysEndAtUnknownDepth(const GainConfig& config)
{
  return config.unknown_only && config.unknown_depth > 0;
}

// --- the general kernel (no ROI, or visibility weighting) ------------------------------

/// Walks one ray's voxels with the shared traversal: looks each up in the snapshot,
/// dedupes those that count, stops at an occupied voxel (unweighted) and past the ROI.
template <typename CodeT, bool kWeighted>
struct RayWalker {
  const Bricks<CodeT>& bricks;
  const Value* values;
  VoxelSet& set;
  std::uint32_t* counts;
  int unknown_left;   ///< unknown ROI voxels the ray may still count
  bool ends_at_depth; ///< the ray ends when unknown_left reaches 0
  double t_stop = std::numeric_limits<double>::infinity();
  double vis = 1.0;
  bool stopped = false; ///< at an occupied voxel (unweighted) or its last unknown one
  bool clipped = false; ///< past the ROI

  bool begin(int kx, int ky, int kz, const int* /*step*/) { return visit(kx, ky, kz); }

  bool next(int /*axis*/, int kx, int ky, int kz, double t_entry)
  {
    if (t_entry > t_stop) {
      clipped = true;
      return false;
    }
    return visit(kx, ky, kz);
  }

  bool visit(int kx, int ky, int kz)
  {
    const unsigned c = bricks.code(kx, ky, kz);
    const bool unknown_in_roi = (c & kInRoi) && c >> kValueShift == 0;
    const bool counts_here = (c & kInRoi) && (!unknown_in_roi || unknown_left-- > 0);
    if constexpr (kWeighted) {
      if (counts_here)
        set.insertMax(kx, ky, kz, vis);
      vis *= values[c >> kValueShift].free_prob;
    } else {
      if (counts_here && set.insert(kx, ky, kz))
        ++counts[c >> kValueShift];
      if (c & kOccupied) {
        stopped = true;
        return false;
      }
    }
    if (ends_at_depth && unknown_in_roi && unknown_left == 0) {
      stopped = true;
      return false;
    }
    return true;
  }
};

template <typename CodeT, bool kWeighted>
ViewGain computeGeneral(const Snapshot& snap, const Bricks<CodeT>& bricks,
                        const GainConfig& config, const ImagePlane& plane,
                        const std::vector<Eigen::Vector3d>& dirs, ThreadScratch& scratch,
                        const Viewpoint& view)
{
  ViewGain result;
  float origin[3];
  rayOrigin(view, origin);
  int key_origin[3];
  if (!snap.lattice.coordToKey(origin, key_origin))
    return result; // outside the octree: no ray
  const Eigen::Matrix3d R = view.orientation.toRotationMatrix();
  markRays(snap, config, plane, view, R, scratch.ray_marks);

  // The voxels that count lie in the ROI's keys, or without ROI within the range.
  int b0[3], nb[3];
  if (snap.roi_mode) {
    if (snap.roi_bbox.empty())
      return result; // no voxel centre inside the ROI
    for (int a = 0; a < 3; ++a) {
      b0[a] = snap.roi_bbox.lo[a] >> kBrickShift;
      nb[a] = (snap.roi_bbox.hi[a] >> kBrickShift) - b0[a] + 1;
    }
  } else {
    const int reach = static_cast<int>(std::ceil(config.raycast_range_m *
                                                 snap.lattice.resolutionFactor())) +
                      2;
    for (int a = 0; a < 3; ++a) {
      const int lo = std::max(key_origin[a] - reach, 0);
      const int hi = std::min(key_origin[a] + reach, kKeyLimit - 1);
      b0[a] = lo >> kBrickShift;
      nb[a] = (hi >> kBrickShift) - b0[a] + 1;
    }
  }
  scratch.voxels.reset(b0, nb, kWeighted);
  scratch.counts.assign(snap.values.size(), 0);

  const int n_rays = config.rays_x * config.rays_y;
  for (int r = 0; r < n_rays; ++r) {
    if (!scratch.ray_marks[static_cast<std::size_t>(r)])
      continue;
    float end[3];
    rayEnd(R, view.position, dirs[static_cast<std::size_t>(r)], config.raycast_range_m,
           end);
    int key_end[3];
    if (!snap.lattice.coordToKey(end, key_end))
      continue;
    RayWalker<CodeT, kWeighted> walker{bricks,
                                       snap.values.data(),
                                       scratch.voxels,
                                       scratch.counts.data(),
                                       unknownDepth(config),
                                       raysEndAtUnknownDepth(config)};
    if (snap.roi_mode) {
      walker.t_stop = clipDistance(snap, Segment(origin, end));
      if (walker.t_stop < 0.0)
        continue; // misses the ROI
    }
    ++result.rays_cast;
    rt::traverseRay(origin, end, key_origin, key_end, snap.lattice, walker);
    if (!walker.stopped && !walker.clipped)
      walker.visit(key_end[0], key_end[1], key_end[2]);
  }

  if constexpr (kWeighted) {
    scratch.voxels.forEach([&](int kx, int ky, int kz, double vis) {
      const unsigned value = bricks.code(kx, ky, kz) >> kValueShift;
      ++result.voxels_seen;
      if (value == 0)
        ++result.unknown_seen;
      result.gain += vis * snap.values[value].entropy;
    });
  } else {
    for (const std::uint32_t v : snap.value_order) {
      result.voxels_seen += scratch.counts[v];
      result.gain += static_cast<double>(scratch.counts[v]) * snap.values[v].entropy;
    }
    result.unknown_seen = scratch.counts[0];
  }
  return result;
}

// --- the fast kernel (ROI, unweighted) -------------------------------------------------

/// Whether the brick at brick coordinates b holds something that counts or stops rays.
template <typename CodeT>
bool brickMatters(const Bricks<CodeT>& bricks, const int b[3])
{
  const unsigned rx = static_cast<unsigned>(b[0] - bricks.b0[0]);
  const unsigned ry = static_cast<unsigned>(b[1] - bricks.b0[1]);
  const unsigned rz = static_cast<unsigned>(b[2] - bricks.b0[2]);
  if (rx >= static_cast<unsigned>(bricks.nb[0]) ||
      ry >= static_cast<unsigned>(bricks.nb[1]) ||
      rz >= static_cast<unsigned>(bricks.nb[2]))
    return false; // outside: unknown, not in the ROI
  const std::uint32_t e = bricks.table[bricks.slot(
      static_cast<int>(rx), static_cast<int>(ry), static_cast<int>(rz))];
  return !(e & kUniform) || (bricks.brick(e)[0] & (kInRoi | kOccupied));
}

/// The brick under the walk: its codes, whether it matters, and its ROI bits.
template <typename CodeT>
struct Cursor {
  const CodeT* voxels;
  bool empty;          ///< nothing in the brick counts or stops a ray
  std::uint64_t* seen; ///< null outside the ROI's bricks (no voxel there counts)
};

template <typename CodeT>
PLANTNBV_ALWAYS_INLINE void loadBrick(const Bricks<CodeT>& bricks, RoiSeen& seen, int kx,
                                      int ky, int kz, Cursor<CodeT>& c)
{
  std::size_t slot;
  if (bricks.slotOf(kx, ky, kz, slot)) {
    const std::uint32_t e = bricks.table[slot];
    c.voxels = bricks.brick(e);
    c.empty = (e & kUniform) && !(c.voxels[0] & (kInRoi | kOccupied));
  } else {
    c.voxels = bricks.brick(bricks.outside_brick);
    c.empty = !(bricks.outside & (kInRoi | kOccupied));
  }
  c.seen = seen.brick(kx >> kBrickShift, ky >> kBrickShift, kz >> kBrickShift);
}

/// Visits a voxel of the cursor's brick: counts it if it is in the ROI and new (an
/// unknown one only while the ray's `unknown_left` lasts); false if the ray ends after
/// it: an occupied voxel, or with `ends_at_depth` the last unknown one it may count.
/// `kDepthLimited`: GainConfig::unknown_depth > 0 (else `unknown_left` is not read; one
/// value less for the walk to keep in registers).
template <typename CodeT, bool kDepthLimited>
PLANTNBV_ALWAYS_INLINE bool visitVoxel(const Cursor<CodeT>& c, std::uint32_t* counts,
                                       int& unknown_left, bool ends_at_depth, int kx,
                                       int ky, int kz)
{
  const int local = brickLocal(kx, ky, kz);
  const unsigned code = c.voxels[local];
  if (code & kInRoi) {
    const bool unknown = code >> kValueShift == 0;
    if (kDepthLimited && unknown) {
      if (unknown_left == 0)
        return true; // deeper than GainConfig::unknown_depth on this ray
      --unknown_left;
    }
    std::uint64_t& word = c.seen[local >> 6];
    const std::uint64_t bit = std::uint64_t{1} << (local & 63);
    if (!(word & bit)) {
      word |= bit;
      ++counts[code >> kValueShift];
    }
    if (kDepthLimited && unknown && ends_at_depth && unknown_left == 0)
      return false;
  }
  return !(code & kOccupied);
}

/// One ray's constants for jumps over bricks where nothing matters.
struct JumpRay {
  rt::MarchRay march;
  int end[3];         ///< key_end
  double length;      ///< OctoMap's float length
  double stop_checks; ///< rt::stopChecksFrom: no stop rule holds before it
  double t_last;      ///< past this nothing counts
};

/// In a brick where nothing matters (nothing in the ROI, nothing occupied): finds where
/// the next brick that matters begins (rt::nextBrickEntry) and takes at once every
/// traversal step that enters a voxel before it (rt::advanceBelow). The jump stops
/// `margin` short of that brick (far more than the rounding of these distances, ~1e-13
/// m) and two voxels short of the segment's end (rt::stopChecksFrom), so no jumped step
/// is the end voxel or trips OctoMap's length rule.
/// \return 1: nothing on the rest of the ray counts (stop it); 0: continue from t, k.
template <typename CodeT>
int jumpEmpty(const Bricks<CodeT>& bricks, const JumpRay& ray,
              const VoxelLattice& lattice, double margin, double t_entry, double t[3],
              int k[3])
{
  int b[3] = {k[0] >> kBrickShift, k[1] >> kBrickShift, k[2] >> kBrickShift};
  const double limit = std::min(ray.t_last, ray.length) + margin;
  const double t_next = rt::nextBrickEntry(ray.march, lattice, kBrickShift, b, limit,
                                           [&bricks](int bx, int by, int bz) {
                                             const int brick[3] = {bx, by, bz};
                                             return brickMatters(bricks, brick);
                                           });
  double target;
  if (t_next < std::numeric_limits<double>::infinity()) {
    target = t_next - margin;
  } else if (ray.t_last < ray.length) {
    return 1; // past the ROI (or the snapshot) before anything matters
  } else {
    // The segment ends where nothing matters, and so does its end voxel unless
    // rounding put that next door.
    if (!(bricks.code(ray.end[0], ray.end[1], ray.end[2]) & (kInRoi | kOccupied)))
      return 1;
    target = ray.length;
  }
  target = std::min(target, ray.stop_checks);
  if (target > t_entry)
    rt::advanceBelow(ray.march, target, t, k);
  return 0;
}

template <typename CodeT, bool kDepthLimited>
ViewGain computeFast(const Snapshot& snap, const Bricks<CodeT>& bricks,
                     const GainConfig& config, const ImagePlane& plane,
                     const std::vector<Eigen::Vector3d>& dirs, ThreadScratch& scratch,
                     const Viewpoint& view)
{
  ViewGain result;
  if (snap.roi_bbox.empty())
    return result; // no voxel centre inside the ROI
  float origin[3];
  rayOrigin(view, origin);
  int key_origin[3];
  if (!snap.lattice.coordToKey(origin, key_origin))
    return result; // outside the octree: no ray
  const Eigen::Matrix3d R = view.orientation.toRotationMatrix();
  markRays(snap, config, plane, view, R, scratch.ray_marks);
  RoiSeen& seen = scratch.seen;
  seen.reset(snap.roi_bbox);
  scratch.counts.assign(snap.values.size(), 0);
  std::uint32_t* const counts = scratch.counts.data();
  const double res = snap.lattice.resolution();
  // Jumps stop this far (metres) short of the next brick that matters.
  const double margin = rt::kJumpMarginVoxels * res;
  const bool ends_at_depth = raysEndAtUnknownDepth(config);
  // The table's bricks in metres.
  Eigen::Vector3d table_lo, table_hi;
  for (int a = 0; a < 3; ++a) {
    table_lo[a] = snap.lattice.keyToLowerFace(bricks.b0[a] << kBrickShift);
    table_hi[a] =
        snap.lattice.keyToLowerFace((bricks.b0[a] + bricks.nb[a]) << kBrickShift);
  }
  const ClipBox table_box = {{table_lo[0], table_lo[1], table_lo[2]},
                             {table_hi[0], table_hi[1], table_hi[2]}};

  const int n_rays = config.rays_x * config.rays_y;
  for (int r = 0; r < n_rays; ++r) {
    if (!scratch.ray_marks[static_cast<std::size_t>(r)])
      continue;
    float end[3];
    rayEnd(R, view.position, dirs[static_cast<std::size_t>(r)], config.raycast_range_m,
           end);
    int key_end[3];
    if (!snap.lattice.coordToKey(end, key_end))
      continue;
    const Segment seg(origin, end);
    const double t_stop = clipDistance(snap, seg);
    if (t_stop < 0.0)
      continue; // misses the ROI
    ++result.rays_cast;
    int unknown_left = unknownDepth(config);

    rt::RaySetup s;
    if (!rt::setupRay(origin, end, key_origin, key_end, snap.lattice, s)) {
      Cursor<CodeT> cursor;
      loadBrick(bricks, seen, key_end[0], key_end[1], key_end[2], cursor); // one voxel
      visitVoxel<CodeT, kDepthLimited>(cursor, counts, unknown_left, ends_at_depth,
                                       key_end[0], key_end[1], key_end[2]);
      continue;
    }
    double tx = s.t_max[0], ty = s.t_max[1], tz = s.t_max[2];
    const double dx = s.t_delta[0], dy = s.t_delta[1], dz = s.t_delta[2];
    const int sx = s.step[0], sy = s.step[1], sz = s.step[2];
    const int ex = key_end[0], ey = key_end[1], ez = key_end[2];
    const double length = s.length;
    int kx = key_origin[0], ky = key_origin[1], kz = key_origin[2];

    // Outside the snapshot's table nothing counts or stops a ray: start the walk where
    // the segment enters it, stop it where it leaves.
    double t_last = t_stop;
    double t_first = 0.0;
    {
      double s0, s1;
      if (!seg.clip(table_box, s0, s1))
        continue;
      const double len = seg.length();
      if (s1 < 1.0)
        t_last = std::min(t_last, s1 * len + margin);
      t_first = s0 * len - margin;
      if (t_first > t_last)
        continue;
    }
    JumpRay jr;
    jr.march = rt::marchRay(origin, s);
    for (int a = 0; a < 3; ++a)
      jr.end[a] = key_end[a];
    jr.length = length;
    jr.t_last = t_last;
    // Neither OctoMap's stop rules nor t_last can end the walk before checks_from.
    const double stop_checks = rt::stopChecksFrom(s, snap.lattice);
    const double checks_from = std::min(stop_checks, t_last);
    jr.stop_checks = stop_checks;
    Cursor<CodeT> cursor;
    const double target = std::min(t_first, stop_checks);
    if (target > 0.0) {
      // Every step that enters a voxel before `target` at once; none of them reaches
      // the end voxel (two voxels short).
      double t[3] = {tx, ty, tz};
      int k[3] = {kx, ky, kz};
      rt::advanceBelow(jr.march, target, t, k);
      tx = t[0], ty = t[1], tz = t[2];
      kx = k[0], ky = k[1], kz = k[2];
      loadBrick(bricks, seen, kx, ky, kz, cursor); // its voxel lies outside the table
    } else {
      loadBrick(bricks, seen, kx, ky, kz, cursor);
      if (!visitVoxel<CodeT, kDepthLimited>(cursor, counts, unknown_left, ends_at_depth,
                                            kx, ky, kz))
        continue; // the ray ends at the camera's voxel
    }
    bool reached_end = false;
    for (;;) {
      // OctoMap's step (ray_traversal.h); a step into a new brick along its axis.
      double t_entry;
      const int axis =
          rt::ddaStep(tx, ty, tz, dx, dy, dz, sx, sy, sz, kx, ky, kz, t_entry);
      // A step into a new brick changes the key's bits above the brick's (keys are
      // >= 0): no per-axis constant to keep in a register.
      const bool new_brick = axis == 0   ? (kx ^ (kx - sx)) > kBrickMask
                             : axis == 1 ? (ky ^ (ky - sy)) > kBrickMask
                                         : (kz ^ (kz - sz)) > kBrickMask;
      if (t_entry >= checks_from) { // no stop before (one test a step instead of five)
        if (kx == ex && ky == ey && kz == ez) {
          reached_end = true;
          break;
        }
        if (std::min(std::min(tx, ty), tz) > length) {
          reached_end = true; // OctoMap's stop for rays that miss the end voxel
          break;
        }
        if (t_entry > t_last)
          break; // past the ROI or the table: nothing more counts
      }
      if (new_brick) {
        loadBrick(bricks, seen, kx, ky, kz, cursor);
        if (cursor.empty) {
          double t[3] = {tx, ty, tz};
          int k[3] = {kx, ky, kz};
          if (jumpEmpty(bricks, jr, snap.lattice, margin, t_entry, t, k))
            break;
          tx = t[0];
          ty = t[1];
          tz = t[2];
          if (k[0] != kx || k[1] != ky || k[2] != kz) {
            kx = k[0];
            ky = k[1];
            kz = k[2];
            loadBrick(bricks, seen, kx, ky, kz, cursor); // where nothing matters
          }
          continue;
        }
      }
      if (!cursor.empty && !visitVoxel<CodeT, kDepthLimited>(cursor, counts, unknown_left,
                                                             ends_at_depth, kx, ky, kz))
        break; // occupied, or the last unknown voxel the ray may count
    }
    if (reached_end) {
      loadBrick(bricks, seen, ex, ey, ez, cursor);
      visitVoxel<CodeT, kDepthLimited>(cursor, counts, unknown_left, ends_at_depth, ex,
                                       ey, ez);
    }
  }

  for (const std::uint32_t v : snap.value_order) {
    result.voxels_seen += counts[v];
    result.gain += static_cast<double>(counts[v]) * snap.values[v].entropy;
  }
  result.unknown_seen = counts[0];
  return result;
}

/// The boxes of the ROI that a ray of some candidate may meet: both kernels count only
/// rays whose segment (raycast_range_m long, origin and end in single precision) meets a
/// box grown by one voxel; a second voxel covers the rounding. The others add nothing to
/// any gain; left out of the snapshot, they cannot stretch its table from the map to a
/// far box.
std::vector<std::size_t> boxesWithinReach(const Roi& roi,
                                          const std::vector<Viewpoint>& candidates,
                                          double range_m, double resolution_m)
{
  const double reach_m = range_m + 2.0 * resolution_m;
  std::vector<std::size_t> reachable;
  for (std::size_t i = 0; i < roi.boxes().size(); ++i) {
    const Eigen::Vector3d lo = roi.boxes()[i].min(), hi = roi.boxes()[i].max();
    for (const Viewpoint& v : candidates) {
      const Eigen::Vector3d outside =
          (lo - v.position).cwiseMax(v.position - hi).cwiseMax(Eigen::Vector3d::Zero());
      if (!(outside.norm() > reach_m)) {
        reachable.push_back(i);
        break;
      }
    }
  }
  return reachable;
}

template <typename CodeT>
ViewGain computeWith(const Snapshot& snap, const Bricks<CodeT>& bricks,
                     const GainConfig& config, const ImagePlane& plane,
                     const std::vector<Eigen::Vector3d>& dirs, ThreadScratch& scratch,
                     const Viewpoint& view)
{
  if (config.visibility_weighted)
    return computeGeneral<CodeT, true>(snap, bricks, config, plane, dirs, scratch, view);
  if (!snap.roi_mode)
    return computeGeneral<CodeT, false>(snap, bricks, config, plane, dirs, scratch, view);
  if (config.unknown_depth > 0)
    return computeFast<CodeT, true>(snap, bricks, config, plane, dirs, scratch, view);
  return computeFast<CodeT, false>(snap, bricks, config, plane, dirs, scratch, view);
}

} // namespace

struct InformationGain::Impl {
  Snapshot snapshot;
  /// The ROI's boxes the snapshot holds (all after update(); those within the
  /// candidates' reach after compute()).
  std::vector<std::size_t> snapshot_boxes;
  std::vector<std::array<int, 3>> changed_bricks; ///< buildSnapshot()'s buffer
  std::vector<Eigen::Vector3d> dirs_C;            ///< the rays (per config)
  ImagePlane plane;
  std::vector<ThreadScratch> scratch;

  ViewGain compute(const GainConfig& config, ThreadScratch& s,
                   const Viewpoint& view) const
  {
    switch (snapshot.code_bytes) {
    case 1:
      return computeWith(snapshot, snapshot.bricks8, config, plane, dirs_C, s, view);
    case 2:
      return computeWith(snapshot, snapshot.bricks16, config, plane, dirs_C, s, view);
    default:
      return computeWith(snapshot, snapshot.bricks32, config, plane, dirs_C, s, view);
    }
  }
};

// ---------------------------------------------------------------------------------------

double occupancyEntropy(double p)
{
  if (!(p >= 0.0 && p <= 1.0))
    return std::numeric_limits<double>::quiet_NaN();
  if (p == 0.0 || p == 1.0)
    return 0.0;
  return -p * std::log2(p) - (1.0 - p) * std::log2(1.0 - p);
}

GainConfig GainConfig::paper()
{
  GainConfig c;
  c.unknown_only = false;
  c.unknown_depth = 0;
  return c;
}

void GainConfig::validate() const
{
  auto fail = [](const char* field, double value, const char* expected) {
    std::ostringstream s;
    s << "GainConfig: " << field << " = " << value << " must be " << expected;
    throw InvalidArgumentError(s.str());
  };
  if (rays_x < 1 || rays_x > 4096)
    fail("rays_x", rays_x, "in [1, 4096]");
  if (rays_y < 1 || rays_y > 4096)
    fail("rays_y", rays_y, "in [1, 4096]");
  if (!(horizontal_fov_rad > 0.0 && horizontal_fov_rad < M_PI))
    fail("horizontal_fov_rad", horizontal_fov_rad, "in (0, pi) (rad)");
  if (!(vertical_fov_rad > 0.0 && vertical_fov_rad < M_PI))
    fail("vertical_fov_rad", vertical_fov_rad, "in (0, pi) (rad)");
  if (!(std::isfinite(raycast_range_m) && raycast_range_m > 0.0))
    fail("raycast_range_m", raycast_range_m, "finite and > 0 (metres)");
  if (unknown_depth < 0)
    fail("unknown_depth", unknown_depth, ">= 0 (voxels; 0: no limit)");
}

InformationGain::InformationGain() : impl_(std::make_unique<Impl>())
{
  impl_->dirs_C = rayDirectionsBody(config_);
  impl_->plane = imagePlane(config_);
}

InformationGain::~InformationGain() = default;

void InformationGain::setConfig(const GainConfig& config)
{
  config.validate();
  if (config.visibility_weighted != config_.visibility_weighted ||
      config.unknown_only != config_.unknown_only)
    dirty_ = true; // the snapshot holds every known voxel with visibility weighting,
                   // and its values' worth depends on unknown_only
  config_ = config;
  impl_->dirs_C = rayDirectionsBody(config_);
  impl_->plane = imagePlane(config_);
}

void InformationGain::setInputMap(std::shared_ptr<const OccupancyMap> map)
{
  if (!map)
    throw InvalidArgumentError("InformationGain::setInputMap: the map is null");
  map_ = std::move(map);
  dirty_ = true;
}

void InformationGain::setRoi(const Roi& roi)
{
  for (const Box& b : roi.boxes())
    if (!b.center.allFinite() || !b.size.allFinite() || (b.size.array() < 0.0).any()) {
      std::ostringstream s;
      s << "InformationGain::setRoi: box '" << b.name << "' with centre ("
        << b.center.transpose() << ") and size (" << b.size.transpose()
        << ") must be finite with sizes >= 0 (metres)";
      throw InvalidArgumentError(s.str());
    }
  roi_ = roi;
  dirty_ = true;
}

void InformationGain::setNumberOfThreads(int threads)
{
  if (threads < 0) {
    std::ostringstream s;
    s << "InformationGain::setNumberOfThreads: " << threads
      << " must be >= 0 (0: OpenMP's default)";
    throw InvalidArgumentError(s.str());
  }
  threads_ = threads;
}

void InformationGain::update()
{
  if (!map_)
    throw InvalidArgumentError("InformationGain::update: no map set (setInputMap)");
  std::vector<std::size_t> all(roi_.boxes().size());
  for (std::size_t i = 0; i < all.size(); ++i)
    all[i] = i;
  buildSnapshot(all);
}

void InformationGain::buildSnapshot(const std::vector<std::size_t>& boxes)
{
  const Stopwatch start;
  Snapshot& snapshot = impl_->snapshot;
  const int threads = threadsOrDefault(threads_);
  // After one insert into the map the snapshot had, only the bricks it changed are read.
  stats_.incremental =
      !dirty_ && snapshot.built && &map_->getOcTree() == snapshot.tree &&
      impl_->snapshot_boxes == boxes &&
      map_->getChangedBricks(stats_.map_revision, impl_->changed_bricks) &&
      snapshot.update(impl_->changed_bricks, threads);
  if (!stats_.incremental) {
    Roi roi;
    for (std::size_t i : boxes)
      roi.addBox(roi_.boxes()[i]);
    snapshot.build(map_->getOcTree(), roi, config_.visibility_weighted,
                   config_.unknown_only, threads);
  }
  stats_.map_revision = map_->revision();
  impl_->snapshot_boxes = boxes;
  dirty_ = false;
  stats_.update_ms = start.ms();
  stats_.bricks = snapshot.brick_count;
  stats_.values = snapshot.values.size();
  stats_.leaves = snapshot.leaf_count;
}

void InformationGain::ensureSnapshot(const std::vector<std::size_t>& boxes)
{
  if (!map_)
    throw InvalidArgumentError("InformationGain::compute: no map set (setInputMap)");
  stats_.rebuilt = false;
  if (dirty_ || !impl_->snapshot.built || map_->revision() != stats_.map_revision ||
      &map_->getOcTree() != impl_->snapshot.tree || impl_->snapshot_boxes != boxes) {
    buildSnapshot(boxes);
    stats_.rebuilt = true;
  }
}

void InformationGain::compute(const std::vector<Viewpoint>& candidates,
                              std::vector<ViewGain>& out)
{
  if (!map_)
    throw InvalidArgumentError("InformationGain::compute: no map set (setInputMap)");
  const std::vector<std::size_t> boxes = boxesWithinReach(
      roi_, candidates, config_.raycast_range_m, map_->getOcTree().getResolution());
  if (!roi_.empty() && boxes.empty()) {
    out.assign(candidates.size(), ViewGain()); // what the kernels give: no ray meets it
    stats_.rebuilt = false;
    stats_.gain_ms = 0.0;
    stats_.candidates = candidates.size();
    stats_.rays_cast = 0;
    return;
  }
  ensureSnapshot(boxes);
  const Stopwatch start;
  out.assign(candidates.size(), ViewGain());
  const int threads = std::max(
      1, std::min(threadsOrDefault(threads_), static_cast<int>(candidates.size())));
  if (impl_->scratch.size() < static_cast<std::size_t>(threads))
    impl_->scratch.resize(static_cast<std::size_t>(threads));
  const auto n = static_cast<std::int64_t>(candidates.size());
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
  for (std::int64_t i = 0; i < n; ++i)
    out[static_cast<std::size_t>(i)] = impl_->compute(
        config_, impl_->scratch[static_cast<std::size_t>(omp_get_thread_num())],
        candidates[static_cast<std::size_t>(i)]);
  stats_.gain_ms = start.ms();
  stats_.candidates = candidates.size();
  stats_.rays_cast = 0;
  for (const ViewGain& g : out)
    stats_.rays_cast += g.rays_cast;
}

ViewGain InformationGain::compute(const Viewpoint& candidate)
{
  std::vector<ViewGain> out;
  compute(std::vector<Viewpoint>{candidate}, out);
  return out.front();
}

} // namespace plantnbv
