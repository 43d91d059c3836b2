#pragma once
// The map snapshot of the fast information gain (internal to the planning module): the
// voxels that can matter, in bricks of 8^3, each voxel a small code.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <plantnbv/common/box.h>
#include <plantnbv/common/voxel_lattice.h>

namespace octomap {
class OcTree;
class OcTreeNode;
} // namespace octomap

namespace plantnbv {
namespace gain_detail {

constexpr int kBrickShift = 3; ///< bricks of 8^3 voxels (octree nodes at depth 13)
constexpr int kBrickMask = (1 << kBrickShift) - 1;
constexpr int kBrickVoxels = 1 << (3 * kBrickShift);
constexpr std::uint32_t kUniform = 0x80000000u; ///< table entry: one code for the brick
/// Table entry while fill() runs on several threads: the brick lies in the filling
/// thread's own buffer (Bricks::thread_voxels), not yet in `voxels`.
constexpr std::uint32_t kThreadLocal = 0x40000000u;
constexpr int kKeyLimit = VoxelLattice::kKeyLimit; ///< keys lie in [0, 65536)

/// Voxel codes: bit 0 = the voxel centre lies in the ROI (always set without ROI),
/// bit 1 = occupied, bits 2.. = the index of its value (0 = unknown).
constexpr unsigned kInRoi = 1u;
constexpr unsigned kOccupied = 2u;
constexpr int kValueShift = 2;

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
  void extend(const KeyBox& b);
};

/// The keys whose voxel centre `box` contains: exactly Box::contains on OctoMap's
/// keyToCoord centres (per axis |centre - c| <= size / 2, the same operations), which
/// per axis is an interval.
KeyBox roiKeyBox(const Box& box, const VoxelLattice& lattice);

/// An axis-aligned box as its corners (metres), for segment clipping.
struct ClipBox {
  double lo[3];
  double hi[3];
};

/// What a value index stands for.
struct Value {
  float log_odds = 0.0f; ///< the map's (0 for unknown)
  /// What a voxel of this value adds to the gain (bits): occupancyEntropy of OctoMap's
  /// getOccupancy(), or 0 for a known value with GainConfig::unknown_only.
  double entropy = 1.0;
  double free_prob = 0.5; ///< 1 - occupancy probability
  bool occupied = false;  ///< log-odds > the map's threshold (OcTree::isNodeOccupied)
};

/// The brick table and the bricks' voxels for one code width.
template <typename CodeT>
struct Bricks {
  int b0[3] = {0, 0, 0}; ///< brick coordinates (key >> 3) of the table's first slot
  int nb[3] = {0, 0, 0};
  /// Per brick its index in `voxels` (512 codes each), with kUniform set when all its
  /// voxels have one code: such bricks share one copy per code. (While fill() runs, a
  /// uniform entry holds the code itself: kUniform | code.)
  std::vector<std::uint32_t> table;
  std::vector<CodeT> voxels;
  CodeT outside = 0;               ///< the code of voxels outside the table
  std::uint32_t outside_brick = 0; ///< a brick of `outside` codes
  /// fill() on several threads: each thread's new bricks, moved into `voxels` in the
  /// order one thread would have made them (kept only for their capacity).
  std::vector<std::vector<CodeT>> thread_voxels;
  /// The bricks that uniform entries share: (code, brick) pairs, few.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> shared;
  /// Snapshot::update(): bricks of `voxels` no entry uses any more, to reuse.
  std::vector<std::uint32_t> free_bricks;

