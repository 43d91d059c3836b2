#include "morton_tree.h"

#include <algorithm>
#include <cmath>
#include <omp.h>
#include <string>

#include <plantnbv/common/error.h>

// The leaf scan and the box test are the inner loop of every search.
#if defined(__GNUC__)
#define PLANTNBV_HOT_INLINE inline __attribute__((always_inline))
#else
#define PLANTNBV_HOT_INLINE inline
#endif

#if defined(__SSE2__) && !defined(PLANTNBV_METRICS_NO_SIMD)
#include <emmintrin.h>
#define PLANTNBV_METRICS_SSE2 1
#endif

namespace plantnbv {
namespace detail {

namespace {

constexpr std::uint32_t kLeafSize = 64; // points per leaf at most
constexpr double kKeyMax = 65535.0;     // 16 bits per axis, 48-bit Morton keys
constexpr std::uint32_t kNoSplit = 64;  // split bit of a node whose keys are all equal
constexpr std::size_t kBlock = MortonTree::kBlockSize;
constexpr std::size_t kParallelBuildMin = 32768; // smaller clouds build on one thread
// Tree depth <= 48 key bits + 32 halvings of equal keys; one stack entry per level.
constexpr int kMaxDepth = 96;
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Spreads the low 16 bits of v to every third bit (Morton interleaving).
inline std::uint64_t spreadBits(std::uint64_t v)
{
  v &= 0xffff;
  v = (v | (v << 16)) & 0x0000ff0000ffULL;
  v = (v | (v << 8)) & 0x00f00f00f00fULL;
  v = (v | (v << 4)) & 0x0c30c30c30c3ULL;
  v = (v | (v << 2)) & 0x249249249249ULL;
  return v;
}

inline int highestBit(std::uint64_t v)
{
  return 63 - __builtin_clzll(v);
}

/// (squared distance, cloud index) in lexicographic order: how ties are broken.
inline bool before(const MortonTree::Neighbor& a, const MortonTree::Neighbor& b)
{
  return a.sqr_dist < b.sqr_dist || (a.sqr_dist == b.sqr_dist && a.index < b.index);
}

#ifdef PLANTNBV_METRICS_SSE2
inline __m128d loadFloatPair(const float* p)
{
  return _mm_cvtps_pd(
      _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))));
}
#endif

} // namespace

/// Per-thread query state of nearestOfEach(): the seed (nearest point of the previous
/// query) and the path from the root to the subtree the previous query started in.
struct MortonTree::Cursor {
  std::uint32_t seed = kNone;
  int depth = -1;
  std::uint32_t node[kMaxDepth];
  std::uint32_t shift[kMaxDepth]; ///< the node's cell: keys equal above this bit
};

inline std::uint32_t MortonTree::quantize(double v, int axis) const
{
  const double t = (v - lo_[axis]) * scale_;
  if (!(t > 0.0))
    return 0;
  return t >= kKeyMax ? 0xffff : static_cast<std::uint32_t>(t);
}

inline double MortonTree::sqrDist(const double q[3], std::uint32_t k) const
{
  const double dx = q[0] - double(xs_[k]);
  const double dy = q[1] - double(ys_[k]);
  const double dz = q[2] - double(zs_[k]);
  return dx * dx + dy * dy + dz * dz;
}

