#include "gain_snapshot.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <omp.h>
#include <sstream>
#include <type_traits>

#include <octomap/OcTree.h>

#include <plantnbv/common/error.h>
#include <plantnbv/planning/information_gain.h>

namespace plantnbv {
namespace gain_detail {

namespace {

/// Snapshot::split(): at least this many tasks where the tree has them, so that
/// threads share the walk evenly (subtrees differ in size by orders of magnitude).
constexpr std::size_t kMinTasks = 256;
/// The deepest root of a task: a node at this depth is one brick.
constexpr int kMaxTaskDepth = VoxelLattice::kTreeDepth - kBrickShift;

/// fill() on one thread: makes bricks in `voxels`.
template <typename CodeT>
struct SharedBrickWriter {
  Bricks<CodeT>& bricks;

  CodeT* materialize(std::size_t s) { return bricks.materialize(s); }
};

/// fill() on several threads: makes bricks in the thread's own buffer; the bricks made
/// before (at the ROI's border) stay in `voxels`.
template <typename CodeT>
struct OwnBrickWriter {
  Bricks<CodeT>& bricks;
  std::vector<CodeT>& own;
  std::vector<std::size_t>& slots; ///< each new brick's slot

  /// Bricks::materialize() into `own`.
  CodeT* materialize(std::size_t s)
  {
    std::uint32_t& e = bricks.table[s];
    if (e & kUniform) {
      const CodeT c = static_cast<CodeT>(e & ~kUniform);
      const auto index = static_cast<std::uint32_t>(own.size() >> (3 * kBrickShift));
      own.resize(own.size() + kBrickVoxels, c);
      slots.push_back(s);
      e = kThreadLocal | index;
    }
    if (e & kThreadLocal)
      return &own[static_cast<std::size_t>(e & ~kThreadLocal) << (3 * kBrickShift)];
    return &bricks.voxels[static_cast<std::size_t>(e) << (3 * kBrickShift)];
  }
};

/// The most bricks a snapshot's table may hold.
constexpr std::size_t kMaxBricks = std::size_t{1} << 28;

/// The bricks of the table that holds `region`.
std::size_t brickCount(const KeyBox& region)
{
  std::size_t n = 1;
  for (int a = 0; a < 3; ++a)
    n *= static_cast<std::size_t>((region.hi[a] >> kBrickShift) -
                                  (region.lo[a] >> kBrickShift) + 1);
  return n;
}

/// The bytes of a voxel code for `n` values.
int codeBytes(std::size_t n)
{
  const std::size_t max_code = (n - 1) << kValueShift | kOccupied | kInRoi;
  return max_code <= 0xffu ? 1 : (max_code <= 0xffffu ? 2 : 4);
}

std::uint32_t floatBits(float f)
{
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  return bits;
}

/// Value indices' order: increasing log-odds, equal values (-0 and 0) by their bits, so
/// that which is kept does not depend on the thread that found it.
bool valueBefore(float a, float b)
{
  return a < b || (a == b && floatBits(a) < floatBits(b));
}

} // namespace

void KeyBox::extend(const KeyBox& b)
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

KeyBox roiKeyBox(const Box& box, const VoxelLattice& lattice)
{
  const double resolution = lattice.resolution();
  KeyBox k;
  for (int a = 0; a < 3; ++a) {
    const double c = box.center[a], half = 0.5 * box.size[a];
    auto inside = [&](int key) { return std::abs(lattice.keyToCoord(key) - c) <= half; };
    // A superset of the interval, then shrunk to it with the exact test.
    const double lo =
        std::floor((c - half) / resolution) + VoxelLattice::kKeyOffset - 2.0;
    const double hi = std::ceil((c + half) / resolution) + VoxelLattice::kKeyOffset + 2.0;
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

template <typename CodeT>
CodeT* Bricks<CodeT>::materialize(std::size_t s)
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

template <typename CodeT>
std::uint32_t Bricks<CodeT>::sharedBrick(std::uint32_t code)
{
  for (const auto& cb : shared)
    if (cb.first == code)
      return cb.second;
  const auto index = static_cast<std::uint32_t>(voxels.size() >> (3 * kBrickShift));
  voxels.resize(voxels.size() + kBrickVoxels, static_cast<CodeT>(code));
  shared.push_back({code, index});
  return index;
}

template <typename CodeT>
void Bricks<CodeT>::shareUniformBricks()
{
  shared.clear();
  outside_brick = sharedBrick(outside);
  for (std::uint32_t& e : table)
    if (e & kUniform)
      e = kUniform | sharedBrick(e & ~kUniform);
}

template <typename CodeT>
void Bricks<CodeT>::store(std::size_t s, const CodeT* v)
{
  std::uint32_t& e = table[s];
  if (std::all_of(v + 1, v + kBrickVoxels, [&](CodeT c) { return c == v[0]; })) {
    if (!(e & kUniform))
      free_bricks.push_back(e);
    e = kUniform | sharedBrick(v[0]);
    return;
  }
  if (e & kUniform) {
    if (!free_bricks.empty()) {
      e = free_bricks.back();
      free_bricks.pop_back();
    } else {
      e = static_cast<std::uint32_t>(voxels.size() >> (3 * kBrickShift));
      voxels.resize(voxels.size() + kBrickVoxels);
    }
  }
  std::copy(v, v + kBrickVoxels,
            &voxels[static_cast<std::size_t>(e) << (3 * kBrickShift)]);
}

template <typename CodeT>
void Bricks<CodeT>::resize(const KeyBox& region)
{
  int b0_new[3], nb_new[3];
  for (int a = 0; a < 3; ++a) {
    b0_new[a] = region.lo[a] >> kBrickShift;
    nb_new[a] = (region.hi[a] >> kBrickShift) - b0_new[a] + 1;
  }
  std::vector<std::uint32_t> t(brickCount(region), kUniform | outside_brick);
  for (int z = 0; z < nb[2]; ++z)
    for (int y = 0; y < nb[1]; ++y) {
      const std::size_t from = slot(0, y, z);
      const std::size_t to = (static_cast<std::size_t>(z + b0[2] - b0_new[2]) *
                                  static_cast<std::size_t>(nb_new[1]) +
                              static_cast<std::size_t>(y + b0[1] - b0_new[1])) *
                                 static_cast<std::size_t>(nb_new[0]) +
                             static_cast<std::size_t>(b0[0] - b0_new[0]);
      std::copy(table.begin() + static_cast<std::ptrdiff_t>(from),
                table.begin() + static_cast<std::ptrdiff_t>(from) + nb[0],
                t.begin() + static_cast<std::ptrdiff_t>(to));
    }
  table.swap(t);
  for (int a = 0; a < 3; ++a) {
    b0[a] = b0_new[a];
    nb[a] = nb_new[a];
  }
}

template <typename CodeT>
void Bricks<CodeT>::clear()
{
  table.clear();
  voxels.clear();
  shared.clear();
  free_bricks.clear();
  for (int a = 0; a < 3; ++a)
    b0[a] = nb[a] = 0;
}

template struct Bricks<std::uint8_t>;
template struct Bricks<std::uint16_t>;
template struct Bricks<std::uint32_t>;

void Snapshot::Part::reset()
{
  leaves.clear();
  distinct.clear();
  hash_keys.assign(64, 0);
  hash_values.assign(64, 0);
  last_key = 0;
  last_value = 0;
  for (int a = 0; a < 3; ++a) { // empty, and min / max take any key
    extent.lo[a] = kKeyLimit;
    extent.hi[a] = -1;
  }
}

std::uint32_t Snapshot::Part::valueIndex(float log_odds)
{
  const std::uint32_t key = floatBits(log_odds) + 1u; // 0 marks an empty slot (NaN
                                                      // bits never occur)
  if (key == last_key) // neighbouring leaves often share their value
    return last_value;
  last_key = key;
  std::size_t mask = hash_keys.size() - 1;
  std::size_t i = (key * 0x9e3779b1u) & mask;
  while (hash_keys[i] != 0) {
    if (hash_keys[i] == key)
      return last_value = hash_values[i];
    i = (i + 1) & mask;
  }
  const auto index = static_cast<std::uint32_t>(distinct.size());
  last_value = index;
  distinct.push_back(log_odds);
  hash_keys[i] = key;
  hash_values[i] = index;
  if (2 * distinct.size() > hash_keys.size()) { // keep it at most half full
    std::vector<std::uint32_t> keys(2 * hash_keys.size(), 0),
        values(2 * hash_keys.size());
    mask = keys.size() - 1;
    for (std::size_t j = 0; j < hash_keys.size(); ++j) {
      if (!hash_keys[j])
        continue;
      std::size_t p = (hash_keys[j] * 0x9e3779b1u) & mask;
      while (keys[p])
        p = (p + 1) & mask;
      keys[p] = hash_keys[j];
      values[p] = hash_values[j];
    }
    hash_keys.swap(keys);
    hash_values.swap(values);
  }
  return index;
}

bool Snapshot::matters(const octomap::OcTreeNode* node, int depth, const int k[3]) const
{
  // Inner nodes hold the maximum of their children (OccupancyMap keeps them so): away
  // from the ROI only subtrees with an occupied voxel matter.
  return full ||
         (roi_mode &&
          roi_bbox.overlapsCube(k, 1 << (VoxelLattice::kTreeDepth - depth))) ||
         node->getLogOdds() > threshold_;
}

void Snapshot::addLeaf(Part& part, const int k[3], int shift, float log_odds) const
{
  part.leaves.push_back({{k[0], k[1], k[2]}, shift, part.valueIndex(log_odds)});
  // The keys the snapshot needs for it: its cube, within the ROI's keys unless it is
  // occupied or every voxel is needed.
  const bool clip = !full && !(log_odds > threshold_);
  for (int a = 0; a < 3; ++a) {
    int l = k[a], h = k[a] + (1 << shift) - 1;
    if (clip) {
      l = std::max(l, roi_bbox.lo[a]);
      h = std::min(h, roi_bbox.hi[a]);
    }
    part.extent.lo[a] = std::min(part.extent.lo[a], l);
    part.extent.hi[a] = std::max(part.extent.hi[a], h);
  }
}

void Snapshot::collectBrick(Part& part, const int k[3]) const
{
  constexpr int kBrickDepth = VoxelLattice::kTreeDepth - kBrickShift;
  const octomap::OcTreeNode* node = tree->getRoot();
  int first[3] = {0, 0, 0}; // of the node's cube
  for (int depth = 0; node; ++depth) {
    if (depth == kBrickDepth) {
      collect(part, node, depth, first);
      return;
    }
    if (!tree->nodeHasChildren(node)) { // a leaf larger than the brick: its part
      if (matters(node, depth, first))
        addLeaf(part, k, kBrickShift, node->getLogOdds());
      return;
    }
    const int shift = VoxelLattice::kTreeDepth - depth - 1; // of the children's cubes
    unsigned i = 0;
    for (int a = 0; a < 3; ++a) {
      const int bit = (k[a] >> shift) & 1;
      i |= static_cast<unsigned>(bit) << a;
      first[a] += bit << shift;
    }
    node = tree->nodeChildExists(node, i) ? tree->getNodeChild(node, i) : nullptr;
  }
}

void Snapshot::collect(Part& part, const octomap::OcTreeNode* node, int depth,
                       const int k[3]) const
{
  if (!matters(node, depth, k))
    return;
  const int shift = VoxelLattice::kTreeDepth - depth;
  if (!tree->nodeHasChildren(node)) {
    addLeaf(part, k, shift, node->getLogOdds());
    return;
  }
  const int half = 1 << (shift - 1);
  for (unsigned i = 0; i < 8; ++i) {
    if (!tree->nodeChildExists(node, i))
      continue;
    const int c[3] = {k[0] + ((i & 1u) ? half : 0), k[1] + ((i & 2u) ? half : 0),
                      k[2] + ((i & 4u) ? half : 0)};
    collect(part, tree->getNodeChild(node, i), depth + 1, c);
  }
}

void Snapshot::split(const octomap::OcTreeNode* root)
{
  tasks_.clear();
  if (!root)
    return;
  Task top;
  top.node = root;
  top.depth = 0;
  top.k[0] = top.k[1] = top.k[2] = 0;
  tasks_.push_back(top);
  // Level by level, each inner node that matters in place of its children: the list
  // stays in the order of the depth-first walk.
  for (int depth = 0; depth < kMaxTaskDepth && tasks_.size() < kMinTasks; ++depth) {
    next_tasks_.clear();
    for (const Task& t : tasks_) {
      if (t.depth != depth || !tree->nodeHasChildren(t.node)) {
        next_tasks_.push_back(t);
        continue;
      }
      if (!matters(t.node, depth, t.k))
        continue; // collect() would leave it at once
      const int half = 1 << (VoxelLattice::kTreeDepth - depth - 1);
      for (unsigned i = 0; i < 8; ++i) {
        if (!tree->nodeChildExists(t.node, i))
          continue;
        Task c;
        c.node = tree->getNodeChild(t.node, i);
        c.depth = depth + 1;
        c.k[0] = t.k[0] + ((i & 1u) ? half : 0);
        c.k[1] = t.k[1] + ((i & 2u) ? half : 0);
        c.k[2] = t.k[2] + ((i & 4u) ? half : 0);
        next_tasks_.push_back(c);
      }
    }
    tasks_.swap(next_tasks_);
  }
}

template <typename Writer>
void Snapshot::fillTask(const Task& task, const KeyBox& region, Writer& writer) const
{
  auto& bricks = writer.bricks;
  using CodeT = typename std::remove_reference_t<decltype(bricks.voxels)>::value_type;
  const Part& part = parts_[static_cast<std::size_t>(task.part)];
  // Local pointers: stores of codes may alias any member.
  const std::uint32_t* remap = part.remap.data();
  const Value* value_of = values.data();
  const Leaf* end = part.leaves.data() + task.leaf_end;
  for (const Leaf* l = part.leaves.data() + task.leaf_begin; l != end; ++l) {
    const Leaf leaf = *l; // a copy: not reloaded after each store
    const std::uint32_t value = remap[leaf.value];
    const std::uint32_t base =
        (value << kValueShift) | (value_of[value].occupied ? kOccupied : 0u);
    if (leaf.shift == 0) { // a single voxel: most leaves
      std::size_t s;
      if (!bricks.slotOf(leaf.k[0], leaf.k[1], leaf.k[2], s))
        continue;
      const std::uint32_t e = bricks.table[s];
      if (e == (kUniform | base) || e == (kUniform | base | kInRoi))
        continue; // the brick already has this value
      CodeT& c = writer.materialize(s)[brickLocal(leaf.k[0], leaf.k[1], leaf.k[2])];
      c = static_cast<CodeT>(base | (c & kInRoi));
      continue;
    }
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
          const std::size_t s =
              bricks.slot(bx - bricks.b0[0], by - bricks.b0[1], bz - bricks.b0[2]);
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
            e = kUniform | base | (e & kInRoi);
            continue;
          }
          CodeT* v = writer.materialize(s);
          for (int z = v_lo[2]; z <= v_hi[2]; ++z)
            for (int y = v_lo[1]; y <= v_hi[1]; ++y)
              for (int x = v_lo[0]; x <= v_hi[0]; ++x) {
                CodeT& c = v[(z << (2 * kBrickShift)) | (y << kBrickShift) | x];
                c = static_cast<CodeT>(base | (c & kInRoi));
              }
        }
  }
}

int Snapshot::roiCover(const int k[3]) const
{
  if (!roi_mode)
    return 0;
  int cover = 0;
  for (const KeyBox& b : roi_boxes) {
    if (b.empty() || !b.overlapsCube(k, 1 << kBrickShift))
      continue;
    bool covers = true;
    for (int a = 0; a < 3; ++a)
      covers = covers && b.lo[a] <= k[a] && b.hi[a] >= k[a] + kBrickMask;
    cover = std::max(cover, covers ? 2 : 1);
  }
  return cover;
}

template <typename CodeT>
void Snapshot::markRoi(const int k[3], CodeT* v) const
{
  for (const KeyBox& b : roi_boxes) {
    if (b.empty() || !b.overlapsCube(k, 1 << kBrickShift))
      continue;
    int v_lo[3], v_hi[3];
    for (int a = 0; a < 3; ++a) {
      v_lo[a] = std::max(b.lo[a], k[a]) - k[a];
      v_hi[a] = std::min(b.hi[a], k[a] + kBrickMask) - k[a];
    }
    for (int z = v_lo[2]; z <= v_hi[2]; ++z)
      for (int y = v_lo[1]; y <= v_hi[1]; ++y)
        for (int x = v_lo[0]; x <= v_hi[0]; ++x)
          v[(z << (2 * kBrickShift)) | (y << kBrickShift) | x] = kInRoi;
  }
}

template <typename CodeT>
void Snapshot::fill(Bricks<CodeT>& bricks, const KeyBox& region, int threads)
{
  bricks.clear();
  const std::size_t n = brickCount(region);
  for (int a = 0; a < 3; ++a) {
    bricks.b0[a] = region.lo[a] >> kBrickShift;
    bricks.nb[a] = (region.hi[a] >> kBrickShift) - bricks.b0[a] + 1;
  }
  if (n > kMaxBricks) {
    std::ostringstream s;
    s << "InformationGain::update: the map's region to snapshot spans " << n
      << " bricks of 8^3 voxels, more than 2^28; with an ROI and no visibility "
         "weighting only the ROI and the occupied voxels are needed";
    throw Error(s.str());
  }
  bricks.outside = static_cast<CodeT>(roi_mode ? 0u : kInRoi); // unknown
  bricks.table.assign(n, kUniform | bricks.outside);

  // Bricks at the ROI's border get per-voxel flags; bricks inside it a uniform code.
  if (roi_mode && !roi_bbox.empty()) {
    const int lo[3] = {roi_bbox.lo[0] >> kBrickShift, roi_bbox.lo[1] >> kBrickShift,
                       roi_bbox.lo[2] >> kBrickShift};
    const int hi[3] = {roi_bbox.hi[0] >> kBrickShift, roi_bbox.hi[1] >> kBrickShift,
                       roi_bbox.hi[2] >> kBrickShift};
    for (int bz = lo[2]; bz <= hi[2]; ++bz)
      for (int by = lo[1]; by <= hi[1]; ++by)
        for (int bx = lo[0]; bx <= hi[0]; ++bx) {
          const int k[3] = {bx << kBrickShift, by << kBrickShift, bz << kBrickShift};
          const int cover = roiCover(k);
          const std::size_t s =
              bricks.slot(bx - bricks.b0[0], by - bricks.b0[1], bz - bricks.b0[2]);
          if (cover == 2)
            bricks.table[s] = kUniform | kInRoi;
          else if (cover == 1)
            markRoi(k, bricks.materialize(s)); // all 0 (`outside`) before
        }
  }

  // The leaves, task by task: a task's leaves lie in its cube, which holds whole bricks,
  // so tasks write disjoint slots and bricks.
  if (threads == 1) {
    SharedBrickWriter<CodeT> writer{bricks};
    for (const Task& task : tasks_)
      fillTask(task, region, writer);
  } else {
    if (bricks.thread_voxels.size() < static_cast<std::size_t>(threads))
      bricks.thread_voxels.resize(static_cast<std::size_t>(threads));
    for (int t = 0; t < threads; ++t) {
      bricks.thread_voxels[static_cast<std::size_t>(t)].clear();
      parts_[static_cast<std::size_t>(t)].brick_slots.clear();
    }
    const auto n_tasks = static_cast<std::int64_t>(tasks_.size());
#pragma omp parallel num_threads(threads)
    {
      const int t = omp_get_thread_num();
      std::vector<CodeT>& own = bricks.thread_voxels[static_cast<std::size_t>(t)];
      std::vector<std::size_t>& slots = parts_[static_cast<std::size_t>(t)].brick_slots;
      OwnBrickWriter<CodeT> writer{bricks, own, slots};
#pragma omp for schedule(dynamic, 1)
      for (std::int64_t i = 0; i < n_tasks; ++i) {
        Task& task = tasks_[static_cast<std::size_t>(i)];
        task.fill_part = t;
        task.brick_begin = slots.size();
        fillTask(task, region, writer);
        task.brick_end = slots.size();
      }
    }
    // Into `voxels` in task order: where one thread would have put them.
    std::size_t next = bricks.voxels.size() >> (3 * kBrickShift);
    for (Task& task : tasks_) {
      task.brick_index = next;
      next += task.brick_end - task.brick_begin;
    }
    bricks.voxels.resize(next << (3 * kBrickShift));
#pragma omp parallel for num_threads(threads) schedule(dynamic, 16)
    for (std::int64_t i = 0; i < n_tasks; ++i) {
      const Task& task = tasks_[static_cast<std::size_t>(i)];
      const auto f = static_cast<std::size_t>(task.fill_part);
      const std::vector<CodeT>& own = bricks.thread_voxels[f];
      const std::vector<std::size_t>& slots = parts_[f].brick_slots;
      std::copy(own.begin() +
                    static_cast<std::ptrdiff_t>(task.brick_begin << (3 * kBrickShift)),
                own.begin() +
                    static_cast<std::ptrdiff_t>(task.brick_end << (3 * kBrickShift)),
                bricks.voxels.begin() +
                    static_cast<std::ptrdiff_t>(task.brick_index << (3 * kBrickShift)));
      for (std::size_t j = task.brick_begin; j < task.brick_end; ++j)
        bricks.table[slots[j]] =
            static_cast<std::uint32_t>(task.brick_index + (j - task.brick_begin));
    }
  }
  brick_count = bricks.voxels.size() >> (3 * kBrickShift);
  bricks.shareUniformBricks();
}

void Snapshot::collectTasks(int threads, bool bricks)
{
  const auto n_tasks = static_cast<std::int64_t>(tasks_.size());
#pragma omp parallel num_threads(threads)
  {
    const int t = omp_get_thread_num();
    Part& part = parts_[static_cast<std::size_t>(t)];
#pragma omp for schedule(dynamic, 1)
    for (std::int64_t i = 0; i < n_tasks; ++i) {
      Task& task = tasks_[static_cast<std::size_t>(i)];
      task.part = t;
      task.leaf_begin = part.leaves.size();
      if (bricks)
        collectBrick(part, task.k);
      else
        collect(part, task.node, task.depth, task.k);
      task.leaf_end = part.leaves.size();
    }
  }
  leaf_count = 0;
  for (int t = 0; t < threads; ++t)
    leaf_count += parts_[static_cast<std::size_t>(t)].leaves.size();
}

void Snapshot::addDistinctValues(int threads, std::vector<float>& sorted)
{
  // Value indices in increasing log-odds (deterministic); 0 is unknown.
  for (int t = 0; t < threads; ++t) {
    const Part& part = parts_[static_cast<std::size_t>(t)];
    sorted.insert(sorted.end(), part.distinct.begin(), part.distinct.end());
  }
  std::sort(sorted.begin(), sorted.end(), valueBefore);
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  for (int t = 0; t < threads; ++t) {
    Part& part = parts_[static_cast<std::size_t>(t)];
    part.remap.resize(part.distinct.size());
    for (std::size_t i = 0; i < part.distinct.size(); ++i)
      part.remap[i] = static_cast<std::uint32_t>(
          std::lower_bound(sorted.begin(), sorted.end(), part.distinct[i]) -
          sorted.begin() + 1);
  }
}

Value Snapshot::valueOf(float log_odds) const
{
  const double p = octomap::probability(log_odds); // OcTreeNode::getOccupancy()
  Value v;
  v.log_odds = log_odds;
  v.entropy = unknown_only_ ? 0.0 : occupancyEntropy(p);
  v.free_prob = 1.0 - p;
  v.occupied = log_odds > threshold_; // OcTree::isNodeOccupied
  return v;
}

void Snapshot::setValues(const std::vector<float>& sorted)
{
  values.assign(1, Value());
  values[0].entropy = occupancyEntropy(0.5);
  for (float log_odds : sorted)
    values.push_back(valueOf(log_odds));
  orderValues();
}

void Snapshot::orderValues()
{
  value_order.resize(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    value_order[i] = static_cast<std::uint32_t>(i);
  std::sort(value_order.begin() + 1, value_order.end(),
            [this](std::uint32_t a, std::uint32_t b) {
              return valueBefore(values[a].log_odds, values[b].log_odds);
            });
}

bool Snapshot::findValue(float log_odds, std::uint32_t& index) const
{
  const auto known = std::lower_bound(
      value_order.begin() + 1, value_order.end(), log_odds,
      [this](std::uint32_t v, float x) { return values[v].log_odds < x; });
  if (known == value_order.end() || !(values[*known].log_odds == log_odds))
    return false;
  index = *known;
  return true;
}

bool Snapshot::addNewValues(int threads)
{
  // The parts' log-odds that no value has yet (equal ones are one value, as in
  // addDistinctValues), in increasing log-odds.
  std::vector<float> added;
  std::uint32_t index;
  for (int t = 0; t < threads; ++t)
    for (float log_odds : parts_[static_cast<std::size_t>(t)].distinct)
      if (!findValue(log_odds, index))
        added.push_back(log_odds);
  std::sort(added.begin(), added.end(), valueBefore);
  added.erase(std::unique(added.begin(), added.end()), added.end());
  if (codeBytes(values.size() + added.size()) != code_bytes)
    return false;
  for (float log_odds : added)
    values.push_back(valueOf(log_odds));
  orderValues();
  for (int t = 0; t < threads; ++t) {
    Part& part = parts_[static_cast<std::size_t>(t)];
    part.remap.resize(part.distinct.size());
    for (std::size_t i = 0; i < part.distinct.size(); ++i) {
      findValue(part.distinct[i], index); // found: every one is a value now
      part.remap[i] = index;
    }
  }
  return true;
}

void Snapshot::build(const octomap::OcTree& octree, const Roi& roi, bool full_map,
                     bool unknown_only, int threads)
{
  built = false;
  tree = &octree;
  lattice = VoxelLattice(tree->getResolution());
  const double resolution = lattice.resolution();
  threshold_ = tree->getOccupancyThresLog();
  unknown_only_ = unknown_only;
  roi_mode = !roi.empty();
  full = full_map || !roi_mode;
  roi_boxes.clear();
  roi_bbox = KeyBox();
  clip_boxes.clear();
  for (const Box& b : roi.boxes()) {
    roi_boxes.push_back(roiKeyBox(b, lattice));
    roi_bbox.extend(roi_boxes.back());
    ClipBox c;
    for (int a = 0; a < 3; ++a) {
      c.lo[a] = b.min()[a] - resolution;
      c.hi[a] = b.max()[a] + resolution;
    }
    clip_boxes.push_back(c);
  }

  // The walk: subtrees in parallel, each thread with its own leaves and values.
  threads = std::max(1, threads);
  if (parts_.size() < static_cast<std::size_t>(threads))
    parts_.resize(static_cast<std::size_t>(threads));
  for (int t = 0; t < threads; ++t) // OpenMP may start fewer
    parts_[static_cast<std::size_t>(t)].reset();
  split(tree->getRoot());
  collectTasks(threads, false);
  std::vector<float> sorted;
  addDistinctValues(threads, sorted);
  setValues(sorted);

  // The region: the ROI's keys, every stored occupied leaf, and the other stored leaves
  // where they matter (within the ROI's keys unless every voxel is needed; collect()).
  KeyBox region = roi_bbox;
  for (int t = 0; t < threads; ++t)
    region.extend(parts_[static_cast<std::size_t>(t)].extent);
  if (region.empty()) // nothing known and no ROI voxel: one brick
    for (int a = 0; a < 3; ++a)
      region.lo[a] = region.hi[a] = VoxelLattice::kKeyOffset;

  region_ = region;
  code_bytes = codeBytes(values.size());
  bricks8.clear();
  bricks16.clear();
  bricks32.clear();
  if (code_bytes == 1)
    fill(bricks8, region, threads);
  else if (code_bytes == 2)
    fill(bricks16, region, threads);
  else
    fill(bricks32, region, threads);
  built = true;
}

bool Snapshot::update(const std::vector<std::array<int, 3>>& changed, int threads)
{
  threads = std::max(1, threads);
  if (parts_.size() < static_cast<std::size_t>(threads))
    parts_.resize(static_cast<std::size_t>(threads));
  for (int t = 0; t < threads; ++t)
    parts_[static_cast<std::size_t>(t)].reset();
  tasks_.clear();
  for (const std::array<int, 3>& b : changed) {
    Task task;
    task.node = nullptr;
    task.depth = VoxelLattice::kTreeDepth - kBrickShift;
    for (int a = 0; a < 3; ++a)
      task.k[a] = b[static_cast<std::size_t>(a)] << kBrickShift;
    tasks_.push_back(task);
  }
  collectTasks(threads, true);

  // The region grows to the changed voxels the snapshot needs (it never shrinks: what
  // lies outside a new build's region is neither in the ROI nor occupied, so the gains
  // do not see the difference).
  KeyBox region = region_;
  for (int t = 0; t < threads; ++t)
    region.extend(parts_[static_cast<std::size_t>(t)].extent);
  if (brickCount(region) > kMaxBricks)
    return false;
  // The values: the old ones keep their indices (some perhaps no longer in the tree: no
  // voxel has them, so they add nothing), the new ones take the next, so that no code
  // changes; the gain sums over them in value_order, a new build's order.
  built = false; // until the bricks are whole again (should they throw)
  if (!addNewValues(threads)) {
    built = true; // unchanged
    return false;
  }
  if (code_bytes == 1)
    updateBricks(bricks8, region);
  else if (code_bytes == 2)
    updateBricks(bricks16, region);
  else
    updateBricks(bricks32, region);
  built = true;
  return true;
}

template <typename CodeT>
void Snapshot::updateBricks(Bricks<CodeT>& bricks, const KeyBox& region)
{
  if (region.lo[0] != region_.lo[0] || region.lo[1] != region_.lo[1] ||
      region.lo[2] != region_.lo[2] || region.hi[0] != region_.hi[0] ||
      region.hi[1] != region_.hi[1] || region.hi[2] != region_.hi[2]) {
    bricks.resize(region);
    region_ = region;
  }
  // Each changed brick as fill() would make it: the ROI's flags, then its leaves.
  CodeT v[kBrickVoxels];
  for (const Task& task : tasks_) {
    std::size_t s;
    if (!bricks.slotOf(task.k[0], task.k[1], task.k[2], s))
      continue; // nothing there is needed: update() grew the box to every needed voxel
    const int cover = roiCover(task.k);
    std::fill(v, v + kBrickVoxels,
              static_cast<CodeT>(cover == 2 ? kInRoi : bricks.outside));
    if (cover == 1)
      markRoi(task.k, v);
    const Part& part = parts_[static_cast<std::size_t>(task.part)];
    for (std::size_t l = task.leaf_begin; l < task.leaf_end; ++l) {
      const Leaf& leaf = part.leaves[l];
      const std::uint32_t value = part.remap[leaf.value];
      const std::uint32_t base =
          (value << kValueShift) | (values[value].occupied ? kOccupied : 0u);
      int lo[3], hi[3];
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::max({leaf.k[a], region_.lo[a], task.k[a]}) - task.k[a];
        hi[a] = std::min({leaf.k[a] + (1 << leaf.shift) - 1, region_.hi[a],
                          task.k[a] + kBrickMask}) -
                task.k[a];
      }
      for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
          for (int x = lo[0]; x <= hi[0]; ++x) {
            CodeT& c = v[(z << (2 * kBrickShift)) | (y << kBrickShift) | x];
            c = static_cast<CodeT>(base | (c & kInRoi));
          }
    }
    bricks.store(s, v);
  }
  brick_count = (bricks.voxels.size() >> (3 * kBrickShift)) - bricks.shared.size() -
                bricks.free_bricks.size();
}

} // namespace gain_detail
} // namespace plantnbv
