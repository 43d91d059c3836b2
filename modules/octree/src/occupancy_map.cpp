#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <omp.h>
#include <sstream>
#include <vector>

#include <octomap/OcTree.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/stopwatch.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/octree/ray_traversal.h>
#include <plantnbv/octree/region_horizon.h>

// This file must round like OctoMap: no fused multiply-add contraction (CMakeLists.txt
// compiles it with -ffp-contract=off), no fast-math.
#ifdef __FAST_MATH__
#error "occupancy_map.cpp must not be compiled with -ffast-math"
#endif

namespace plantnbv {

namespace {

using ray_traversal::traverseRay;
constexpr int kTreeDepth = VoxelLattice::kTreeDepth;

/// The per-frame bitset is made of blocks of 64^3 voxels aligned with the octree (an
/// octree node at depth 10). Inside a block, voxel (x, y, z) (0..63 each) is bit
/// morton(x, y, z) of the block's 4096 x 64 bits, x in the lowest bit of each triple as
/// in OctoMap's child index: bits in increasing order are voxels in octree order.
constexpr int kBlockShift = 6;
constexpr int kBlockMask = (1 << kBlockShift) - 1;
constexpr int kWordsPerBlock = 1 << (3 * kBlockShift - 6);

/// Spreads the 10 low bits of v to every third bit (bit i to bit 3i).
constexpr std::uint32_t spreadBits(std::uint32_t v)
{
  v &= 0x000003ffu;
  v = (v ^ (v << 16)) & 0xff0000ffu;
  v = (v ^ (v << 8)) & 0x0300f00fu;
  v = (v ^ (v << 4)) & 0x030c30c3u;
  v = (v ^ (v << 2)) & 0x09249249u;
  return v;
}

/// The inverse of spreadBits: every third bit (from bit 0) packed.
constexpr std::uint32_t compactBits(std::uint32_t v)
{
  v &= 0x09249249u;
  v = (v ^ (v >> 2)) & 0x030c30c3u;
  v = (v ^ (v >> 4)) & 0x0300f00fu;
  v = (v ^ (v >> 8)) & 0xff0000ffu;
  v = (v ^ (v >> 16)) & 0x000003ffu;
  return v;
}

std::uint32_t morton3(std::uint32_t x, std::uint32_t y, std::uint32_t z)
{
  return spreadBits(x) | (spreadBits(y) << 1) | (spreadBits(z) << 2);
}

/// spreadBits of 0..63, for the voxel's bit inside its block (one lookup per axis).
struct SpreadTable {
  std::uint32_t values[64];
  constexpr SpreadTable() : values()
  {
    for (std::uint32_t v = 0; v < 64; ++v)
      values[v] = spreadBits(v);
  }
};
constexpr SpreadTable kSpread;

/// 64^3 voxels: a free bit and an occupied bit each. Bits are set concurrently with
/// relaxed atomics (the result is a set union, independent of the order).
struct Block {
  std::atomic<std::uint64_t> free_bits[kWordsPerBlock];
  std::atomic<std::uint64_t> occupied_bits[kWordsPerBlock];

  Block()
  {
    for (int w = 0; w < kWordsPerBlock; ++w) {
      free_bits[w].store(0, std::memory_order_relaxed);
      occupied_bits[w].store(0, std::memory_order_relaxed);
    }
  }
};

/// Sets `bit` in `word`; `shared`: other threads write the bitset too (an atomic
/// read-modify-write, a locked instruction), else a plain load and store.
void setBit(std::atomic<std::uint64_t>& word, std::uint64_t bit, bool shared)
{
  // Most voxels are crossed by many rays: test first, write once.
  const std::uint64_t old = word.load(std::memory_order_relaxed);
  if (old & bit)
    return;
  if (shared)
    word.fetch_or(bit, std::memory_order_relaxed);
  else
    word.store(old | bit, std::memory_order_relaxed);
}

/// A frame's rays in tiles of its image, the order in which they are walked. Rays of
/// neighbouring pixels cross the same voxels (a voxel of 3 mm at 0.4 m spans about
/// 3 x 3 pixels of the paper's camera): walked one after another in both directions,
/// they test bitset words still in the core's cache, and threads that take whole tiles
/// work on different parts of the bitset. The bitset, and so the map, is the same in any
/// order. An unorganized cloud (height 1, or a size that is not width x height) is cut
/// into runs of as many points as a tile holds.
class RayTiles {
public:
  // Pixels; 32 x 16 and 16 x 16 measured best (docs/performance.md, "Rays in tiles").
  static constexpr std::int64_t kTileWidth = 32;
  static constexpr std::int64_t kTileHeight = 16;

  RayTiles(std::int64_t n, std::uint32_t cloud_width, std::uint32_t cloud_height)
  {
    const bool organized =
        cloud_height > 1 && static_cast<std::int64_t>(cloud_width) * cloud_height == n;
    width_ = organized ? cloud_width : n;
    height_ = organized ? cloud_height : 1;
    tile_width_ = organized ? kTileWidth : kTileWidth * kTileHeight;
    tile_height_ = organized ? kTileHeight : 1;
    tiles_x_ = (width_ + tile_width_ - 1) / tile_width_;
    count_ = tiles_x_ * ((height_ + tile_height_ - 1) / tile_height_);
  }

  /// How many tiles the frame has.
  std::int64_t count() const { return count_; }