void MortonTree::build(const MortonTreeInput& input, int threads)
{
  cloud_size_ = input.cloud_size;
  // The points to use: positions j of the index list (or of the cloud).
  const std::size_t m = input.has_indices ? input.num_indices : input.cloud_size;
  if (cloud_size_ >= kNone || m >= kNone)
    throw InvalidArgumentError("a cloud of " + std::to_string(std::max(cloud_size_, m)) +
                               " points is too large (at most 4294967294)");
  nodes_.clear();
  node_keys_.clear();
  root_count_ = 0;
  const auto cloudIndexAt = [&input](std::size_t j) -> std::size_t {
    return input.has_indices ? static_cast<std::size_t>(input.indices[j]) : j;
  };
  const auto coordinate = [&input](const float* base, std::size_t i) {
    return *reinterpret_cast<const float*>(reinterpret_cast<const char*>(base) +
                                           i * input.stride_bytes);
  };
  // Point j of the list: its cloud index and coordinates; false if not finite.
  const auto finitePoint = [&](std::size_t j, std::size_t& i, float& x, float& y,
                               float& z) {
    i = cloudIndexAt(j);
    x = coordinate(input.x, i);
    y = coordinate(input.y, i);
    z = coordinate(input.z, i);
    return std::isfinite(x) && std::isfinite(y) && std::isfinite(z);
  };
  // Fixed chunks (not per thread), so that the team size cannot change the order.
  const int chunks = m < kParallelBuildMin ? 1 : std::max(threads, 1);
  const auto chunkBegin = [chunks](long long c, std::size_t n) {
    return n * static_cast<std::size_t>(c) / static_cast<std::size_t>(chunks);
  };

  // Finite points and bounds, per chunk.
  std::vector<std::size_t> first(chunks + 1, 0);
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> bounds(6 * chunks);
#pragma omp parallel for num_threads(chunks) schedule(static, 1)
  for (long long c = 0; c < chunks; ++c) {
    float lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
    std::size_t count = 0;
    for (std::size_t j = chunkBegin(c, m); j < chunkBegin(c + 1, m); ++j) {
      std::size_t i;
      float x, y, z;
      if (!finitePoint(j, i, x, y, z))
        continue;
      ++count;
      lo[0] = std::min(lo[0], x);
      lo[1] = std::min(lo[1], y);
      lo[2] = std::min(lo[2], z);
      hi[0] = std::max(hi[0], x);
      hi[1] = std::max(hi[1], y);
      hi[2] = std::max(hi[2], z);
    }
    first[c + 1] = count;
    std::copy(lo, lo + 3, &bounds[6 * c]);
    std::copy(hi, hi + 3, &bounds[6 * c + 3]);
  }
  float lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
  for (int c = 0; c < chunks; ++c) {
    first[c + 1] += first[c];
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], bounds[6 * c + a]);
      hi[a] = std::max(hi[a], bounds[6 * c + 3 + a]);
    }
  }
  n_ = first[chunks];
  // Left uninitialised: each chunk touches its own part first (page faults in parallel).
  xs_.reset(new float[n_ + 1]);
  ys_.reset(new float[n_ + 1]);
  zs_.reset(new float[n_ + 1]);
  orig_.reset(new std::uint32_t[n_]);
  xs_[n_] = ys_[n_] = zs_[n_] = std::numeric_limits<float>::quiet_NaN();
  if (n_ == 0)
    return;

  // One cubic frame (the largest extent) keeps Morton cells cubes.
  double extent = 0.0;
  for (int a = 0; a < 3; ++a) {
    lo_[a] = lo[a];
    extent = std::max(extent, double(hi[a]) - double(lo[a]));
  }
  scale_ = extent > 0.0 ? kKeyMax / extent : 0.0;

  // Keys, then a stable LSD radix sort of the 48-bit keys (4 passes of 12 bits), each
  // pass counted and scattered per chunk.
  std::unique_ptr<std::uint64_t[]> keys(new std::uint64_t[n_]),
      keys_tmp(new std::uint64_t[n_]);
  std::unique_ptr<std::uint32_t[]> index(new std::uint32_t[n_]),
      index_tmp(new std::uint32_t[n_]);
  constexpr std::size_t kBuckets = 4096;
  std::vector<std::uint32_t> offsets(chunks * kBuckets);
  bool skip_pass = false;
