// The fast information gain: a bricked snapshot of the map, OctoMap's exact ray
// traversal (plantnbv/octree/ray_traversal.h), rays culled and clipped to the ROI.
// Compiled with -ffp-contract=off (CMakeLists.txt): the traversal must round like
// OctoMap's.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <omp.h>
#include <sstream>
#include <unordered_set>
#include <vector>

#include <octomap/OcTree.h>

#include <plantnbv/common/error.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/octree/ray_traversal.h>
#include <plantnbv/planning/information_gain.h>

#include "gain_rays.h"

namespace plantnbv {

namespace rt = ray_traversal;

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

constexpr int kBrickShift = 3; ///< bricks of 8^3 voxels (an octree node at depth 13)
constexpr int kBrickMask = (1 << kBrickShift) - 1;
constexpr int kBrickVoxels = 1 << (3 * kBrickShift);
constexpr std::uint32_t kUniform = 0x80000000u; ///< table entry: one code for the brick
constexpr int kKeyLimit = 2 * rt::kTreeMaxVal;  ///< keys lie in [0, 65536)

inline int brickLocal(int kx, int ky, int kz)
{
  return ((kz & kBrickMask) << (2 * kBrickShift)) | ((ky & kBrickMask) << kBrickShift) |
         (kx & kBrickMask);
}

/// An inclusive box of keys; empty when lo > hi on an axis.
struct KeyBox {
  int lo[3] = {0, 0, 0};
  int hi[3] = {-1, -1, -1};

  bool empty() const { return lo[0] > hi[0] || lo[1] > hi[1] || lo[2] > hi[2]; }
  bool contains(int kx, int ky, int kz) const
  {
    return kx >= lo[0] && kx <= hi[0] && ky >= lo[1] && ky <= hi[1] && kz >= lo[2] &&
           kz <= hi[2];
  }
  /// Overlaps the cube of side `size` from key `k`.
  bool overlapsCube(const int k[3], int size) const
  {
    for (int a = 0; a < 3; ++a)
      if (k[a] + size - 1 < lo[a] || k[a] > hi[a])
        return false;
    return true;
  }
  void extend(const KeyBox& b)
  {
    if (b.empty())
      return;
    if (empty()) {
      *this = b;
      return;
    }
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], b.lo[a]);
      hi[a] = std::max(hi[a], b.hi[a]);
    }
  }
};

/// The keys whose voxel centre the box contains, per axis an interval: exactly
/// Box::contains on keyToCoord centres (|centre - c| <= size / 2, the same operations).
KeyBox roiKeyBox(const Box& box, double resolution)
{
  KeyBox k;
  for (int a = 0; a < 3; ++a) {
    const double c = box.center[a], half = 0.5 * box.size[a];
    auto inside = [&](int key) { return std::abs(rt::keyToCoord(resolution, key) - c) <= half; };
    const double lo = std::floor((c - half) / resolution) + rt::kTreeMaxVal - 2.0;
    const double hi = std::ceil((c + half) / resolution) + rt::kTreeMaxVal + 2.0;
    int klo = static_cast<int>(std::max(lo, 0.0));
    int khi = static_cast<int>(std::min(hi, kKeyLimit - 1.0));
    while (klo <= khi && !inside(klo))
      ++klo;
    while (khi >= klo && !inside(khi))
      --khi;
    k.lo[a] = klo;
    k.hi[a] = khi;
  }
  return k;
}

/// What a code's value stands for.
struct Value {
  double entropy = 1.0;   ///< bits
  double free_prob = 0.5; ///< 1 - occupancy probability
  bool occupied = false;
};

/// A leaf of the octree: a cube of 2^shift voxels per side from key k.
struct Leaf {
  int k[3];
  int shift;
  float log_odds;
};

/// Per voxel a code: (value index << 1) | in ROI. Value 0 is "unknown". The table holds
/// per 8^3 brick either kUniform | code or the brick's index in `voxels`.
template <typename CodeT>
struct Bricks {
  int b0[3] = {0, 0, 0};
  int nb[3] = {0, 0, 0};
  std::vector<std::uint32_t> table;
  std::vector<CodeT> voxels;
  CodeT outside = 0; ///< the code of voxels outside the table