  /// Calls `f(i)` for the index of each point of tile `tile`, row by row.
  template <typename F>
  void forEachRay(std::int64_t tile, F&& f) const
  {
    const std::int64_t row0 = tile / tiles_x_ * tile_height_;
    const std::int64_t col0 = tile % tiles_x_ * tile_width_;
    const std::int64_t row_end = std::min(height_, row0 + tile_height_);
    const std::int64_t col_end = std::min(width_, col0 + tile_width_);
    for (std::int64_t row = row0; row < row_end; ++row)
      for (std::int64_t col = col0; col < col_end; ++col)
        f(row * width_ + col);
  }

private:
  std::int64_t width_, height_;           ///< the image (an unorganized cloud: one row)
  std::int64_t tile_width_, tile_height_; ///< a tile (an unorganized cloud: one row)
  std::int64_t tiles_x_, count_;          ///< tiles per row of tiles, and in all
};

/// One frame's ray: where it ends and whether the end is a hit.
struct Ray {
  float end[3];
  int key_end[3];
  bool valid = false; ///< false: non-finite point or end outside the octree
  bool hit = false;   ///< false: beyond max range, free space only
};

/// OctoMap counts a tree's nodes (and flags a change of its extent) in protected members
/// that only its own node creation and deletion change, without synchronisation.
/// Threads that update disjoint subtrees of one tree create and delete their nodes
/// through a tree object of their own (a counter, holding no nodes), and the counts are
/// added to the tree's afterwards.
struct TreeNodeCount : octomap::OcTree {
  static std::size_t& of(octomap::OcTree& tree)
  {
    return tree.*(&TreeNodeCount::tree_size);
  }
  static bool& changed(octomap::OcTree& tree)
  {
    return tree.*(&TreeNodeCount::size_changed);
  }
};

/// OctoMap's non-lazy update of an inner node once its children are final: pruned if
/// its 8 children are equal leaves, otherwise given the maximum of their log-odds.
void finishNode(octomap::OcTree& nodes, octomap::OcTreeNode* node)
{
  if (!nodes.pruneNode(node))
    node->updateOccupancyChildren();
}

/// Applies updates to the tree in increasing octree (Morton) order, each to a distinct
/// aligned cube of voxels (a single voxel, or all voxels of an octree node: every voxel
/// of the cube gets the same update), with OctoMap's updateNode semantics per voxel:
/// early abort at a node at a clamping bound, expansion of pruned nodes, creation of new
/// ones with log-odds 0 before the update, clamping. It keeps the path from the root to
/// the last cube; a node is finished (finishNode) when the walk leaves it for good.
/// Every node on the way is visited once per frame instead of once per voxel, and a cube
/// whose voxels would all end up equal is updated as one node, as OctoMap's pruning
/// would leave it.
///
/// The tree is updated in two levels (applyBitset): one updater opens the paths from the
/// root to the blocks' nodes, listing the nodes it leaves instead of finishing them
/// (`deferred`); then an updater per thread walks whole blocks, each below its block's
/// node (startAt), creating nodes through the thread's counter; the listed nodes are
/// finished last.
class OrderedTreeUpdater {
public:
  /// `tree`: the tree updated (its clamping bounds and update rule, both read only);
  /// `nodes`: the tree object that creates, expands and prunes nodes (`tree` itself, or
  /// a thread's counter, see TreeNodeCount); `deferred`: where the nodes the walk leaves
  /// are listed, children before parents, instead of finished (nullptr: finished).
  OrderedTreeUpdater(const octomap::OcTree& tree, octomap::OcTree& nodes,
                     std::vector<octomap::OcTreeNode*>* deferred = nullptr)
      : tree_(tree), nodes_tree_(nodes), deferred_(deferred),
        clamp_min_(tree.getClampingThresMinLog()),
        clamp_max_(tree.getClampingThresMaxLog())
  {
  }

  /// Works below `node`, the node at `depth` that holds the cubes applied until the next
  /// call; `created`: it was made in this frame (its log-odds are a new node's 0).
  void startAt(octomap::OcTreeNode* node, int depth, bool created)
  {
    nodes_[depth] = node;
    created_[depth] = created;
    base_ = depth;
    top_ = -1;
  }

  /// Updates the cube of the node at `target_depth` (16: one voxel) holding `key`.
  void apply(const octomap::OcTreeKey& key, int target_depth, float log_odds_update)
  {
    if (!descend(key, target_depth, &log_odds_update))
      return;
    octomap::OcTreeNode* node = nodes_[top_];
    if (created_[top_])
      tree_.updateNodeLogOdds(node, log_odds_update); // new: 0 + update, clamped
    else if (!nodes_tree_.nodeHasChildren(node)) {
      if (!unchanged(node->getLogOdds(), log_odds_update))
        tree_.updateNodeLogOdds(node, log_odds_update);
    } else {
      updateSubtree(node, log_odds_update);
    }
  }

  /// The node at `depth` holding `key`, made where missing, without an update; pruned
  /// nodes on the way are expanded whatever the updates below them will be (finishing
  /// prunes them again where nothing changed). `created`: it was made now. With the
  /// tree still empty, `key` must be that of the frame's first updated voxel: OctoMap
  /// makes the root with the path to a voxel.
  octomap::OcTreeNode* open(const octomap::OcTreeKey& key, int depth, bool& created)
  {
    descend(key, depth, nullptr);
    created = created_[top_];
    return nodes_[top_];
  }

  /// Finishes (or lists) the open path up to the node of startAt, or the root.
  void finish()
  {
    for (int d = top_ - 1; d >= base_; --d)
      leave(nodes_[d]);
    top_ = -1;
  }

private:
  /// Moves the open path to the node at `target_depth` holding `key` (top_), making
  /// missing nodes. A pruned node on the way is expanded, unless `update` is given and
  /// leaves it unchanged (OctoMap's early abort, for every voxel of the cube): then the
  /// path ends there and the result is false.
  bool descend(const octomap::OcTreeKey& key, int target_depth, const float* update)
  {
    int depth;
    if (top_ < 0) {
      if (base_ == 0) {
        if (!nodes_tree_.getRoot()) {
          // The root can only be made by the tree: a lazy update by 0 creates the root
          // and the path to this key's voxel, a leaf at log-odds 0 (what a new node
          // starts from), and changes nothing else; the real update follows.
          nodes_tree_.updateNode(key, 0.0f, /*lazy_eval=*/true);
        }
        nodes_[0] = nodes_tree_.getRoot();
        created_[0] = false;
      }
      depth = base_;
    } else {
      // Cubes come in increasing octree order: the deepest node shared with the last
      // one is above the highest differing key bit.
      const unsigned diff = static_cast<unsigned>(key[0] ^ key_[0]) |
                            static_cast<unsigned>(key[1] ^ key_[1]) |
                            static_cast<unsigned>(key[2] ^ key_[2]);
      const int level = 31 - __builtin_clz(diff); // cubes are distinct: diff != 0
      const int shared = kTreeDepth - 1 - level;
      for (int d = top_ - 1; d > shared; --d)
        leave(nodes_[d]);
      depth = std::min(top_, shared);
    }
    key_ = key;

    octomap::OcTreeNode* node = nodes_[depth];
    while (depth < target_depth) {
      const unsigned pos = octomap::computeChildIdx(key, kTreeDepth - 1 - depth);
      if (!nodes_tree_.nodeChildExists(node, pos)) {
        if (!nodes_tree_.nodeHasChildren(node) && !created_[depth]) {
          // A pruned node: OctoMap's search finds it, so its early abort applies here.
          if (update && unchanged(node->getLogOdds(), *update)) {
            top_ = depth;
            return false;
          }
          nodes_tree_.expandNode(node);
          created_[depth + 1] = false;
        } else {
          nodes_tree_.createNodeChild(node, pos);
          created_[depth + 1] = true;
        }
      } else {
        created_[depth + 1] = false;
      }
      node = nodes_tree_.getNodeChild(node, pos);
      nodes_[++depth] = node;
    }
    top_ = depth;
    return true;
  }

  void leave(octomap::OcTreeNode* node)
  {
    if (deferred_)
      deferred_->push_back(node);
    else
      finishNode(nodes_tree_, node);
  }

  /// OctoMap's early abort in updateNode: a node at a clamping bound that the update
  /// would push further is left as it is.
  bool unchanged(float log_odds, float update) const
  {
    return (update >= 0 && log_odds >= clamp_max_) ||
           (update <= 0 && log_odds <= clamp_min_);
  }