#pragma omp parallel num_threads(chunks)
  {
#pragma omp for schedule(static, 1)
    for (long long c = 0; c < chunks; ++c) {
      std::size_t k = first[c];
      for (std::size_t j = chunkBegin(c, m); j < chunkBegin(c + 1, m); ++j) {
        std::size_t i;
        float x, y, z;
        if (!finitePoint(j, i, x, y, z))
          continue;
        index[k] = static_cast<std::uint32_t>(i);
        keys[k++] = spreadBits(quantize(x, 0)) | spreadBits(quantize(y, 1)) << 1 |
                    spreadBits(quantize(z, 2)) << 2;
      }
    }
    for (int shift = 0; shift < 48; shift += 12) {
#pragma omp for schedule(static, 1)
      for (long long c = 0; c < chunks; ++c) {
        std::uint32_t* count = &offsets[c * kBuckets];
        std::fill(count, count + kBuckets, 0u);
        for (std::size_t k = chunkBegin(c, n_); k < chunkBegin(c + 1, n_); ++k)
          ++count[(keys[k] >> shift) & 0xfff];
      }
#pragma omp single
      {
        // Bucket by bucket, chunk by chunk: where each chunk writes its keys.
        std::uint32_t sum = 0, largest = 0;
        for (std::size_t b = 0; b < kBuckets; ++b) {
          std::uint32_t bucket = 0;
          for (int c = 0; c < chunks; ++c) {
            const std::uint32_t count = offsets[c * kBuckets + b];
            offsets[c * kBuckets + b] = sum;
            sum += count;
            bucket += count;
          }
          largest = std::max(largest, bucket);
        }
        skip_pass = largest == n_; // one digit value: already in order
      }
      if (!skip_pass) {
#pragma omp for schedule(static, 1)
        for (long long c = 0; c < chunks; ++c) {
          std::uint32_t* offset = &offsets[c * kBuckets];
          for (std::size_t k = chunkBegin(c, n_); k < chunkBegin(c + 1, n_); ++k) {
            const std::uint32_t dst = offset[(keys[k] >> shift) & 0xfff]++;
            keys_tmp[dst] = keys[k];
            index_tmp[dst] = index[k];
          }
        }
#pragma omp single
        {
          keys.swap(keys_tmp);
          index.swap(index_tmp);
        }
      }
    }
#pragma omp for schedule(static)
    for (long long k = 0; k < static_cast<long long>(n_); ++k) {
      const std::size_t i = index[k];
      xs_[k] = coordinate(input.x, i);
      ys_[k] = coordinate(input.y, i);
      zs_[k] = coordinate(input.z, i);
      orig_[k] = index[k];
    }
  }

  if (n_ <= kLeafSize) {
    root_count_ = static_cast<std::uint32_t>(n_);
    return;
  }
  nodes_.reserve(2 * (n_ / kLeafSize + 1));
  node_keys_.reserve(2 * (n_ / kLeafSize + 1));
  float root_lo[3], root_hi[3];
  buildRange(keys.get(), 0, static_cast<std::uint32_t>(n_), root_lo, root_hi, 0);
}

void MortonTree::leafBox(std::uint32_t begin, std::uint32_t end, float lo[3],
                         float hi[3]) const
{
  lo[0] = hi[0] = xs_[begin];
  lo[1] = hi[1] = ys_[begin];
  lo[2] = hi[2] = zs_[begin];
  for (std::uint32_t k = begin + 1; k < end; ++k) {
    lo[0] = std::min(lo[0], xs_[k]);
    lo[1] = std::min(lo[1], ys_[k]);
    lo[2] = std::min(lo[2], zs_[k]);
    hi[0] = std::max(hi[0], xs_[k]);
    hi[1] = std::max(hi[1], ys_[k]);
    hi[2] = std::max(hi[2], zs_[k]);
  }
}