  std::size_t slot(int bx, int by, int bz) const
  {
    return (static_cast<std::size_t>(bz) * nb[1] + by) * nb[0] + bx;
  }

  CodeT code(int kx, int ky, int kz) const
  {
    const unsigned bx = static_cast<unsigned>((kx >> kBrickShift) - b0[0]);
    const unsigned by = static_cast<unsigned>((ky >> kBrickShift) - b0[1]);
    const unsigned bz = static_cast<unsigned>((kz >> kBrickShift) - b0[2]);
    if (bx >= static_cast<unsigned>(nb[0]) || by >= static_cast<unsigned>(nb[1]) ||
        bz >= static_cast<unsigned>(nb[2]))
      return outside;
    const std::uint32_t e = table[slot(static_cast<int>(bx), static_cast<int>(by),
                                       static_cast<int>(bz))];
    if (e & kUniform)
      return static_cast<CodeT>(e & ~kUniform);
    return voxels[(static_cast<std::size_t>(e) << (3 * kBrickShift)) + brickLocal(kx, ky, kz)];
  }

  /// The brick at slot s as voxels (allocated, filled with its uniform code, if needed).
  CodeT* materialize(std::size_t s)
  {
    std::uint32_t& e = table[s];
    if (e & kUniform) {
      const CodeT c = static_cast<CodeT>(e & ~kUniform);
      const std::size_t index = voxels.size() >> (3 * kBrickShift);
      voxels.resize(voxels.size() + kBrickVoxels, c);
      e = static_cast<std::uint32_t>(index);
    }
    return &voxels[static_cast<std::size_t>(e) << (3 * kBrickShift)];
  }

  void clear()
  {
    table.clear();
    voxels.clear();
    for (int a = 0; a < 3; ++a)
      b0[a] = nb[a] = 0;
  }
};

/// One candidate's set of distinct voxels (keys in a box of bricks), with the largest
/// visibility per voxel when weighted. Reused: reset() clears only what was used.
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
      auto it = overflow_.insert(pack(kx, ky, kz));
      if (it.second)
        overflow_vis_.push_back({pack(kx, ky, kz), vis});
      else
        for (auto& [key, v] : overflow_vis_)
          if (key == pack(kx, ky, kz))
            v = std::max(v, vis);
      return;
    }
    const int local = brickLocal(kx, ky, kz);
    const std::size_t slot = static_cast<std::size_t>(w - bits_.data()) / 8;
    double& v = vis_[slot * kBrickVoxels + local];
    if (vis > v)
      v = vis; // starts at -1
  }

  /// Calls f(kx, ky, kz, vis) for every voxel in a fixed order (first-touched brick
  /// first, then voxel index); vis is 1 when not weighted.
  template <typename F>
  void forEach(F&& f) const
  {
    for (std::size_t slot = 0; slot < used_.size(); ++slot) {
      const std::size_t s = used_[slot];
      const int bx = static_cast<int>(s % nb_[0]);
      const int by = static_cast<int>((s / nb_[0]) % nb_[1]);
      const int bz = static_cast<int>(s / (static_cast<std::size_t>(nb_[0]) * nb_[1]));
      const int base[3] = {(bx + b0_[0]) << kBrickShift, (by + b0_[1]) << kBrickShift,
                           (bz + b0_[2]) << kBrickShift};
      for (int local = 0; local < kBrickVoxels; ++local) {
        double vis = 1.0;
        if (weighted_) {
          vis = vis_[slot * kBrickVoxels + local];
          if (vis < 0.0)
            continue;
        } else if (!(bits_[slot * 8 + (local >> 6)] >> (local & 63) & 1u)) {
          continue;
        }
        f(base[0] + (local & kBrickMask), base[1] + ((local >> kBrickShift) & kBrickMask),
          base[2] + (local >> (2 * kBrickShift)), vis);
      }
    }
    for (const auto& [key, vis] : overflow_vis_)
      f(static_cast<int>(key >> 32), static_cast<int>((key >> 16) & 0xffffu),
        static_cast<int>(key & 0xffffu), vis);
    if (!weighted_) {
      std::vector<std::uint64_t> rest(overflow_.begin(), overflow_.end());
      std::sort(rest.begin(), rest.end());
      for (const std::uint64_t key : rest)
        f(static_cast<int>(key >> 32), static_cast<int>((key >> 16) & 0xffffu),
          static_cast<int>(key & 0xffffu), 1.0);
    }
  }

