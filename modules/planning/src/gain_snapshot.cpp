#include "gain_snapshot.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include <octomap/OcTree.h>

#include <plantnbv/common/error.h>
#include <plantnbv/planning/information_gain.h>

namespace plantnbv {
namespace gain_detail {

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
void Bricks<CodeT>::shareUniformBricks()
{
  std::vector<std::pair<std::uint32_t, std::uint32_t>> shared; // code -> brick, few
  auto brickOf = [&](std::uint32_t code) {
    for (const auto& cb : shared)
      if (cb.first == code)
        return cb.second;
    const auto index = static_cast<std::uint32_t>(voxels.size() >> (3 * kBrickShift));
    voxels.resize(voxels.size() + kBrickVoxels, static_cast<CodeT>(code));
    shared.push_back({code, index});
    return index;
  };
  outside_brick = brickOf(outside);
  for (std::uint32_t& e : table)
    if (e & kUniform)
      e = kUniform | brickOf(e & ~kUniform);
}

template <typename CodeT>
void Bricks<CodeT>::clear()
{
  table.clear();
  voxels.clear();
  for (int a = 0; a < 3; ++a)
    b0[a] = nb[a] = 0;
}

template struct Bricks<std::uint8_t>;
template struct Bricks<std::uint16_t>;
template struct Bricks<std::uint32_t>;

std::uint32_t Snapshot::valueIndex(float log_odds)
{
  std::uint32_t bits;
  std::memcpy(&bits, &log_odds, sizeof bits);
  const std::uint32_t key = bits + 1u; // 0 marks an empty slot (NaN bits never occur)
  if (key == last_key_)                // neighbouring leaves often share their value
    return last_value_;
  last_key_ = key;
  std::size_t mask = hash_keys_.size() - 1;
  std::size_t i = (key * 0x9e3779b1u) & mask;
  while (hash_keys_[i] != 0) {
    if (hash_keys_[i] == key)
      return last_value_ = hash_values_[i];
    i = (i + 1) & mask;
  }
  const auto index = static_cast<std::uint32_t>(distinct_.size());
  last_value_ = index;
  distinct_.push_back(log_odds);
  hash_keys_[i] = key;
  hash_values_[i] = index;
  if (2 * distinct_.size() > hash_keys_.size()) { // keep it at most half full
    std::vector<std::uint32_t> keys(2 * hash_keys_.size(), 0),
        values(2 * hash_keys_.size());
    mask = keys.size() - 1;
    for (std::size_t j = 0; j < hash_keys_.size(); ++j) {
      if (!hash_keys_[j])
        continue;
      std::size_t p = (hash_keys_[j] * 0x9e3779b1u) & mask;
      while (keys[p])
        p = (p + 1) & mask;
      keys[p] = hash_keys_[j];
      values[p] = hash_values_[j];
    }
    hash_keys_.swap(keys);
    hash_values_.swap(values);
  }
  return index;
}

void Snapshot::collect(const octomap::OcTreeNode* node, int depth, const int k[3])
{
  const int size = 1 << (VoxelLattice::kTreeDepth - depth);
  const bool near_roi = roi_mode && roi_bbox.overlapsCube(k, size);
  const float log_odds = node->getLogOdds();
  if (!tree->nodeHasChildren(node)) {
    if (full || near_roi || log_odds > threshold_)
      leaves_.push_back(
          {{k[0], k[1], k[2]}, VoxelLattice::kTreeDepth - depth, valueIndex(log_odds)});
    return;
  }
  // Inner nodes hold the maximum of their children (OccupancyMap keeps them so): away
  // from the ROI only subtrees with an occupied voxel matter.
  if (!full && !near_roi && !(log_odds > threshold_))
    return;
  const int half = size >> 1;
  for (unsigned i = 0; i < 8; ++i) {
    if (!tree->nodeChildExists(node, i))
      continue;
    const int c[3] = {k[0] + ((i & 1u) ? half : 0), k[1] + ((i & 2u) ? half : 0),
                      k[2] + ((i & 4u) ? half : 0)};
    collect(tree->getNodeChild(node, i), depth + 1, c);
  }
}

template <typename CodeT>
void Snapshot::fill(Bricks<CodeT>& bricks, const KeyBox& region)
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
          const std::size_t s =
              bricks.slot(bx - bricks.b0[0], by - bricks.b0[1], bz - bricks.b0[2]);
          if (inside) {
            bricks.table[s] = kUniform | kInRoi;
          } else if (touches) {
            CodeT* v = bricks.materialize(s);
            for (int local = 0; local < kBrickVoxels; ++local) {
              const int kx = k[0] + (local & kBrickMask);
              const int ky = k[1] + ((local >> kBrickShift) & kBrickMask);
              const int kz = k[2] + (local >> (2 * kBrickShift));
              bool in = false;
              for (const KeyBox& b : roi_boxes)
                in = in || b.contains(kx, ky, kz);
              v[local] = static_cast<CodeT>(in ? kInRoi : 0u);
            }
          }
        }
  }

  for (const Leaf& leaf : leaves_) {
    const std::uint32_t value = remap_[leaf.value];
    const std::uint32_t base =
        (value << kValueShift) | (values[value].occupied ? kOccupied : 0u);
    if (leaf.shift == 0) { // a single voxel: most leaves
      std::size_t s;
      if (!bricks.slotOf(leaf.k[0], leaf.k[1], leaf.k[2], s))
        continue;
      const std::uint32_t e = bricks.table[s];
      if (e == (kUniform | base) || e == (kUniform | base | kInRoi))
        continue; // the brick already has this value
      CodeT& c = bricks.materialize(s)[brickLocal(leaf.k[0], leaf.k[1], leaf.k[2])];
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
          CodeT* v = bricks.materialize(s);
          for (int z = v_lo[2]; z <= v_hi[2]; ++z)
            for (int y = v_lo[1]; y <= v_hi[1]; ++y)
              for (int x = v_lo[0]; x <= v_hi[0]; ++x) {
                CodeT& c = v[(z << (2 * kBrickShift)) | (y << kBrickShift) | x];
                c = static_cast<CodeT>(base | (c & kInRoi));
              }
        }
  }
  brick_count = bricks.voxels.size() >> (3 * kBrickShift);
  bricks.shareUniformBricks();
}