std::uint32_t MortonTree::buildRange(const std::uint64_t* keys, std::uint32_t begin,
                                     std::uint32_t end, float lo[3], float hi[3],
                                     int depth)
{
  // Split at the highest differing bit: the first half is every key with a 0 there.
  // Equal keys (duplicates, or a zero extent) are halved instead.
  const std::uint64_t diff = keys[begin] ^ keys[end - 1];
  std::uint32_t split_bit = kNoSplit, split;
  if (diff == 0)
    split = begin + (end - begin) / 2;
  else {
    split_bit = static_cast<std::uint32_t>(highestBit(diff));
    const std::uint64_t mask = std::uint64_t(1) << split_bit;
    split = static_cast<std::uint32_t>(
        std::partition_point(keys + begin, keys + end,
                             [mask](std::uint64_t k) { return !(k & mask); }) -
        keys);
  }
  if (depth + 2 >= kMaxDepth) // cannot happen with 48-bit keys and < 2^32 points
    throw Error("metrics: search tree deeper than " + std::to_string(kMaxDepth));
  const auto id = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  node_keys_.push_back({keys[begin], split_bit});
  const std::uint32_t range[2][2] = {{begin, split}, {split, end}};
  float child_lo[2][3], child_hi[2][3];
  for (int c = 0; c < 2; ++c) {
    const std::uint32_t count = range[c][1] - range[c][0];
    std::uint32_t child = range[c][0], leaf_count = count;
    if (count <= kLeafSize)
      leafBox(range[c][0], range[c][1], child_lo[c], child_hi[c]);
    else {
      child =
          buildRange(keys, range[c][0], range[c][1], child_lo[c], child_hi[c], depth + 1);
      leaf_count = 0;
    }
    Node& node = nodes_[id]; // not across the recursion: nodes_ may have grown
    node.child[c] = child;
    node.count[c] = leaf_count;
    for (int a = 0; a < 3; ++a) {
      node.lo[a][c] = child_lo[c][a];
      node.hi[a][c] = child_hi[c][a];
    }
  }
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::min(child_lo[0][a], child_lo[1][a]);
    hi[a] = std::max(child_hi[0][a], child_hi[1][a]);
  }
  return id;
}

template <bool kTies>
PLANTNBV_HOT_INLINE void MortonTree::scanLeaf(std::uint32_t begin, std::uint32_t count,
                                              const double q[3], double& best,
                                              std::uint32_t& best_index) const
{
  // Pairs of points; an odd leaf also reads the next point (a real point of the cloud, or
  // the NaN pad, which never compares less or equal), so the minimum stays exact.
  const std::uint32_t end = begin + count;
  // A candidate at distance d and tree position k replaces the best one.
  const auto better = [&](double d, std::uint32_t k) {
    return d < best || (kTies && d == best && orig_[k] < orig_[best_index]);
  };
#ifdef PLANTNBV_METRICS_SSE2
  const __m128d qx = _mm_set1_pd(q[0]), qy = _mm_set1_pd(q[1]), qz = _mm_set1_pd(q[2]);
  __m128d limit = _mm_set1_pd(best);
  for (std::uint32_t k = begin; k < end; k += 2) {
    const __m128d dx = _mm_sub_pd(qx, loadFloatPair(&xs_[k]));
    const __m128d dy = _mm_sub_pd(qy, loadFloatPair(&ys_[k]));
    const __m128d dz = _mm_sub_pd(qz, loadFloatPair(&zs_[k]));
    const __m128d d = _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)),
                                 _mm_mul_pd(dz, dz));
    const int closer =
        _mm_movemask_pd(kTies ? _mm_cmple_pd(d, limit) : _mm_cmplt_pd(d, limit));
    if (closer) {
      double lanes[2];
      _mm_storeu_pd(lanes, d);
      if ((closer & 1) && better(lanes[0], k)) {
        best = lanes[0];
        best_index = k;
      }
      if ((closer & 2) && better(lanes[1], k + 1)) {
        best = lanes[1];
        best_index = k + 1;
      }
      limit = _mm_set1_pd(best);
    }
  }
#else
  for (std::uint32_t k = begin; k < end; ++k) {
    const double d = sqrDist(q, k);
    if (better(d, k)) {
      best = d;
      best_index = k;
    }
  }
#endif
}

PLANTNBV_HOT_INLINE void MortonTree::boxSqrDists(const Node& node, const double q[3],
                                                 double d[2]) const
{
  // Per axis the gap max(lo - q, q - hi, 0): never larger than the gap to a point inside.
#ifdef PLANTNBV_METRICS_SSE2
  const __m128d zero = _mm_setzero_pd();
  __m128d sum = zero;
  for (int a = 0; a < 3; ++a) {
    const __m128d qa = _mm_set1_pd(q[a]);
    const __m128d gap = _mm_max_pd(_mm_max_pd(_mm_sub_pd(loadFloatPair(node.lo[a]), qa),
                                              _mm_sub_pd(qa, loadFloatPair(node.hi[a]))),
                                   zero);
    sum = a == 0 ? _mm_mul_pd(gap, gap) : _mm_add_pd(sum, _mm_mul_pd(gap, gap));
  }
  _mm_storeu_pd(d, sum);
#else
  for (int c = 0; c < 2; ++c) {
    double sum = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double below = double(node.lo[a][c]) - q[a],
                   above = q[a] - double(node.hi[a][c]);
      double gap = below > above ? below : above;
      gap = gap > 0.0 ? gap : 0.0;
      sum = a == 0 ? gap * gap : sum + gap * gap;
    }
    d[c] = sum;
  }