private:
  static std::uint64_t pack(int kx, int ky, int kz)
  {
    return (static_cast<std::uint64_t>(kx) << 32) | (static_cast<std::uint64_t>(ky) << 16) |
           static_cast<std::uint64_t>(kz);
  }

  /// The bit words of the voxel's brick (made on first use); null outside the box.
  std::uint64_t* words(int kx, int ky, int kz)
  {
    const unsigned bx = static_cast<unsigned>((kx >> kBrickShift) - b0_[0]);
    const unsigned by = static_cast<unsigned>((ky >> kBrickShift) - b0_[1]);
    const unsigned bz = static_cast<unsigned>((kz >> kBrickShift) - b0_[2]);
    if (bx >= static_cast<unsigned>(nb_[0]) || by >= static_cast<unsigned>(nb_[1]) ||
        bz >= static_cast<unsigned>(nb_[2]))
      return nullptr;
    const std::size_t s = (static_cast<std::size_t>(bz) * nb_[1] + by) * nb_[0] + bx;
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
  /// Voxels outside the box (never expected: the box holds every voxel that counts).
  std::unordered_set<std::uint64_t> overflow_;
  std::vector<std::pair<std::uint64_t, double>> overflow_vis_;
};

/// One thread's buffers.
struct ThreadScratch {
  VoxelSet set;
  std::vector<std::uint32_t> counts; ///< per value
  std::vector<std::uint8_t> ray_marks;
};

} // namespace

struct InformationGain::Impl {
  // The snapshot (update()).
  const octomap::OcTree* tree = nullptr;
  double resolution = 0.0;
  double resolution_factor = 0.0;
  bool roi_mode = false; ///< a non-empty ROI
  bool full = false;     ///< every known voxel stored (no ROI, or visibility weighting)
  bool wide = false;     ///< 32-bit codes (more than 32767 distinct values)
  std::vector<KeyBox> roi_boxes; ///< keys inside each ROI box (some may be empty)
  KeyBox roi_bbox;               ///< their union's bounding box
  std::vector<Box> clip_boxes;   ///< the ROI boxes grown by one voxel
  std::vector<Value> values;
  Bricks<std::uint16_t> narrow;
  Bricks<std::uint32_t> wide_bricks;
  std::vector<Leaf> leaves;
  bool built = false;

  // The rays (per config).
  std::vector<Eigen::Vector3d> dirs_C;
  gain_detail::ImagePlane plane;

  std::vector<ThreadScratch> scratch;

  void collect(const octomap::OcTreeNode* node, int depth, const int k[3], float threshold)
  {
    const int size = 1 << (rt::kTreeDepth - depth);
    const bool near_roi = roi_mode && roi_bbox.overlapsCube(k, size);
    if (!tree->nodeHasChildren(node)) {
      if (full || near_roi || node->getLogOdds() > threshold)
        leaves.push_back({{k[0], k[1], k[2]}, rt::kTreeDepth - depth, node->getLogOdds()});
      return;
    }
    // Inner nodes hold the maximum of their children (OccupancyMap keeps them so):
    // away from the ROI only subtrees with an occupied voxel matter.
    if (!full && !near_roi && !(node->getLogOdds() > threshold))
      return;
    const int half = size >> 1;
    for (unsigned i = 0; i < 8; ++i) {
      if (!tree->nodeChildExists(node, i))
        continue;
      const int c[3] = {k[0] + ((i & 1u) ? half : 0), k[1] + ((i & 2u) ? half : 0),
                        k[2] + ((i & 4u) ? half : 0)};
      collect(tree->getNodeChild(node, i), depth + 1, c, threshold);
    }
  }