void Snapshot::build(const octomap::OcTree& octree, const Roi& roi, bool full_map,
                     bool unknown_only)
{
  built = false;
  tree = &octree;
  lattice = VoxelLattice(tree->getResolution());
  const double resolution = lattice.resolution();
  threshold_ = tree->getOccupancyThresLog();
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

  leaves_.clear();
  distinct_.clear();
  last_key_ = 0;
  hash_keys_.assign(64, 0);
  hash_values_.assign(64, 0);
  if (const octomap::OcTreeNode* root = tree->getRoot()) {
    const int k[3] = {0, 0, 0};
    collect(root, 0, k);
  }
  leaf_count = leaves_.size();

  // Value indices in increasing log-odds (deterministic); 0 is unknown.
  std::vector<float> sorted(distinct_);
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  remap_.resize(distinct_.size());
  for (std::size_t i = 0; i < distinct_.size(); ++i)
    remap_[i] = static_cast<std::uint32_t>(
        std::lower_bound(sorted.begin(), sorted.end(), distinct_[i]) - sorted.begin() +
        1);
  values.assign(sorted.size() + 1, Value());
  values[0].entropy = occupancyEntropy(0.5);
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    const double p = octomap::probability(sorted[i]); // OcTreeNode::getOccupancy()
    Value& v = values[i + 1];
    v.log_odds = sorted[i];
    v.entropy = unknown_only ? 0.0 : occupancyEntropy(p);
    v.free_prob = 1.0 - p;
    v.occupied = sorted[i] > threshold_; // OcTree::isNodeOccupied
  }

  // The region: the ROI's keys, every stored occupied leaf, and the other stored leaves
  // where they matter (within the ROI's keys unless every voxel is needed).
  int lo[3] = {kKeyLimit, kKeyLimit, kKeyLimit}, hi[3] = {-1, -1, -1};
  if (!roi_bbox.empty())
    for (int a = 0; a < 3; ++a) {
      lo[a] = roi_bbox.lo[a];
      hi[a] = roi_bbox.hi[a];
    }
  for (const Leaf& leaf : leaves_) {
    const bool clip = !full && !values[remap_[leaf.value]].occupied;
    for (int a = 0; a < 3; ++a) {
      int l = leaf.k[a], h = leaf.k[a] + (1 << leaf.shift) - 1;
      if (clip) {
        l = std::max(l, roi_bbox.lo[a]);
        h = std::min(h, roi_bbox.hi[a]);
      }
      lo[a] = std::min(lo[a], l);
      hi[a] = std::max(hi[a], h);
    }
  }
  KeyBox region;
  for (int a = 0; a < 3; ++a) {
    region.lo[a] = lo[a];
    region.hi[a] = hi[a];
  }
  if (region.empty()) // nothing known and no ROI voxel: one brick
    for (int a = 0; a < 3; ++a)
      region.lo[a] = region.hi[a] = VoxelLattice::kKeyOffset;

  const std::size_t max_code = (values.size() - 1) << kValueShift | kOccupied | kInRoi;
  code_bytes = max_code <= 0xffu ? 1 : (max_code <= 0xffffu ? 2 : 4);
  bricks8.clear();
  bricks16.clear();
  bricks32.clear();
  if (code_bytes == 1)
    fill(bricks8, region);
  else if (code_bytes == 2)
    fill(bricks16, region);
  else
    fill(bricks32, region);
  built = true;
}

} // namespace gain_detail
} // namespace plantnbv