#endif
}

PLANTNBV_HOT_INLINE MortonTree::Subtree
MortonTree::startNode(const double q[3], double best, Cursor& cursor) const
{
  if (cursor.depth < 0) {
    cursor.depth = 0;
    cursor.node[0] = 0;
    cursor.shift[0] = 64; // the root's cell is everything
  }
  if (!(best < kInf))
    return {0, 0};
  // Key range of the ball's bounding box, widened by one key step plus a bound on the
  // rounding of (q +- r - lo) * scale, so that every point nearer than sqrt(best) is in
  // it.
  const double r = std::sqrt(best);
  std::uint64_t key_min = 0, key_max = 0;
  for (int a = 0; a < 3; ++a) {
    const double margin = 1.0 + 8.0 * std::numeric_limits<double>::epsilon() *
                                    (std::abs(q[a]) + r + std::abs(lo_[a])) * scale_;
    const double t_lo = (q[a] - r - lo_[a]) * scale_ - margin;
    const double t_hi = (q[a] + r - lo_[a]) * scale_ + margin;
    // (uint32: converting a double to uint64 takes a branch on x86-64)
    const std::uint32_t k_lo =
        t_lo > 0.0 ? static_cast<std::uint32_t>(std::min(t_lo, kKeyMax)) : 0;
    const std::uint32_t k_hi =
        t_hi > 0.0 ? static_cast<std::uint32_t>(std::min(t_hi, kKeyMax)) : 0;
    key_min |= spreadBits(k_lo) << a;
    key_max |= spreadBits(k_hi) << a;
  }
  // Up: to the deepest node on the path whose cell contains the box.
  int depth = cursor.depth;
  for (; depth > 0; --depth) {
    const std::uint32_t shift = cursor.shift[depth];
    const std::uint64_t cell = node_keys_[cursor.node[depth]].key >> shift;
    if ((key_min >> shift) == cell && (key_max >> shift) == cell)
      break;
  }
  // Down: into the child whose cell contains the box, while there is one.
  std::uint32_t v = cursor.node[depth];
  for (;;) {
    const NodeKey& nk = node_keys_[v];
    const std::uint32_t bit = nk.split_bit;
    if (bit == kNoSplit || (key_min >> bit) != (key_max >> bit) ||
        (key_min >> (bit + 1)) != (nk.key >> (bit + 1)))
      break;
    const int c = static_cast<int>((key_min >> bit) & 1);
    if (nodes_[v].count[c] != 0) { // the box lies in a leaf's cell: that leaf only
      cursor.depth = depth;
      return {nodes_[v].child[c], nodes_[v].count[c]};
    }
    v = nodes_[v].child[c];
    ++depth;
    cursor.node[depth] = v;
    cursor.shift[depth] = bit;
  }
  cursor.depth = depth;
  return {v, 0};
}