  template <typename CodeT>
  void fill(Bricks<CodeT>& bricks, const KeyBox& region, const std::vector<float>& sorted)
  {
    bricks.clear();
    std::size_t n = 1;
    for (int a = 0; a < 3; ++a) {
      bricks.b0[a] = region.lo[a] >> kBrickShift;
      bricks.nb[a] = (region.hi[a] >> kBrickShift) - bricks.b0[a] + 1;
      n *= static_cast<std::size_t>(bricks.nb[a]);
    }
    if (n > (std::size_t{1} << 28)) {
      std::ostringstream s;
      s << "InformationGain::update: the map's region to snapshot spans " << n
        << " bricks of 8^3 voxels, more than 2^28; use an ROI (and no visibility "
           "weighting) so that only the occupied voxels outside it are needed";
      throw Error(s.str());
    }
    bricks.outside = roi_mode ? 0 : 1; // unknown; in the "ROI" when everything counts
    bricks.table.assign(n, kUniform | bricks.outside);

    // Bricks at the ROI's border get per-voxel flags; bricks inside it a uniform code.
    if (roi_mode && !roi_bbox.empty()) {
      for (int bz = roi_bbox.lo[2] >> kBrickShift; bz <= roi_bbox.hi[2] >> kBrickShift; ++bz)
        for (int by = roi_bbox.lo[1] >> kBrickShift; by <= roi_bbox.hi[1] >> kBrickShift; ++by)
          for (int bx = roi_bbox.lo[0] >> kBrickShift; bx <= roi_bbox.hi[0] >> kBrickShift;
               ++bx) {
            const int k[3] = {bx << kBrickShift, by << kBrickShift, bz << kBrickShift};
            bool inside = false, touches = false;
            for (const KeyBox& b : roi_boxes) {
              if (b.empty() || !b.overlapsCube(k, 1 << kBrickShift))
                continue;
              touches = true;
              bool covers = true;
              for (int a = 0; a < 3; ++a)
                covers = covers && b.lo[a] <= k[a] && b.hi[a] >= k[a] + kBrickMask;
              inside = inside || covers;
            }
            const std::size_t s = bricks.slot(bx - bricks.b0[0], by - bricks.b0[1],
                                              bz - bricks.b0[2]);
            if (inside) {
              bricks.table[s] = kUniform | 1u;
            } else if (touches) {
              CodeT* v = bricks.materialize(s);
              for (int local = 0; local < kBrickVoxels; ++local) {
                const int kx = k[0] + (local & kBrickMask);
                const int ky = k[1] + ((local >> kBrickShift) & kBrickMask);
                const int kz = k[2] + (local >> (2 * kBrickShift));
                bool in = false;
                for (const KeyBox& b : roi_boxes)
                  in = in || b.contains(kx, ky, kz);
                v[local] = static_cast<CodeT>(in ? 1 : 0);
              }
            }
          }
    }

    for (const Leaf& leaf : leaves) {
      const auto it = std::lower_bound(sorted.begin(), sorted.end(), leaf.log_odds);
      const CodeT value = static_cast<CodeT>((it - sorted.begin()) + 1);
      const int size = 1 << leaf.shift;
      int lo[3], hi[3];
      bool empty = false;
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::max(leaf.k[a], region.lo[a]);
        hi[a] = std::min(leaf.k[a] + size - 1, region.hi[a]);
        empty = empty || lo[a] > hi[a];
      }
      if (empty)
        continue;
      for (int bz = lo[2] >> kBrickShift; bz <= hi[2] >> kBrickShift; ++bz)
        for (int by = lo[1] >> kBrickShift; by <= hi[1] >> kBrickShift; ++by)
          for (int bx = lo[0] >> kBrickShift; bx <= hi[0] >> kBrickShift; ++bx) {
            const std::size_t s = bricks.slot(bx - bricks.b0[0], by - bricks.b0[1],
                                              bz - bricks.b0[2]);
            const int k0[3] = {bx << kBrickShift, by << kBrickShift, bz << kBrickShift};
            int v_lo[3], v_hi[3];
            bool whole = true;
            for (int a = 0; a < 3; ++a) {
              v_lo[a] = std::max(lo[a], k0[a]) - k0[a];
              v_hi[a] = std::min(hi[a], k0[a] + kBrickMask) - k0[a];
              whole = whole && v_lo[a] == 0 && v_hi[a] == kBrickMask;
            }
            std::uint32_t& e = bricks.table[s];
            if (whole && (e & kUniform)) {
              e = kUniform | (static_cast<std::uint32_t>(value) << 1) | (e & 1u);
              continue;
            }
            CodeT* v = bricks.materialize(s);
            for (int z = v_lo[2]; z <= v_hi[2]; ++z)
              for (int y = v_lo[1]; y <= v_hi[1]; ++y)
                for (int x = v_lo[0]; x <= v_hi[0]; ++x) {
                  CodeT& c = v[(z << (2 * kBrickShift)) | (y << kBrickShift) | x];
                  c = static_cast<CodeT>((value << 1) | (c & 1u));
                }
          }
    }
  }

  std::size_t brickCount() const
  {
    return wide ? wide_bricks.voxels.size() / kBrickVoxels : narrow.voxels.size() / kBrickVoxels;
  }

  void build(const OccupancyMap& map, const Roi& roi, const GainConfig& config)
  {
    built = false;
    tree = &map.getOcTree();
    resolution = tree->getResolution();
    resolution_factor = 1.0 / resolution; // as OcTreeBaseImpl computes it
    roi_mode = !roi.empty();
    full = !roi_mode || config.visibility_weighted;
    roi_boxes.clear();
    roi_bbox = KeyBox();
    clip_boxes.clear();
    for (const Box& b : roi.boxes()) {
      roi_boxes.push_back(roiKeyBox(b, resolution));
      roi_bbox.extend(roi_boxes.back());
      const Eigen::Vector3d grow = Eigen::Vector3d::Constant(resolution);
      clip_boxes.push_back(Box::fromMinMax(b.min() - grow, b.max() + grow));
    }

    leaves.clear();
    const float threshold = tree->getOccupancyThresLog();
    if (const octomap::OcTreeNode* root = tree->getRoot()) {
      const int k[3] = {0, 0, 0};
      collect(root, 0, k, threshold);
    }

    // The distinct log-odds values, sorted: value i + 1 is sorted[i]; 0 is unknown.
    std::vector<float> sorted;
    sorted.reserve(leaves.size());
    for (const Leaf& leaf : leaves)
      sorted.push_back(leaf.log_odds);
    std::sort(sorted.begin(), sorted.end());
    sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
    values.assign(sorted.size() + 1, Value());
    values[0].entropy = occupancyEntropy(0.5);
    values[0].free_prob = 0.5;
    values[0].occupied = false;
    for (std::size_t i = 0; i < sorted.size(); ++i) {
      const double p = octomap::probability(sorted[i]); // OcTreeNode::getOccupancy()
      values[i + 1].entropy = occupancyEntropy(p);
      values[i + 1].free_prob = 1.0 - p;
      values[i + 1].occupied = sorted[i] > threshold; // OcTree::isNodeOccupied
    }
    wide = values.size() > 32767;

    // The region: the ROI's keys, every stored occupied leaf, and the other stored
    // leaves where they matter (within the ROI's keys unless every voxel is needed).
    KeyBox region = roi_bbox;
    for (const Leaf& leaf : leaves) {
      KeyBox b;
      for (int a = 0; a < 3; ++a) {
        b.lo[a] = leaf.k[a];
        b.hi[a] = leaf.k[a] + (1 << leaf.shift) - 1;
        if (!full && !(leaf.log_odds > threshold)) {
          b.lo[a] = std::max(b.lo[a], roi_bbox.lo[a]);
          b.hi[a] = std::min(b.hi[a], roi_bbox.hi[a]);
        }
      }
      region.extend(b);
    }
    if (region.empty()) // nothing known, no ROI voxel: one brick of "unknown"
      for (int a = 0; a < 3; ++a)
        region.lo[a] = region.hi[a] = rt::kTreeMaxVal;
    if (wide) {
      narrow.clear();
      fill(wide_bricks, region, sorted);
    } else {
      wide_bricks.clear();
      fill(narrow, region, sorted);
    }
    built = true;
  }
};