  /// Every voxel under `node` (an inner node) gets the update: existing leaves (pruned
  /// or not) in place, unknown parts as new leaves as large as the missing child.
  void updateSubtree(octomap::OcTreeNode* node, float log_odds_update)
  {
    for (unsigned i = 0; i < 8; ++i) {
      if (nodes_tree_.nodeChildExists(node, i)) {
        octomap::OcTreeNode* child = nodes_tree_.getNodeChild(node, i);
        if (nodes_tree_.nodeHasChildren(child))
          updateSubtree(child, log_odds_update);
        else if (!unchanged(child->getLogOdds(), log_odds_update))
          tree_.updateNodeLogOdds(child, log_odds_update);
      } else {
        tree_.updateNodeLogOdds(nodes_tree_.createNodeChild(node, i), log_odds_update);
      }
    }
    finishNode(nodes_tree_, node);
  }

  const octomap::OcTree& tree_;
  octomap::OcTree& nodes_tree_;
  std::vector<octomap::OcTreeNode*>* const deferred_;
  const float clamp_min_;
  const float clamp_max_;
  octomap::OcTreeNode* nodes_[kTreeDepth + 1] = {};
  bool created_[kTreeDepth + 1] = {};
  octomap::OcTreeKey key_;
  int base_ = 0; ///< depth of the node the path starts from
  int top_ = -1; ///< depth of the last node of the open path; -1: none
};

/// The key of voxel `m` (its Morton index in the block) of the block whose first voxel
/// has key `first`.
octomap::OcTreeKey voxelKey(const octomap::OcTreeKey& first, std::uint32_t m)
{
  return octomap::OcTreeKey(
      static_cast<octomap::key_type>(first[0] + compactBits(m)),
      static_cast<octomap::key_type>(first[1] + compactBits(m >> 1)),
      static_cast<octomap::key_type>(first[2] + compactBits(m >> 2)));
}

/// Feeds one block of the bitset to the updater in octree order, as the largest
/// uniform cubes: an octree node whose voxels are all hit (or all missed and none hit)
/// is one update; below that, 2x2x2 cubes (one byte of a word), then single voxels.
class BlockWalker {
public:
  BlockWalker(OrderedTreeUpdater& updater, float hit, float miss)
      : updater_(updater), hit_(hit), miss_(miss)
  {
  }

  /// `free_bits` / `occupied_bits`: the block's words; `first`: key of its first voxel.
  void walk(const std::uint64_t* free_bits, const std::uint64_t* occupied_bits,
            const octomap::OcTreeKey& first)
  {
    free_ = free_bits;
    occupied_ = occupied_bits;
    first_ = first;
    walkWords(0, kWordsPerBlock, kTreeDepth - kBlockShift);
  }

private:
  static constexpr std::uint64_t kAll = ~std::uint64_t{0};

  /// Words [first, first + count): the voxels of one octree node at `depth`.
  void walkWords(int first, int count, int depth)
  {
    bool empty = true, all_hit = true, all_missed = true;
    for (int w = first; w < first + count && (empty || all_hit || all_missed); ++w) {
      const std::uint64_t f = free_[w], o = occupied_[w];
      empty = empty && (f | o) == 0;
      all_hit = all_hit && o == kAll;
      all_missed = all_missed && f == kAll && o == 0;
    }
    if (empty)
      return;
    if (all_hit || all_missed) {
      cube(static_cast<std::uint32_t>(first) << 6, depth, all_hit ? hit_ : miss_);
      return;
    }
    if (count == 1) {
      walkBytes(first);
      return;
    }
    const int part = count / 8;
    for (int i = 0; i < 8; ++i)
      walkWords(first + i * part, part, depth + 1);
  }

  /// One mixed word (a 4x4x4 node): its 2x2x2 nodes (bytes), then voxels.
  void walkBytes(int w)
  {
    for (int j = 0; j < 8; ++j) {
      const unsigned f = static_cast<unsigned>(free_[w] >> (8 * j)) & 0xffu;
      const unsigned o = static_cast<unsigned>(occupied_[w] >> (8 * j)) & 0xffu;
      if (!(f | o))
        continue;
      const std::uint32_t m0 = (static_cast<std::uint32_t>(w) << 6) | (8u * j);
      if (o == 0xffu || (f == 0xffu && o == 0)) {
        cube(m0, kTreeDepth - 1, o ? hit_ : miss_);
        continue;
      }
      for (unsigned bits = f | o; bits; bits &= bits - 1) {
        const unsigned b = static_cast<unsigned>(__builtin_ctz(bits));
        cube(m0 | b, kTreeDepth, (o >> b) & 1u ? hit_ : miss_);
      }
    }
  }

  /// The cube whose first voxel has index m in the block.
  void cube(std::uint32_t m, int depth, float update)
  {
    updater_.apply(voxelKey(first_, m), depth, update);
    ++updates_;
  }

public:
  std::size_t updates() const { return updates_; }

private:
  std::size_t updates_ = 0;
  OrderedTreeUpdater& updater_;
  const float hit_;
  const float miss_;
  const std::uint64_t* free_ = nullptr;
  const std::uint64_t* occupied_ = nullptr;
  octomap::OcTreeKey first_;
};

std::string rangeMessage(const char* field, double value, const char* expected)
{
  std::ostringstream s;
  s << "OccupancyMap::Config: " << field << " = " << value << " must be " << expected;
  return s.str();
}

bool inOpen(double v, double lo, double hi)
{
  return v > lo && v < hi;
}

} // namespace

/// Per-frame buffers, kept between frames so that an insertion allocates (almost)
/// nothing: the rays, and the blocks of the bitset with a table from block coordinates
/// (over the frame's bounding box of keys) to blocks.
namespace detail {

struct OccupancyMapScratch {
  struct UsedBlock {
    std::uint32_t morton; ///< of the block coordinates: the blocks' octree order
    int coords[3];        ///< block coordinates (key >> 6)
    std::size_t slot;     ///< index in the table
    Block* block;
    /// Its node in the tree, once applyBitset opened the path to it (null: no voxel
    /// marked), and whether that node was made in this frame.
    octomap::OcTreeNode* node = nullptr;
    bool node_created = false;
    /// Its 8^3-voxel bricks (bit b: the brick at Morton index b in the block) that
    /// hold a marked voxel: OccupancyMap::getChangedBricks.
    std::uint64_t changed[8] = {0, 0, 0, 0, 0, 0, 0, 0};

    /// The key of the block's first voxel.
    octomap::OcTreeKey firstKey() const
    {
      return octomap::OcTreeKey(static_cast<octomap::key_type>(coords[0] << kBlockShift),
                                static_cast<octomap::key_type>(coords[1] << kBlockShift),
                                static_cast<octomap::key_type>(coords[2] << kBlockShift));
    }
  };