template <bool kTies>
void MortonTree::search(std::uint32_t start, const double q[3], double& best_io,
                        std::uint32_t& best_index_io) const
{
  struct Entry {
    std::uint32_t ref, count;
    double sqr_dist;
  };
  // With ties, a subtree at exactly the best distance may hold a smaller cloud index.
  const auto mayHold = [](double box_sqr_dist, double best) {
    return kTies ? box_sqr_dist <= best : box_sqr_dist < best;
  };
  Entry stack[kMaxDepth];
  int top = 0;
  double best = best_io;
  std::uint32_t best_index = best_index_io;
  // The current subtree: a node (count 0) or a leaf's points.
  std::uint32_t ref = start, count = 0;
  for (;;) {
    if (count != 0)
      scanLeaf<kTies>(ref, count, q, best, best_index);
    else {
      const Node& node = nodes_[ref];
      double d[2];
      boxSqrDists(node, q, d);
      const int near = d[1] < d[0];
      const double d_near = near ? d[1] : d[0], d_far = near ? d[0] : d[1];
      if (mayHold(d_near, best)) {
        if (mayHold(d_far, best))
          stack[top++] = {node.child[1 - near], node.count[1 - near], d_far};
        ref = node.child[near];
        count = node.count[near];
        continue;
      }
    }
    // Next: the most recently deferred subtree that can still hold a nearer point.
    while (top > 0 && !mayHold(stack[top - 1].sqr_dist, best))
      --top;
    if (top == 0)
      break;
    --top;
    ref = stack[top].ref;
    count = stack[top].count;
  }
  best_io = best;
  best_index_io = best_index;
}

PLANTNBV_HOT_INLINE double MortonTree::seededNearest(const double q[3], double best,
                                                     std::uint32_t& best_index,
                                                     Cursor& cursor) const
{
  if (root_count_ != 0)
    scanLeaf<false>(0, root_count_, q, best, best_index);
  else if (n_ != 0) {
    const Subtree start = startNode(q, best, cursor);
    if (start.count != 0)
      scanLeaf<false>(start.ref, start.count, q, best, best_index);
    else
      search<false>(start.ref, q, best, best_index);
  }
  return best;
}

PLANTNBV_HOT_INLINE double MortonTree::nearestBelow(const double q[3], double bound,
                                                    std::uint32_t& best_index,
                                                    Cursor& cursor) const
{
  // The previous query's nearest point bounds this one's distance (coherent order).
  best_index = cursor.seed;
  double best = best_index == kNone ? kInf : sqrDist(q, best_index);
  if (!(best < bound)) { // the seed is too far: only nearer points count
    best = bound;
    best_index = kNone;
  }
  best = seededNearest(q, best, best_index, cursor);
  cursor.seed = best_index;
  return best;
}

template <typename Block>
void MortonTree::queryBlocks(const MortonTree& queries, int threads, Block&& block) const
{
  const std::size_t n = queries.size();
  const auto blocks = static_cast<long long>((n + kBlock - 1) / kBlock);
#pragma omp parallel num_threads(threads)
  {
    Cursor cursor;
#pragma omp for schedule(dynamic, 1)
    for (long long b = 0; b < blocks; ++b) {
      const std::size_t begin = static_cast<std::size_t>(b) * kBlock;
      block(static_cast<std::size_t>(b), begin, std::min(n, begin + kBlock), cursor);
    }
  }
}

void MortonTree::nearestOfEach(const MortonTree& queries, int threads,
                               const BlockFn& block, double max_dist) const
{
  // Every squared distance whose root is below max_dist is below this bound (the double
  // after max_dist^2 rounded): the search, which only looks for points strictly nearer
  // than its best, starts from it.
  const double bound = max_dist < kInf ? std::nextafter(max_dist * max_dist, kInf) : kInf;
  queryBlocks(queries, threads,
              [&](std::size_t b, std::size_t begin, std::size_t end, Cursor& cursor) {
                double dists[kBlock];
                for (std::size_t k = begin; k < end; ++k) {
                  const double q[3] = {queries.xs_[k], queries.ys_[k], queries.zs_[k]};
                  std::uint32_t best_index;
                  const double best = nearestBelow(q, bound, best_index, cursor);
                  const double dist = best_index == kNone ? kInf : std::sqrt(best);
                  dists[k - begin] = dist < max_dist ? dist : kInf;
                }
                block(b, begin, end, dists);
              });
}

void MortonTree::nearestSquaredOfEach(const MortonTree& queries, int threads,
                                      const double* bounds, double* out) const
{
  queryBlocks(queries, threads,
              [&](std::size_t, std::size_t begin, std::size_t end, Cursor& cursor) {
                for (std::size_t k = begin; k < end; ++k) {
                  const double q[3] = {queries.xs_[k], queries.ys_[k], queries.zs_[k]};
                  std::uint32_t best_index;
                  out[k] = nearestBelow(q, bounds ? bounds[k] : kInf, best_index, cursor);
                }
              });
}