// ---------------------------------------------------------------------------------------

namespace {

/// Walks one ray's voxels: looks each up in the snapshot, dedupes those in the ROI,
/// stops at an occupied voxel (unweighted) and once past the ROI's last box.
template <typename CodeT, bool kWeighted>
struct RayWalker {
  const Bricks<CodeT>& bricks;
  const Value* values;
  VoxelSet& set;
  std::uint32_t* counts;
  double t_stop = std::numeric_limits<double>::infinity();
  double vis = 1.0;
  bool stopped = false; ///< at an occupied voxel
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
    const CodeT c = bricks.code(kx, ky, kz);
    const Value& value = values[c >> 1];
    if constexpr (kWeighted) {
      if (c & 1u)
        set.insertMax(kx, ky, kz, vis);
      vis *= value.free_prob;
      return true;
    } else {
      if ((c & 1u) && set.insert(kx, ky, kz))
        ++counts[c >> 1];
      if (value.occupied) {
        stopped = true;
        return false;
      }
      return true;
    }
  }
};

/// The segment o + s (e - o), s in [0, 1], against a box: the interval of s inside it.
bool clipSegment(const double o[3], const double d[3], const Box& box, double& s0, double& s1)
{
  s0 = 0.0;
  s1 = 1.0;
  const Eigen::Vector3d lo = box.min(), hi = box.max();
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < lo[a] || o[a] > hi[a])
        return false;
      continue;
    }
    double t0 = (lo[a] - o[a]) / d[a], t1 = (hi[a] - o[a]) / d[a];
    if (t0 > t1)
      std::swap(t0, t1);
    s0 = std::max(s0, t0);
    s1 = std::min(s1, t1);
    if (s0 > s1)
      return false;
  }
  return true;
}

} // namespace