  std::vector<Ray> rays;
  RegionHorizon horizon; ///< with an update region: where the frame's rays may enter it
  /// What a thread needs to update the tree from whole blocks (applyBitset).
  struct BlockUpdateBuffers {
    std::vector<std::uint64_t> free_words, occupied_words; ///< one block, while walked
    std::unique_ptr<octomap::OcTree> counter;              ///< see TreeNodeCount
  };
  std::vector<BlockUpdateBuffers> update_buffers; ///< per thread
  std::vector<octomap::OcTreeNode*> deferred;     ///< nodes above the blocks, to finish
  std::vector<std::unique_ptr<Block>> blocks;     ///< all blocks ever made
  std::vector<Block*> spare;                      ///< zeroed blocks not in use
  std::vector<UsedBlock> used;
  /// The last insert's changed bricks (OccupancyMap::getChangedBricks).
  std::vector<std::array<int, 3>> changed_bricks;
  std::unique_ptr<std::atomic<Block*>[]> table;
  std::size_t table_capacity = 0;
  int table_lo[3] = {0, 0, 0}; ///< block coordinates of the table's first slot
  int table_size[3] = {0, 0, 0};
  std::mutex mutex;
  /// Keys that fell outside the table (per thread); never seen, kept for safety.
  std::vector<std::vector<std::uint64_t>> overflow;

  void prepareTable(const int key_lo[3], const int key_hi[3])
  {
    std::size_t n = 1;
    for (int a = 0; a < 3; ++a) {
      table_lo[a] = key_lo[a] >> kBlockShift;
      table_size[a] = (key_hi[a] >> kBlockShift) - table_lo[a] + 1;
      n *= static_cast<std::size_t>(table_size[a]);
    }
    if (n > table_capacity) {
      table.reset(new std::atomic<Block*>[n]);
      for (std::size_t i = 0; i < n; ++i)
        table[i].store(nullptr, std::memory_order_relaxed);
      table_capacity = n;
    }
  }

  /// The block at block coordinates b (inside the table), made on first use.
  Block* blockAt(const int b[3])
  {
    const std::size_t slot =
        (static_cast<std::size_t>(b[0] - table_lo[0]) * table_size[1] +
         static_cast<std::size_t>(b[1] - table_lo[1])) *
            table_size[2] +
        static_cast<std::size_t>(b[2] - table_lo[2]);
    Block* block = table[slot].load(std::memory_order_acquire);
    if (block)
      return block;
    std::lock_guard<std::mutex> lock(mutex);
    block = table[slot].load(std::memory_order_relaxed);
    if (block)
      return block;
    if (spare.empty()) {
      blocks.push_back(std::make_unique<Block>());
      spare.push_back(blocks.back().get());
    }
    block = spare.back();
    spare.pop_back();
    used.push_back(
        {morton3(static_cast<std::uint32_t>(b[0]), static_cast<std::uint32_t>(b[1]),
                 static_cast<std::uint32_t>(b[2])),
         {b[0], b[1], b[2]},
         slot,
         block});
    table[slot].store(block, std::memory_order_release);
    return block;
  }
};

} // namespace detail

namespace {

using Scratch = detail::OccupancyMapScratch;

/// A free voxel outside the frame's bounding box of keys (padded by one voxel), which
/// the DDA cannot leave: kept in a list all the same (hits are always in the box).
/// Keys outside the octree (OctoMap would wrap them) are dropped. Out of line: the
/// walk's state stays in registers.
[[gnu::noinline]] void keepOutside(std::vector<std::uint64_t>& overflow, int kx, int ky,
                                   int kz)
{
  const int limit = VoxelLattice::kKeyLimit;
  if (kx < 0 || ky < 0 || kz < 0 || kx >= limit || ky >= limit || kz >= limit)
    return;
  overflow.push_back((static_cast<std::uint64_t>(kx) << 32) |
                     (static_cast<std::uint64_t>(ky) << 16) |
                     static_cast<std::uint64_t>(kz));
}

/// The block at block coordinates b, or nullptr outside the frame's table. Out of line
/// (rays are coherent: the block rarely changes along one).
[[gnu::noinline]] Block* blockOrNull(Scratch& scratch, int bx, int by, int bz)
{
  const int b[3] = {bx, by, bz};
  for (int a = 0; a < 3; ++a)
    if (b[a] < scratch.table_lo[a] || b[a] >= scratch.table_lo[a] + scratch.table_size[a])
      return nullptr;
  return scratch.blockAt(b);
}

/// One ray's writer into the bitset. Along the ray it keeps the current block and the
/// voxel's bit index inside it, and moves that index by one voxel per step (a Morton
/// increment) instead of recomputing it. Made afresh for every ray, as a local of
/// markRay, so that the compiler keeps its state in registers. `kShared`: other threads
/// write the same bitset at the same time.
template <bool kShared>
class RayBitsetWriter {
public:
  RayBitsetWriter(Scratch& scratch, std::vector<std::uint64_t>& overflow)
      : scratch_(scratch), overflow_(overflow)
  {
  }

  /// A ray's first voxel (marked free); `step` is the ray's direction of travel per axis.
  void begin(int kx, int ky, int kz, const int step[3])
  {
    up_ = 0;
    for (int a = 0; a < 3; ++a)
      if (step[a] > 0)
        up_ |= kAxisBits << a;
    locate(kx, ky, kz);
    markFree(kx, ky, kz);
  }

  /// The ray's next voxel, one step along `axis` from the last one (marked free).
  void next(int axis, int kx, int ky, int kz, double /*t_entry*/)
  {
    const std::uint32_t mask = kAxisBits << axis;
    const std::uint32_t local = morton_ & mask;
    const bool up = (up_ & mask) != 0;
    if (!block_ || local == (up ? mask : 0u)) {
      locate(kx, ky, kz); // into the next block
    } else if (up) {
      morton_ = (((morton_ | ~mask) + 1u) & mask) | (morton_ & ~mask);
    } else {
      morton_ = ((local - 1u) & mask) | (morton_ & ~mask);
    }
    markFree(kx, ky, kz);
  }

  /// The ray's voxel after a jump (traverseRayInRegion): located, not marked.
  void resume(int kx, int ky, int kz) { locate(kx, ky, kz); }

  /// An end voxel (marked occupied).
  void markOccupied(int kx, int ky, int kz)
  {
    locate(kx, ky, kz);
    if (block_)
      setBit(block_->occupied_bits[morton_ >> 6], std::uint64_t{1} << (morton_ & 63u),
             kShared);
  }

private:
  /// The x bits of a voxel's 18-bit index in its block (y, z: shifted by 1, 2).
  static constexpr std::uint32_t kAxisBits = 0x9249u;