MortonTreeInput MortonTree::sortedPoints() const
{
  MortonTreeInput input;
  input.x = xs_.get();
  input.y = ys_.get();
  input.z = zs_.get();
  input.stride_bytes = sizeof(float);
  input.cloud_size = n_;
  return input;
}

bool MortonTree::nearest(const double q[3], Neighbor& out) const
{
  if (n_ == 0)
    return false;
  double best = kInf;
  std::uint32_t best_index = kNone;
  if (root_count_ != 0)
    scanLeaf<true>(0, root_count_, q, best, best_index);
  else
    search<true>(0, q, best, best_index);
  out = {best, orig_[best_index]};
  return true;
}

template <typename Keep, typename Leaf>
void MortonTree::visit(const double q[3], Keep&& keep, Leaf&& leaf) const
{
  if (n_ == 0)
    return;
  if (root_count_ != 0) {
    leaf(0u, root_count_);
    return;
  }
  struct Entry {
    std::uint32_t ref, count;
    double sqr_dist;
  };
  Entry stack[kMaxDepth];
  int top = 0;
  std::uint32_t ref = 0, count = 0;
  for (;;) {
    if (count != 0)
      leaf(ref, count);
    else {
      const Node& node = nodes_[ref];
      double d[2];
      boxSqrDists(node, q, d);
      const int near = d[1] < d[0];
      const double d_near = near ? d[1] : d[0], d_far = near ? d[0] : d[1];
      if (keep(d_near)) {
        if (keep(d_far))
          stack[top++] = {node.child[1 - near], node.count[1 - near], d_far};
        ref = node.child[near];
        count = node.count[near];
        continue;
      }
    }
    while (top > 0 && !keep(stack[top - 1].sqr_dist))
      --top;
    if (top == 0)
      break;
    --top;
    ref = stack[top].ref;
    count = stack[top].count;
  }
}

void MortonTree::nearestK(const double q[3], std::size_t k, float sqr_limit,
                          std::vector<Neighbor>& out) const
{
  // A max-heap of the best k so far (its front is the k-th, the one to beat).
  out.clear();
  if (k == 0)
    return;
  const auto heapLess = [](const Neighbor& a, const Neighbor& b) { return before(a, b); };
  // Every point of a subtree is at least its box distance away, and rounding to float
  // is monotone: a subtree is skipped when that bound cannot enter the result.
  const auto keep = [&](double box_sqr_dist) {
    return static_cast<float>(box_sqr_dist) < sqr_limit &&
           (out.size() < k || box_sqr_dist <= out.front().sqr_dist);
  };
  const auto leaf = [&](std::uint32_t begin, std::uint32_t count) {
    for (std::uint32_t p = begin; p < begin + count; ++p) {
      const Neighbor c{sqrDist(q, p), orig_[p]};
      if (!(static_cast<float>(c.sqr_dist) < sqr_limit))
        continue;
      if (out.size() < k) {
        out.push_back(c);
        std::push_heap(out.begin(), out.end(), heapLess);
      } else if (before(c, out.front())) {
        std::pop_heap(out.begin(), out.end(), heapLess);
        out.back() = c;
        std::push_heap(out.begin(), out.end(), heapLess);
      }
    }
  };
  visit(q, keep, leaf);
  std::sort_heap(out.begin(), out.end(), heapLess);
}

void MortonTree::withinRadius(const double q[3], float sqr_limit, bool sorted,
                              std::vector<Neighbor>& out) const
{
  out.clear();
  const auto keep = [sqr_limit](double box_sqr_dist) {
    return static_cast<float>(box_sqr_dist) < sqr_limit;
  };
  const auto leaf = [&](std::uint32_t begin, std::uint32_t count) {
    for (std::uint32_t p = begin; p < begin + count; ++p) {
      const double d = sqrDist(q, p);
      if (static_cast<float>(d) < sqr_limit)
        out.push_back({d, orig_[p]});
    }
  };
  visit(q, keep, leaf);
  if (sorted)
    std::sort(out.begin(), out.end(), before);
}

} // namespace detail
} // namespace plantnbv