  std::size_t slot(int rx, int ry, int rz) const
  {
    return (static_cast<std::size_t>(rz) * static_cast<std::size_t>(nb[1]) +
            static_cast<std::size_t>(ry)) *
               static_cast<std::size_t>(nb[0]) +
           static_cast<std::size_t>(rx);
  }
  /// The slot of the brick holding key k, false outside the table.
  bool slotOf(int kx, int ky, int kz, std::size_t& s) const
  {
    const unsigned rx = static_cast<unsigned>((kx >> kBrickShift) - b0[0]);
    const unsigned ry = static_cast<unsigned>((ky >> kBrickShift) - b0[1]);
    const unsigned rz = static_cast<unsigned>((kz >> kBrickShift) - b0[2]);
    if (rx >= static_cast<unsigned>(nb[0]) || ry >= static_cast<unsigned>(nb[1]) ||
        rz >= static_cast<unsigned>(nb[2]))
      return false;
    s = slot(static_cast<int>(rx), static_cast<int>(ry), static_cast<int>(rz));
    return true;
  }
  /// The codes of the brick of a table entry.
  const CodeT* brick(std::uint32_t entry) const
  {
    return &voxels[static_cast<std::size_t>(entry & ~kUniform) << (3 * kBrickShift)];
  }
  CodeT code(int kx, int ky, int kz) const
  {
    std::size_t s;
    if (!slotOf(kx, ky, kz, s))
      return outside;
    return brick(table[s])[brickLocal(kx, ky, kz)];
  }
  /// fill(): the brick at slot s as voxels (allocated, filled with its uniform code).
  CodeT* materialize(std::size_t s);
  /// After fill(): uniform entries point to one shared brick per code.
  void shareUniformBricks();
  /// The shared brick of `code`, made if there is none yet.
  std::uint32_t sharedBrick(std::uint32_t code);
  /// Snapshot::update(): the brick at slot s gets the codes `v` (512), as a shared
  /// brick if they are all alike, else as its own.
  void store(std::size_t s, const CodeT* v);
  /// Snapshot::update(): the table over the bricks of `region`, a box that holds the
  /// old one; the new slots hold `outside`.
  void resize(const KeyBox& region);
  void clear();
};

/// The snapshot: what the gain needs of the map, for one ROI and mode.
class Snapshot {
public:
  /// Rebuilds from the tree. `full`: every known voxel (no ROI, or visibility
  /// weighting); otherwise the voxels in the ROI's key box and the occupied ones.
  /// `unknown_only`: a known value is worth 0 bits (GainConfig::unknown_only).
  /// `threads` (>= 1) OpenMP threads walk disjoint subtrees and fill their bricks; their
  /// output is merged in the tree's order, so the snapshot (its codes, values and the
  /// layout of its bricks) is the same at any thread count.
  void build(const octomap::OcTree& tree, const Roi& roi, bool full, bool unknown_only,
             int threads);
  /// Brings the snapshot up to date after a change of its tree that changed no voxel
  /// outside the `changed` bricks (brick coordinates, key >> 3;
  /// OccupancyMap::getChangedBricks): reads only their voxels from the tree. Gains are
  /// then those of a snapshot built anew (the values of voxels no longer in the tree may
  /// stay in `values`: no voxel has them, so they add nothing). \return false, the
  /// snapshot unchanged, where it cannot: the values need wider codes, or the region
  /// would span more than 2^28 bricks; build() it then.
  bool update(const std::vector<std::array<int, 3>>& changed, int threads);

  const octomap::OcTree* tree = nullptr;
  VoxelLattice lattice{1.0}; ///< the tree's
  bool roi_mode = false;     ///< a non-empty ROI
  bool full = false;
  int code_bytes = 1;              ///< 1, 2 or 4: which of the Bricks below is in use
  std::vector<KeyBox> roi_boxes;   ///< keys inside each ROI box (some may be empty)
  KeyBox roi_bbox;                 ///< their union's bounding box
  std::vector<ClipBox> clip_boxes; ///< the ROI boxes grown by one voxel
  std::vector<Value> values;       ///< by value index; 0 = unknown
  /// The value indices in the order the gain sums over them: unknown (0) first, then by
  /// increasing log-odds. A build's indices are in that order already; update() gives
  /// new values the next indices, and this keeps the sums those of a new build.
  std::vector<std::uint32_t> value_order;
  Bricks<std::uint8_t> bricks8;
  Bricks<std::uint16_t> bricks16;
  Bricks<std::uint32_t> bricks32;
  std::size_t leaf_count = 0;
  std::size_t brick_count = 0;
  bool built = false;

private:
  struct Leaf {
    int k[3];
    int shift;           ///< the cube has 2^shift voxels per side
    std::uint32_t value; ///< provisional: an index into its Part's `distinct`
  };
  /// One thread's share of the walk (and its buffer of slots in fill()).
  struct Part {
    std::vector<Leaf> leaves;
    std::vector<float> distinct;          ///< log-odds per provisional index
    std::vector<std::uint32_t> hash_keys; ///< open addressing: float bits + 1 (0 = empty)
    std::vector<std::uint32_t> hash_values;
    std::uint32_t last_key = 0; ///< valueIndex's last lookup (0: none)
    std::uint32_t last_value = 0;
    std::vector<std::uint32_t> remap; ///< provisional index -> sorted value index
    KeyBox extent; ///< the keys its leaves need in the snapshot (see collect())
    /// fill() on several threads: the table slot of each brick in the thread's buffer.
    std::vector<std::size_t> brick_slots;