  void markFree(int kx, int ky, int kz)
  {
    if (block_)
      setBit(block_->free_bits[morton_ >> 6], std::uint64_t{1} << (morton_ & 63u),
             kShared);
    else
      keepOutside(overflow_, kx, ky, kz);
  }

  /// Block and bit index of key (kx, ky, kz); block_ null if outside the table.
  void locate(int kx, int ky, int kz)
  {
    const int bx = kx >> kBlockShift, by = ky >> kBlockShift, bz = kz >> kBlockShift;
    if (!block_ || bx != block_x_ || by != block_y_ || bz != block_z_) {
      block_ = blockOrNull(scratch_, bx, by, bz);
      block_x_ = bx;
      block_y_ = by;
      block_z_ = bz;
    }
    morton_ = kSpread.values[kx & kBlockMask] | (kSpread.values[ky & kBlockMask] << 1) |
              (kSpread.values[kz & kBlockMask] << 2);
  }

  Scratch& scratch_;
  std::vector<std::uint64_t>& overflow_;
  Block* block_ = nullptr;
  int block_x_ = 0, block_y_ = 0, block_z_ = 0;
  std::uint32_t morton_ = 0;
  std::uint32_t up_ = 0; ///< the axis bits (kAxisBits << axis) of the axes walked up
};

/// One ray into the bitset: its voxels free, its end occupied when it is a hit. Every
/// call inside is inlined (flatten), so the writer's state lives in registers.
template <bool kShared>
[[gnu::flatten]] void markRay(const float origin[3], const int key_origin[3],
                              const Ray& ray, const VoxelLattice& lattice,
                              Scratch& scratch, std::vector<std::uint64_t>& overflow)
{
  RayBitsetWriter<kShared> writer(scratch, overflow);
  traverseRay(origin, ray.end, key_origin, ray.key_end, lattice, writer);
  if (ray.hit)
    writer.markOccupied(ray.key_end[0], ray.key_end[1], ray.key_end[2]);
}

/// markRay through an update region for `count` (up to kRaysTogether) neighbouring
/// rays: their first jumps from the camera advanced together (startRaysInRegion), then
/// each walked. Only the voxels in the region are certain to be marked.
template <bool kShared>
[[gnu::flatten]] void
markRaysInRegion(const float origin[3], const int key_origin[3], const Ray* const rays[],
                 int count, const VoxelLattice& lattice, const UpdateRegion& region,
                 Scratch& scratch, std::vector<std::uint64_t>& overflow)
{
  namespace rt = ray_traversal;
  const float* ends[rt::kRaysTogether];
  const int* key_ends[rt::kRaysTogether];
  double clear_until[rt::kRaysTogether];
  for (int i = 0; i < count; ++i) {
    ends[i] = rays[i]->end;
    key_ends[i] = rays[i]->key_end;
    clear_until[i] = scratch.horizon.clearDistance(rays[i]->end);
  }
  rt::RegionRayStart starts[rt::kRaysTogether];
  rt::startRaysInRegion(origin, ends, key_origin, key_ends, clear_until, count, lattice,
                        region, starts);
  for (int i = 0; i < count; ++i) {
    const Ray& ray = *rays[i];
    RayBitsetWriter<kShared> writer(scratch, overflow);
    rt::walkRayInRegion(origin, key_origin, ray.key_end, lattice, region, starts[i],
                        writer);
    if (ray.hit)
      writer.markOccupied(ray.key_end[0], ray.key_end[1], ray.key_end[2]);
  }
}

/// The Morton index of the block's first marked voxel; false: none (a ray can reach a
/// block after a jump and mark nothing in it).
bool firstMarkedVoxel(const Block& block, std::uint32_t& m)
{
  for (int w = 0; w < kWordsPerBlock; ++w) {
    const std::uint64_t bits = block.free_bits[w].load(std::memory_order_relaxed) |
                               block.occupied_bits[w].load(std::memory_order_relaxed);
    if (bits) {
      m = (static_cast<std::uint32_t>(w) << 6) |
          static_cast<std::uint32_t>(__builtin_ctzll(bits));
      return true;
    }
  }
  return false;
}

/// Appends the block's changed bricks (UsedBlock::changed) as brick coordinates.
void listChangedBricks(const Scratch::UsedBlock& used,
                       std::vector<std::array<int, 3>>& out)
{
  constexpr int kBrickShift = OccupancyMap::kChangedBrickShift;
  for (int word = 0; word < 8; ++word)
    for (std::uint64_t bits = used.changed[word]; bits != 0; bits &= bits - 1) {
      // The brick's first voxel: Morton index (brick's index) * 8^3 in the block.
      const auto b = static_cast<std::uint32_t>(word * 64 + __builtin_ctzll(bits));
      const octomap::OcTreeKey k = voxelKey(used.firstKey(), b << (3 * kBrickShift));
      out.push_back({k[0] >> kBrickShift, k[1] >> kBrickShift, k[2] >> kBrickShift});
    }
}

/// Step 3 of insert: the frame's bitset into the tree, and the used blocks (sorted in
/// octree order) cleared for the next frame. A voxel both free and occupied is occupied
/// only. The blocks are disjoint subtrees: the paths from the root to their nodes are
/// opened on one thread, the blocks then walked on `threads` threads (one at a time:
/// their work differs by orders of magnitude), and the nodes above them finished last,
/// children before parents. The tree is the same for any thread count.
void applyBitset(octomap::OcTree& tree, Scratch& scratch, int threads,
                 OccupancyMap::InsertStats& stats)
{
  constexpr int kBlockDepth = kTreeDepth - kBlockShift;
  const auto blocks = static_cast<std::int64_t>(scratch.used.size());
  scratch.deferred.clear();
  OrderedTreeUpdater opener(tree, tree, &scratch.deferred);
  for (Scratch::UsedBlock& used : scratch.used) {
    std::uint32_t first;
    if (firstMarkedVoxel(*used.block, first))
      used.node =
          opener.open(voxelKey(used.firstKey(), first), kBlockDepth, used.node_created);
  }
  opener.finish();

  threads = static_cast<int>(
      std::max<std::int64_t>(1, std::min<std::int64_t>(threads, blocks)));
  if (scratch.update_buffers.size() < static_cast<std::size_t>(threads))
    scratch.update_buffers.resize(static_cast<std::size_t>(threads));
  for (Scratch::BlockUpdateBuffers& buffers : scratch.update_buffers)
    if (!buffers.counter) {
      buffers.free_words.resize(kWordsPerBlock);
      buffers.occupied_words.resize(kWordsPerBlock);
      buffers.counter = std::make_unique<octomap::OcTree>(tree.getResolution());
    }
  const float hit = tree.getProbHitLog();
  const float miss = tree.getProbMissLog();
  std::size_t occupied_voxels = 0, free_voxels = 0, tree_updates = 0, nodes_added = 0;
  bool nodes_changed = false;
  std::exception_ptr error;
#pragma omp parallel num_threads(threads)                                                 \
    reduction(+ : occupied_voxels, free_voxels, tree_updates)
  {
    Scratch::BlockUpdateBuffers& buffers =
        scratch.update_buffers[static_cast<std::size_t>(omp_get_thread_num())];
    std::uint64_t* const free_words = buffers.free_words.data();
    std::uint64_t* const occupied_words = buffers.occupied_words.data();
    octomap::OcTree& counter = *buffers.counter;
    const std::size_t counted_before = counter.size();
    TreeNodeCount::changed(counter) = false;
    OrderedTreeUpdater updater(tree, counter);
    BlockWalker walker(updater, hit, miss);
#pragma omp for schedule(dynamic, 1)
    for (std::int64_t i = 0; i < blocks; ++i) {
      Scratch::UsedBlock& used = scratch.used[static_cast<std::size_t>(i)];
      if (!used.node)
        continue;
      // The block's bits, copied out and cleared for the next frame.
      Block& block = *used.block;
      for (int w = 0; w < kWordsPerBlock; ++w) {
        const std::uint64_t f = block.free_bits[w].load(std::memory_order_relaxed);
        const std::uint64_t o = block.occupied_bits[w].load(std::memory_order_relaxed);
        free_words[w] = f;
        occupied_words[w] = o;
        if (f | o) {
          block.free_bits[w].store(0, std::memory_order_relaxed);
          block.occupied_bits[w].store(0, std::memory_order_relaxed);
          occupied_voxels += static_cast<std::size_t>(__builtin_popcountll(o));
          free_voxels += static_cast<std::size_t>(__builtin_popcountll(f & ~o));
          // Eight words (4^3 voxels each, in Morton order) make a brick of 8^3.
          used.changed[w >> 9] |= std::uint64_t{1} << ((w >> 3) & 63);
        }
      }
      try {
        updater.startAt(used.node, kBlockDepth, used.node_created);
        walker.walk(free_words, occupied_words, used.firstKey());
        updater.finish();
      } catch (...) {
        // std::bad_alloc: the other blocks go on and the nodes above them are finished;
        // the first error is thrown then.
#pragma omp critical(plantnbv_occupancy_error)
        if (!error)
          error = std::current_exception();
      }
    }
    tree_updates += walker.updates();
#pragma omp critical(plantnbv_occupancy_counts)
    {
      nodes_added += counter.size() - counted_before; // modulo 2^64: nodes pruned count
      nodes_changed = nodes_changed || TreeNodeCount::changed(counter);
    }
  }
  TreeNodeCount::of(tree) += nodes_added;
  if (nodes_changed)
    TreeNodeCount::changed(tree) = true;
  stats.occupied_voxels += occupied_voxels;
  stats.free_voxels += free_voxels;
  stats.tree_updates += tree_updates;
  scratch.changed_bricks.clear();
  for (const Scratch::UsedBlock& used : scratch.used) {
    scratch.table[used.slot].store(nullptr, std::memory_order_relaxed);
    scratch.spare.push_back(used.block);
    listChangedBricks(used, scratch.changed_bricks);
  }
  scratch.used.clear();
  for (octomap::OcTreeNode* node : scratch.deferred)
    finishNode(tree, node);
  if (error)
    std::rethrow_exception(error);
}

} // namespace

void OccupancyMap::Config::validate() const
{
  if (!(resolution_m >= kMinMapResolutionM && resolution_m <= kMaxMapResolutionM)) {
    std::ostringstream range;
    range << "in [" << kMinMapResolutionM << ", " << kMaxMapResolutionM << "] (metres)";
    throw InvalidArgumentError(
        rangeMessage("resolution_m", resolution_m, range.str().c_str()));
  }
  if (!inOpen(prob_hit, 0.5, 1.0))
    throw InvalidArgumentError(rangeMessage("prob_hit", prob_hit, "in (0.5, 1)"));
  if (!inOpen(prob_miss, 0.0, 0.5))
    throw InvalidArgumentError(rangeMessage("prob_miss", prob_miss, "in (0, 0.5)"));
  if (!inOpen(clamp_min, 0.0, 0.5))
    throw InvalidArgumentError(rangeMessage("clamp_min", clamp_min, "in (0, 0.5)"));
  if (!inOpen(clamp_max, 0.5, 1.0))
    throw InvalidArgumentError(rangeMessage("clamp_max", clamp_max, "in (0.5, 1)"));
  if (!inOpen(occupancy_threshold, 0.0, 1.0))
    throw InvalidArgumentError(
        rangeMessage("occupancy_threshold", occupancy_threshold, "in (0, 1)"));
  if (!(std::isfinite(max_range_m) && max_range_m > 0.0))
    throw InvalidArgumentError(
        rangeMessage("max_range_m", max_range_m, "finite and > 0 (metres)"));
  if (max_range_m > 8192.0 * resolution_m) {
    std::ostringstream s;
    s << "OccupancyMap::Config: max_range_m = " << max_range_m
      << " must be at most 8192 voxels (" << 8192.0 * resolution_m
      << " m at resolution_m = " << resolution_m << ")";
    throw InvalidArgumentError(s.str());
  }
}

OccupancyMap::OccupancyMap() : OccupancyMap(Config()) {}

OccupancyMap::OccupancyMap(const Config& config) : config_(config)
{
  config_.validate();
  tree_ = std::make_unique<octomap::OcTree>(config_.resolution_m);
  tree_->setProbHit(config_.prob_hit);
  tree_->setProbMiss(config_.prob_miss);
  tree_->setClampingThresMin(config_.clamp_min);
  tree_->setClampingThresMax(config_.clamp_max);
  tree_->setOccupancyThres(config_.occupancy_threshold);
  scratch_ = std::make_unique<detail::OccupancyMapScratch>();
}

OccupancyMap::~OccupancyMap() = default;

void OccupancyMap::setNumberOfThreads(int threads)
{
  if (threads < 0) {
    std::ostringstream s;
    s << "OccupancyMap::setNumberOfThreads: " << threads
      << " must be >= 0 (0: OpenMP's default)";
    throw InvalidArgumentError(s.str());
  }
  threads_ = threads;
}

void OccupancyMap::setUpdateRegion(std::shared_ptr<const UpdateRegion> region)
{
  if (region && region->resolution() != config_.resolution_m) {
    std::ostringstream s;
    s << "OccupancyMap::setUpdateRegion: the region's resolution " << region->resolution()
      << " m is not the map's " << config_.resolution_m << " m";
    throw InvalidArgumentError(s.str());
  }
  region_ = std::move(region);
}

void OccupancyMap::insert(const CloudXYZ& points_W,
                          const Eigen::Vector3d& sensor_origin_W)
{
  insertImpl(points_W, sensor_origin_W);
}

void OccupancyMap::insert(const CloudXYZL& points_W,
                          const Eigen::Vector3d& sensor_origin_W)
{
  insertImpl(points_W, sensor_origin_W);
}

template <typename PointT>
void OccupancyMap::insertImpl(const pcl::PointCloud<PointT>& points_W,
                              const Eigen::Vector3d& sensor_origin_W)
{
  const Stopwatch start;
  const VoxelLattice lattice(tree_->getResolution());
  const double max_range = config_.max_range_m;
  // OctoMap works with the origin in single precision (point3d).
  const float origin[3] = {static_cast<float>(sensor_origin_W.x()),
                           static_cast<float>(sensor_origin_W.y()),
                           static_cast<float>(sensor_origin_W.z())};
  int key_origin[3];
  if (!sensor_origin_W.allFinite() || !lattice.coordToKey(origin, key_origin)) {
    std::ostringstream s;
    s << "OccupancyMap::insert: sensor origin (" << sensor_origin_W.x() << ", "
      << sensor_origin_W.y() << ", " << sensor_origin_W.z()
      << ") is not finite or lies outside the octree (+-"
      << VoxelLattice::kKeyOffset * lattice.resolution() << " m)";
    throw InvalidArgumentError(s.str());
  }

  ++revision_; // before the tree changes (also if this insertion throws half-way)
  InsertStats stats;
  stats.points = points_W.size();
  const auto n = static_cast<std::int64_t>(points_W.size());
  // Small frames run on one thread: starting threads would cost more than it saves.
  const int requested = threads_ > 0 ? threads_ : omp_get_max_threads();
  const int threads = static_cast<int>(
      std::min<std::int64_t>(requested, std::max<std::int64_t>(1, n / 4096)));
  Scratch& scratch = *scratch_;
  scratch.rays.resize(points_W.size());
  Ray* const rays = scratch.rays.data();

  // 1. Each point's ray end and keys (OctoMap's computeUpdate), and the bounding box of
  //    all keys.
  int key_lo[3] = {key_origin[0], key_origin[1], key_origin[2]};
  int key_hi[3] = {key_origin[0], key_origin[1], key_origin[2]};
  std::size_t non_finite = 0, beyond_range = 0, outside_map = 0, hits_outside_region = 0;
  const UpdateRegion* const region = region_.get();
#pragma omp parallel num_threads(threads) reduction(+ : non_finite, beyond_range,        \
                                                       outside_map, hits_outside_region)
  {
    int lo[3] = {key_lo[0], key_lo[1], key_lo[2]};
    int hi[3] = {key_hi[0], key_hi[1], key_hi[2]};
#pragma omp for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) {
      const PointT& point = points_W[static_cast<std::size_t>(i)];
      Ray& ray = rays[i];
      ray.valid = false;
      if (!(std::isfinite(point.x) && std::isfinite(point.y) && std::isfinite(point.z))) {
        ++non_finite; // NaNs crash OctoMap's computeRayKeys: they never reach it
        continue;
      }
      const float p[3] = {point.x, point.y, point.z};
      const float d[3] = {p[0] - origin[0], p[1] - origin[1], p[2] - origin[2]};
      const double norm =
          std::sqrt(static_cast<double>(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
      if (norm <= max_range) {
        std::copy(p, p + 3, ray.end);
        ray.hit = true;
      } else {
        // (p - origin).normalized() * (float)maxrange + origin, in float as OctoMap.
        ++beyond_range;
        const float len = static_cast<float>(norm);
        const float range = static_cast<float>(max_range);
        for (int a = 0; a < 3; ++a)
          ray.end[a] = origin[a] + (d[a] / len) * range;
        ray.hit = false;
      }
      if (!lattice.coordToKey(ray.end, ray.key_end)) {
        ++outside_map;
        continue;
      }
      ray.valid = true;
      if (region && ray.hit &&
          !region->containsKey(ray.key_end[0], ray.key_end[1], ray.key_end[2]))
        ++hits_outside_region;
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], ray.key_end[a]);
        hi[a] = std::max(hi[a], ray.key_end[a]);
      }
    }