namespace {

/// The gain of one candidate on the snapshot.
template <typename CodeT, bool kWeighted>
ViewGain computeOne(const InformationGain::Impl& impl, const Bricks<CodeT>& bricks,
                    const GainConfig& config, ThreadScratch& scratch, const Viewpoint& view)
{
  ViewGain result;
  float origin[3];
  gain_detail::rayOrigin(view, origin);
  int key_origin[3];
  if (!rt::coordToKeyChecked(impl.resolution_factor, origin, key_origin))
    return result; // outside the octree: no ray
  const Eigen::Matrix3d R = view.orientation.toRotationMatrix();
  const int n_rays = config.rays_x * config.rays_y;

  // Rays that may meet the ROI: those whose image-plane cell lies in the projection of
  // a (grown) box, then the exact segment test below.
  std::vector<std::uint8_t>& marks = scratch.ray_marks;
  marks.assign(static_cast<std::size_t>(n_rays), impl.roi_mode ? 0 : 1);
  if (impl.roi_mode) {
    const Eigen::Matrix3d Rt = R.transpose();
    for (const Box& box : impl.clip_boxes) {
      const Eigen::Vector3d lo = box.min(), hi = box.max();
      double x_min = std::numeric_limits<double>::infinity(), x_max = -x_min;
      double y_min = x_min, y_max = -x_min;
      bool behind = false;
      for (int c = 0; c < 8; ++c) {
        const Eigen::Vector3d corner((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(),
                                     (c & 4) ? hi.z() : lo.z());
        const Eigen::Vector3d v = Rt * (corner - view.position); // body frame
        if (!(v.x() > 1e-6)) {
          behind = true;
          break;
        }
        const double x_o = -v.y() / v.x(), y_o = -v.z() / v.x();
        x_min = std::min(x_min, x_o);
        x_max = std::max(x_max, x_o);
        y_min = std::min(y_min, y_o);
        y_max = std::max(y_max, y_o);
      }
      int i0 = 0, i1 = config.rays_x - 1, j0 = 0, j1 = config.rays_y - 1;
      if (!behind) {
        // Column of image-plane x: ((x / tan_h + 1) rays_x - 1) / 2; one cell of margin.
        auto cell = [](double v, double tan_half, int n) {
          return ((v / tan_half + 1.0) * n - 1.0) * 0.5;
        };
        const double ci0 = cell(x_min, impl.plane.tan_half_h, config.rays_x);
        const double ci1 = cell(x_max, impl.plane.tan_half_h, config.rays_x);
        const double cj0 = cell(y_min, impl.plane.tan_half_v, config.rays_y);
        const double cj1 = cell(y_max, impl.plane.tan_half_v, config.rays_y);
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

  // The voxels that count lie in the ROI's keys, or without ROI within the range.
  int b0[3], nb[3];
  if (impl.roi_mode) {
    if (impl.roi_bbox.empty())
      return result; // no voxel centre inside the ROI
    for (int a = 0; a < 3; ++a) {
      b0[a] = impl.roi_bbox.lo[a] >> kBrickShift;
      nb[a] = (impl.roi_bbox.hi[a] >> kBrickShift) - b0[a] + 1;
    }
  } else {
    const int reach = static_cast<int>(std::ceil(config.raycast_range_m * impl.resolution_factor)) + 2;
    for (int a = 0; a < 3; ++a) {
      const int lo = std::max(key_origin[a] - reach, 0);
      const int hi = std::min(key_origin[a] + reach, kKeyLimit - 1);
      b0[a] = lo >> kBrickShift;
      nb[a] = (hi >> kBrickShift) - b0[a] + 1;
    }
  }
  scratch.set.reset(b0, nb, kWeighted);
  scratch.counts.assign(impl.values.size(), 0);

  const double o[3] = {origin[0], origin[1], origin[2]};
  for (int r = 0; r < n_rays; ++r) {
    if (!marks[static_cast<std::size_t>(r)])
      continue;
    float end[3];
    gain_detail::rayEnd(R, view.position, impl.dirs_C[static_cast<std::size_t>(r)],
                        config.raycast_range_m, end);
    int key_end[3];
    if (!rt::coordToKeyChecked(impl.resolution_factor, end, key_end))
      continue;
    RayWalker<CodeT, kWeighted> walker{bricks, impl.values.data(), scratch.set,
                                       scratch.counts.data()};
    if (impl.roi_mode) {
      const double d[3] = {end[0] - o[0], end[1] - o[1], end[2] - o[2]};
      double s_last = -1.0;
      for (const Box& box : impl.clip_boxes) {
        double s0, s1;
        if (clipSegment(o, d, box, s0, s1))
          s_last = std::max(s_last, s1);
      }
      if (s_last < 0.0)
        continue; // misses the ROI
      // The segment ends in a box: nothing is clipped (the end voxel may count).
      if (s_last < 1.0)
        walker.t_stop = s_last * std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    ++result.rays_cast;
    rt::traverseRay(origin, end, key_origin, key_end, impl.resolution, walker);
    if (!walker.stopped && !walker.clipped)
      walker.visit(key_end[0], key_end[1], key_end[2]);
  }

  if constexpr (kWeighted) {
    scratch.set.forEach([&](int kx, int ky, int kz, double vis) {
      const CodeT c = bricks.code(kx, ky, kz);
      ++result.voxels_seen;
      if ((c >> 1) == 0)
        ++result.unknown_seen;
      result.gain += vis * impl.values[c >> 1].entropy;
    });
  } else {
    for (std::size_t v = 0; v < impl.values.size(); ++v) {
      result.voxels_seen += scratch.counts[v];
      result.gain += static_cast<double>(scratch.counts[v]) * impl.values[v].entropy;
    }
    result.unknown_seen = scratch.counts[0];
  }
  return result;
}

} // namespace

// ---------------------------------------------------------------------------------------

double occupancyEntropy(double p)
{
  if (!(p >= 0.0 && p <= 1.0))
    return std::numeric_limits<double>::quiet_NaN();
  if (p == 0.0 || p == 1.0)
    return 0.0;
  return -p * std::log2(p) - (1.0 - p) * std::log2(1.0 - p);
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
}

InformationGain::InformationGain() : impl_(std::make_unique<Impl>())
{
  impl_->dirs_C = gain_detail::rayDirectionsBody(config_);
  impl_->plane = gain_detail::imagePlane(config_);
}

InformationGain::~InformationGain() = default;

void InformationGain::setConfig(const GainConfig& config)
{
  config.validate();
  if (config.visibility_weighted != config_.visibility_weighted)
    dirty_ = true; // the snapshot holds more with visibility weighting
  config_ = config;
  impl_->dirs_C = gain_detail::rayDirectionsBody(config_);
  impl_->plane = gain_detail::imagePlane(config_);
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
      s << "InformationGain::setRoi: box '" << b.name << "' centre (" << b.center.transpose()
        << ") size (" << b.size.transpose() << ") must be finite with sizes >= 0";
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
  const auto start = Clock::now();
  stats_.map_revision = map_->revision();
  impl_->build(*map_, roi_, config_);
  dirty_ = false;
  stats_.update_ms = msSince(start);
  stats_.bricks = impl_->brickCount();
  stats_.values = impl_->values.size();
  stats_.leaves = impl_->leaves.size();
}

void InformationGain::ensureSnapshot()
{
  if (!map_)
    throw InvalidArgumentError("InformationGain::compute: no map set (setInputMap)");
  stats_.update_ms = 0.0;
  if (dirty_ || !impl_->built || map_->revision() != stats_.map_revision ||
      &map_->getOcTree() != impl_->tree)
    update();
}

void InformationGain::compute(const std::vector<Viewpoint>& candidates,
                              std::vector<ViewGain>& out)
{
  ensureSnapshot();
  const auto start = Clock::now();
  out.assign(candidates.size(), ViewGain());
  const int threads = std::max(
      1, std::min(threads_ > 0 ? threads_ : omp_get_max_threads(),
                  static_cast<int>(candidates.size())));
  if (impl_->scratch.size() < static_cast<std::size_t>(threads))
    impl_->scratch.resize(static_cast<std::size_t>(threads));
  const Impl& impl = *impl_;
  const auto n = static_cast<std::int64_t>(candidates.size());
  const bool weighted = config_.visibility_weighted;
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
  for (std::int64_t i = 0; i < n; ++i) {
    ThreadScratch& scratch = impl_->scratch[static_cast<std::size_t>(omp_get_thread_num())];
    const Viewpoint& view = candidates[static_cast<std::size_t>(i)];
    ViewGain& g = out[static_cast<std::size_t>(i)];
    if (impl.wide)
      g = weighted ? computeOne<std::uint32_t, true>(impl, impl.wide_bricks, config_, scratch, view)
                   : computeOne<std::uint32_t, false>(impl, impl.wide_bricks, config_, scratch, view);
    else
      g = weighted ? computeOne<std::uint16_t, true>(impl, impl.narrow, config_, scratch, view)
                   : computeOne<std::uint16_t, false>(impl, impl.narrow, config_, scratch, view);
  }
  stats_.gain_ms = msSince(start);
  stats_.candidates = candidates.size();
  stats_.rays_cast = 0;
  for (const ViewGain& g : out)
    stats_.rays_cast += g.rays_cast;
}

ViewGain InformationGain::compute(const Viewpoint& candidate)
{
  std::vector<ViewGain> out;
  compute({candidate}, out);
  return out.front();
}

} // namespace plantnbv