    void reset();
    std::uint32_t valueIndex(float log_odds);
  };
  /// A subtree that one thread walks, then one thread fills: its root lies at depth 13
  /// or above, so its cube holds whole bricks. Tasks are disjoint cubes, listed in the
  /// order of a depth-first walk.
  struct Task {
    const octomap::OcTreeNode* node;
    int depth;
    int k[3];
    int part = 0; ///< collect(): the Part that holds its leaves
    std::size_t leaf_begin = 0, leaf_end = 0;
    /// fill() on several threads: its new bricks are [brick_begin, brick_end) of
    /// thread fill_part's buffer, and go to `voxels` from brick_index on.
    int fill_part = 0;
    std::size_t brick_begin = 0, brick_end = 0, brick_index = 0;
  };
  /// Whether the subtree at `node` (depth, first key k) can hold a voxel to snapshot.
  bool matters(const octomap::OcTreeNode* node, int depth, const int k[3]) const;
  /// collect(): a leaf that matters, the cube of 2^shift voxels from key k.
  void addLeaf(Part& part, const int k[3], int shift, float log_odds) const;
  /// update(): the leaves over the brick whose first key is k (a leaf larger than the
  /// brick as the brick's cube), into `part`.
  void collectBrick(Part& part, const int k[3]) const;
  /// The tasks' leaves into parts_ (in parallel): their subtrees, or with `bricks` the
  /// bricks from their first keys (collectBrick()).
  void collectTasks(int threads, bool bricks);
  /// Adds the parts' distinct log-odds to `sorted` (kept sorted, each value once) and
  /// sets the parts' remap to the value indices.
  void addDistinctValues(int threads, std::vector<float>& sorted);
  /// `values` and `value_order` from the sorted distinct log-odds.
  void setValues(const std::vector<float>& sorted);
  /// `value_order` from `values`.
  void orderValues();
  /// What a voxel of these log-odds stands for.
  Value valueOf(float log_odds) const;
  /// The index of the value equal to `log_odds`; false if there is none.
  bool findValue(float log_odds, std::uint32_t& index) const;
  /// update(): the parts' log-odds that are not values yet appended as values (in
  /// increasing log-odds), and the parts' remap set. \return false, nothing changed,
  /// where the values would need wider codes.
  bool addNewValues(int threads);
  /// How the ROI covers the brick whose first key is k: 0 not, 1 in part, 2 whole.
  int roiCover(const int k[3]) const;
  /// Sets kInRoi on the brick's voxels (first key k) that lie in an ROI box.
  template <typename CodeT>
  void markRoi(const int k[3], CodeT* v) const;
  /// update() for one code width: the table grown to `region`, then the changed bricks
  /// written from the tasks' leaves.
  template <typename CodeT>
  void updateBricks(Bricks<CodeT>& bricks, const KeyBox& region);
  /// tasks_: the tree's top levels cut into disjoint subtrees.
  void split(const octomap::OcTreeNode* root);
  void collect(Part& part, const octomap::OcTreeNode* node, int depth,
               const int k[3]) const;
  template <typename CodeT>
  void fill(Bricks<CodeT>& bricks, const KeyBox& region, int threads);
  /// fill(): the leaves of one task, into bricks made by `writer`.
  template <typename Writer>
  void fillTask(const Task& task, const KeyBox& region, Writer& writer) const;

  float threshold_ = 0.0f;
  bool unknown_only_ = false;
  KeyBox region_;           ///< the keys the bricks hold (fill()'s region)
  std::vector<Part> parts_; ///< one per thread
  std::vector<Task> tasks_;
  std::vector<Task> next_tasks_; ///< split()'s buffer
};

} // namespace gain_detail
} // namespace plantnbv