#pragma omp critical(plantnbv_occupancy_bounds)
    for (int a = 0; a < 3; ++a) {
      key_lo[a] = std::min(key_lo[a], lo[a]);
      key_hi[a] = std::max(key_hi[a], hi[a]);
    }
  }
  stats.non_finite = non_finite;
  stats.beyond_range = beyond_range;
  stats.outside_map = outside_map;
  stats.hits_outside_region = hits_outside_region;
  stats.rays_ms = start.ms();
  const Stopwatch traverse_start;

  // 2. The rays' voxels into the bitset, in parallel. A ray's voxels stay within one
  //    voxel of the box of its end voxels (rounding); the table covers that.
  for (int a = 0; a < 3; ++a) {
    key_lo[a] = std::max(key_lo[a] - 1, 0);
    key_hi[a] = std::min(key_hi[a] + 1, VoxelLattice::kKeyLimit - 1);
  }
  scratch.prepareTable(key_lo, key_hi);
  scratch.used.clear();
  if (region) {
    // Where the rays may first enter the region, around their mean direction (from at
    // most about 4096 of them, in order: the same for any thread count).
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    const std::int64_t stride = std::max<std::int64_t>(1, n / 4096);
    for (std::int64_t i = 0; i < n; i += stride)
      if (rays[i].valid) {
        const Eigen::Vector3d d(double(rays[i].end[0]) - origin[0],
                                double(rays[i].end[1]) - origin[1],
                                double(rays[i].end[2]) - origin[2]);
        const double norm = d.norm();
        if (norm > 0.0)
          axis += d / norm;
      }
    // No ray is longer than max_range (up to its float rounding).
    scratch.horizon.compute(*region, origin, axis,
                            max_range + 2.0 * lattice.resolution());
  }
  scratch.overflow.resize(static_cast<std::size_t>(threads));
  const RayTiles tiles(n, points_W.width, points_W.height);
#pragma omp parallel num_threads(threads)
  {
    std::vector<std::uint64_t>& overflow =
        scratch.overflow[static_cast<std::size_t>(omp_get_thread_num())];
    overflow.clear();
    const bool shared = threads > 1;
    // Eight tiles at a time (a strip of 256 x 16 pixels of the paper's camera): one tile
    // at a time, the threads walked neighbouring tiles at once and were 7-9 % slower.
    // With a region, rays go in groups of neighbours (markRaysInRegion).
    const Ray* group[ray_traversal::kRaysTogether];
    int grouped = 0;
    const auto markGroup = [&] {
      if (shared)
        markRaysInRegion<true>(origin, key_origin, group, grouped, lattice, *region,
                               scratch, overflow);
      else
        markRaysInRegion<false>(origin, key_origin, group, grouped, lattice, *region,
                                scratch, overflow);
      grouped = 0;
    };
#pragma omp for schedule(dynamic, 8)
    for (std::int64_t tile = 0; tile < tiles.count(); ++tile) {
      tiles.forEachRay(tile, [&](std::int64_t i) {
        const Ray& ray = rays[i];
        if (!ray.valid)
          return;
        if (region) {
          group[grouped++] = &ray;
          if (grouped == ray_traversal::kRaysTogether)
            markGroup();
        } else if (shared) {
          markRay<true>(origin, key_origin, ray, lattice, scratch, overflow);
        } else {
          markRay<false>(origin, key_origin, ray, lattice, scratch, overflow);
        }
      });
      if (grouped > 0)
        markGroup();
    }
  }
  stats.traverse_ms = traverse_start.ms();

  // 3. The bitset into the tree: blocks in octree order, voxels in octree order inside
  //    a block, the blocks' subtrees in parallel (applyBitset).
  const Stopwatch update_start;
  // Should the tree throw (std::bad_alloc), the bitset is left half cleared: start the
  // next frame with new buffers.
  struct ScratchGuard {
    std::unique_ptr<detail::OccupancyMapScratch>& scratch;
    bool done = false;
    ~ScratchGuard()
    {
      if (!done)
        scratch = std::make_unique<detail::OccupancyMapScratch>();
    }
  } guard{scratch_};
  std::sort(scratch.used.begin(), scratch.used.end(),
            [](const Scratch::UsedBlock& a, const Scratch::UsedBlock& b) {
              return a.morton < b.morton;
            });
  applyBitset(*tree_, scratch, threads, stats);

  // Keys outside the table (not expected, see keepOutside): free voxels
  // distinct from all above, applied one by one with OctoMap's own non-lazy update.
  std::vector<std::uint64_t> overflow;
  for (const auto& list : scratch.overflow)
    overflow.insert(overflow.end(), list.begin(), list.end());
  std::sort(overflow.begin(), overflow.end());
  overflow.erase(std::unique(overflow.begin(), overflow.end()), overflow.end());
  for (const std::uint64_t packed : overflow) {
    const octomap::OcTreeKey key(static_cast<octomap::key_type>(packed >> 32),
                                 static_cast<octomap::key_type>((packed >> 16) & 0xffffu),
                                 static_cast<octomap::key_type>(packed & 0xffffu));
    tree_->updateNode(key, tree_->getProbMissLog(), /*lazy_eval=*/false);
    scratch.changed_bricks.push_back({key[0] >> kChangedBrickShift,
                                      key[1] >> kChangedBrickShift,
                                      key[2] >> kChangedBrickShift});
  }
  stats.free_voxels += overflow.size();
  stats.tree_updates += overflow.size();
  if (!overflow.empty()) { // each brick once
    std::vector<std::array<int, 3>>& changed = scratch.changed_bricks;
    std::sort(changed.begin(), changed.end());
    changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  }
  changed_bricks_revision_ = revision_;
  guard.done = true;
  stats.update_ms = update_start.ms();
  stats.total_ms = start.ms();
  last_stats_ = stats;
}

bool OccupancyMap::getChangedBricks(std::uint64_t since,
                                    std::vector<std::array<int, 3>>& bricks) const
{
  bricks.clear();
  if (changed_bricks_revision_ != revision_ || since + 1 != revision_)
    return false;
  bricks = scratch_->changed_bricks;
  return true;
}

void OccupancyMap::clear()
{
  ++revision_;
  tree_->clear();
  last_stats_ = InsertStats();
}

bool OccupancyMap::computeKey(const Eigen::Vector3d& point_W,
                              octomap::OcTreeKey& key) const
{
  if (!point_W.allFinite())
    return false;
  const VoxelLattice lattice(tree_->getResolution());
  int k[3];
  for (int a = 0; a < 3; ++a)
    if (!lattice.coordToKey(point_W[a], k[a]))
      return false;
  key = octomap::OcTreeKey(static_cast<octomap::key_type>(k[0]),
                           static_cast<octomap::key_type>(k[1]),
                           static_cast<octomap::key_type>(k[2]));
  return true;
}

VoxelState OccupancyMap::state(const octomap::OcTreeKey& key) const
{
  const octomap::OcTreeNode* node = tree_->search(key);
  if (!node)
    return VoxelState::unknown;
  return tree_->isNodeOccupied(node) ? VoxelState::occupied : VoxelState::free;
}

VoxelState OccupancyMap::state(const Eigen::Vector3d& point_W) const
{
  octomap::OcTreeKey key;
  return computeKey(point_W, key) ? state(key) : VoxelState::unknown;
}

float OccupancyMap::logOdds(const octomap::OcTreeKey& key) const
{
  const octomap::OcTreeNode* node = tree_->search(key);
  return node ? node->getLogOdds() : 0.0f;
}

double OccupancyMap::probability(const octomap::OcTreeKey& key) const
{
  const octomap::OcTreeNode* node = tree_->search(key);
  return node ? node->getOccupancy() : 0.5;
}

double OccupancyMap::probability(const Eigen::Vector3d& point_W) const
{
  octomap::OcTreeKey key;
  return computeKey(point_W, key) ? probability(key) : 0.5;
}

bool OccupancyMap::isKnown(const octomap::OcTreeKey& key) const
{
  return tree_->search(key) != nullptr;
}

void OccupancyMap::getOccupiedVoxelCentres(CloudXYZ& cloud,
                                           const OccupiedVoxelOptions& options) const
{
  OccupiedVoxelOptions own = options;
  own.inner_nodes_hold_max = true; // insert is non-lazy; read() updates inner nodes
  own.threads = threads_;
  occupiedVoxelCentres(*tree_, cloud, own);
}

OccupancyMap::VoxelCounts OccupancyMap::countVoxels() const
{
  VoxelCounts counts;
  const unsigned depth = tree_->getTreeDepth();
  for (auto it = tree_->begin_leafs(), end = tree_->end_leafs(); it != end; ++it) {
    const std::size_t voxels = std::size_t{1} << (3 * (depth - it.getDepth()));
    if (tree_->isNodeOccupied(*it))
      counts.occupied += voxels;
    else
      counts.free += voxels;
  }
  return counts;
}

std::unique_ptr<OccupancyMap> OccupancyMap::read(const std::string& path, Config config,
                                                 bool* maximum_likelihood)
{
  std::unique_ptr<octomap::OcTree> tree = readOcTree(path, maximum_likelihood);
  config.resolution_m = tree->getResolution();
  auto map = std::make_unique<OccupancyMap>(config);
  tree->setProbHit(config.prob_hit);
  tree->setProbMiss(config.prob_miss);
  tree->setClampingThresMin(config.clamp_min);
  tree->setClampingThresMax(config.clamp_max);
  tree->setOccupancyThres(config.occupancy_threshold);
  tree->updateInnerOccupancy();
  tree->prune();
  map->tree_ = std::move(tree);
  return map;
}

void OccupancyMap::write(const std::string& path) const
{
  writeOcTree(path, *tree_);
}

} // namespace plantnbv
