#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <omp.h>
#include <string>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/metrics/reconstruction_metrics.h>

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

namespace {

constexpr std::uint32_t kLeafSize = 64; // points per leaf at most
constexpr double kKeyMax = 65535.0;     // 16 bits per axis, 48-bit Morton keys
constexpr std::uint32_t kNoSplit = 64;  // split bit of a node whose keys are all equal
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr std::size_t kBlock = 1024; // queries per work item and per partial sum
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

/// Per-thread query state: the seed (nearest point of the previous query) and the path
/// from the root to the subtree the previous query started in.
struct Cursor {
  std::uint32_t seed = kNone;
  int depth = -1;
  std::uint32_t node[kMaxDepth];
  std::uint32_t shift[kMaxDepth]; ///< the node's cell: keys equal above this bit
};

/// \brief Exact nearest-neighbour search over the finite points of one cloud.
///
/// The points are sorted by 48-bit Morton key (16 bits per axis over the cubic bounding
/// box). A binary radix tree over the sorted keys (Karras 2012) splits every range at
/// the highest key bit that differs, so each node is the set of all points of one
/// Morton cell; nodes store the tight float boxes of both children for pruning.
/// A query starts from the smallest cell that contains its search ball (found by walking
/// up and down from the previous query's cell), then runs a nearest-child-first
/// depth-first search with box pruning. Box distances are lower bounds of the computed
/// point distances (same operations on smaller per-axis gaps, monotone rounding), so
/// pruning is exact.
class MortonTree {
public:
  /// \param[in] threads at least 1
  void build(const CloudXYZ& cloud, int threads);

  std::size_t size() const { return n_; }
  std::size_t cloudSize() const { return cloud_size_; }
  std::uint32_t cloudIndex(std::size_t k) const { return orig_[k]; }
  void point(std::size_t k, double q[3]) const
  {
    q[0] = xs_[k];
    q[1] = ys_[k];
    q[2] = zs_[k];
  }

  /// Squared distance from q to the nearest point; `best` (a squared distance) and
  /// `best_index` hold a known candidate on entry (or kInf and kNone).
  double nearest(const double q[3], double best, std::uint32_t& best_index,
                 Cursor& cursor) const;

  double sqrDist(const double q[3], std::uint32_t k) const
  {
    const double dx = q[0] - double(xs_[k]);
    const double dy = q[1] - double(ys_[k]);
    const double dz = q[2] - double(zs_[k]);
    return dx * dx + dy * dy + dz * dz;
  }

private:
  /// Both children of an internal node: boxes as float pairs (one lane per child), and
  /// for each child either a node index (count 0) or a leaf's first point and count.
  struct alignas(64) Node {
    float lo[3][2];
    float hi[3][2];
    std::uint32_t child[2];
    std::uint32_t count[2];
  };
  struct NodeKey {
    std::uint64_t key;       ///< the Morton key of the node's first point
    std::uint32_t split_bit; ///< the highest bit in which its keys differ, or kNoSplit
  };

  std::uint32_t quantize(double v, int axis) const
  {
    const double t = (v - lo_[axis]) * scale_;
    if (!(t > 0.0))
      return 0;
    return t >= kKeyMax ? 0xffff : static_cast<std::uint32_t>(t);
  }
  std::uint32_t buildRange(const std::uint64_t* keys, std::uint32_t begin,
                           std::uint32_t end, float lo[3], float hi[3], int depth);
  void leafBox(std::uint32_t begin, std::uint32_t end, float lo[3], float hi[3]) const;
  void scanLeaf(std::uint32_t begin, std::uint32_t count, const double q[3], double& best,
                std::uint32_t& best_index) const;
  void boxSqrDists(const Node& node, const double q[3], double d[2]) const;
  /// The smallest subtree whose cell holds every point nearer than sqrt(best): a node
  /// (count 0) or a leaf's points.
  struct Subtree {
    std::uint32_t ref, count;
  };
  Subtree startNode(const double q[3], double best, Cursor& cursor) const;
  void search(std::uint32_t start, const double q[3], double& best,
              std::uint32_t& best_index) const;

  std::size_t n_ = 0, cloud_size_ = 0;
  std::uint32_t root_count_ = 0; ///< n_ when the whole tree is one leaf, else 0
  double lo_[3] = {0.0, 0.0, 0.0};
  double scale_ = 0.0;
  std::unique_ptr<float[]> xs_, ys_, zs_; ///< sorted points and one NaN pad (pair scans)
  std::unique_ptr<std::uint32_t[]> orig_; ///< cloud index of each sorted point
  std::vector<Node> nodes_;
  std::vector<NodeKey> node_keys_;
};

void MortonTree::build(const CloudXYZ& cloud, int threads)
{
  cloud_size_ = cloud.size();
  if (cloud_size_ >= kNone)
    throw InvalidArgumentError("a cloud of " + std::to_string(cloud_size_) +
                               " points is too large (at most 4294967294)");
  nodes_.clear();
  node_keys_.clear();
  root_count_ = 0;
  // Fixed chunks (not per thread), so that the team size cannot change the order.
  const int chunks = cloud_size_ < kParallelBuildMin ? 1 : std::max(threads, 1);
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
    for (std::size_t i = chunkBegin(c, cloud_size_); i < chunkBegin(c + 1, cloud_size_);
         ++i) {
      const auto& p = cloud[i];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        continue;
      ++count;
      lo[0] = std::min(lo[0], p.x);
      lo[1] = std::min(lo[1], p.y);
      lo[2] = std::min(lo[2], p.z);
      hi[0] = std::max(hi[0], p.x);
      hi[1] = std::max(hi[1], p.y);
      hi[2] = std::max(hi[2], p.z);
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
      for (std::size_t i = chunkBegin(c, cloud_size_); i < chunkBegin(c + 1, cloud_size_);
           ++i) {
        const auto& p = cloud[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
          continue;
        index[k] = static_cast<std::uint32_t>(i);
        keys[k++] = spreadBits(quantize(p.x, 0)) | spreadBits(quantize(p.y, 1)) << 1 |
                    spreadBits(quantize(p.z, 2)) << 2;
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
      const auto& p = cloud[index[k]];
      xs_[k] = p.x;
      ys_[k] = p.y;
      zs_[k] = p.z;
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

#ifdef PLANTNBV_METRICS_SSE2
inline __m128d loadFloatPair(const float* p)
{
  return _mm_cvtps_pd(
      _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))));
}
#endif

PLANTNBV_HOT_INLINE void MortonTree::scanLeaf(std::uint32_t begin, std::uint32_t count,
                                              const double q[3], double& best,
                                              std::uint32_t& best_index) const
{
  // Pairs of points; an odd leaf also reads the next point (a real point of the cloud, or
  // the NaN pad, which never compares less), so the minimum stays exact.
  const std::uint32_t end = begin + count;
#ifdef PLANTNBV_METRICS_SSE2
  const __m128d qx = _mm_set1_pd(q[0]), qy = _mm_set1_pd(q[1]), qz = _mm_set1_pd(q[2]);
  __m128d limit = _mm_set1_pd(best);
  for (std::uint32_t k = begin; k < end; k += 2) {
    const __m128d dx = _mm_sub_pd(qx, loadFloatPair(&xs_[k]));
    const __m128d dy = _mm_sub_pd(qy, loadFloatPair(&ys_[k]));
    const __m128d dz = _mm_sub_pd(qz, loadFloatPair(&zs_[k]));
    const __m128d d = _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)),
                                 _mm_mul_pd(dz, dz));
    const int closer = _mm_movemask_pd(_mm_cmplt_pd(d, limit));
    if (closer) {
      double lanes[2];
      _mm_storeu_pd(lanes, d);
      if ((closer & 1) && lanes[0] < best) {
        best = lanes[0];
        best_index = k;
      }
      if ((closer & 2) && lanes[1] < best) {
        best = lanes[1];
        best_index = k + 1;
      }
      limit = _mm_set1_pd(best);
    }
  }
#else
  for (std::uint32_t k = begin; k < end; ++k) {
    const double d = sqrDist(q, k);
    if (d < best) {
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

void MortonTree::search(std::uint32_t start, const double q[3], double& best_io,
                        std::uint32_t& best_index_io) const
{
  struct Entry {
    std::uint32_t ref, count;
    double sqr_dist;
  };
  Entry stack[kMaxDepth];
  int top = 0;
  double best = best_io;
  std::uint32_t best_index = best_index_io;
  // The current subtree: a node (count 0) or a leaf's points.
  std::uint32_t ref = start, count = 0;
  for (;;) {
    if (count != 0)
      scanLeaf(ref, count, q, best, best_index);
    else {
      const Node& node = nodes_[ref];
      double d[2];
      boxSqrDists(node, q, d);
      const int near = d[1] < d[0];
      const double d_near = near ? d[1] : d[0], d_far = near ? d[0] : d[1];
      if (d_near < best) {
        if (d_far < best)
          stack[top++] = {node.child[1 - near], node.count[1 - near], d_far};
        ref = node.child[near];
        count = node.count[near];
        continue;
      }
    }
    // Next: the most recently deferred subtree that can still hold a nearer point.
    while (top > 0 && stack[top - 1].sqr_dist >= best)
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

PLANTNBV_HOT_INLINE double MortonTree::nearest(const double q[3], double best,
                                               std::uint32_t& best_index,
                                               Cursor& cursor) const
{
  if (root_count_ != 0)
    scanLeaf(0, root_count_, q, best, best_index);
  else if (n_ != 0) {
    const Subtree start = startNode(q, best, cursor);
    if (start.count != 0)
      scanLeaf(start.ref, start.count, q, best, best_index);
    else
      search(start.ref, q, best, best_index);
  }
  return best;
}

/// Finds the nearest target point of every finite query point, in tree order and in
/// blocks of kBlock queries; block(b, begin, end, dists) gets the distances of queries
/// [begin, end) in that order.
template <typename Block>
void searchAll(const MortonTree& queries, const MortonTree& targets, int threads,
               Block&& block)
{
  const std::size_t n = queries.size();
  const auto blocks = static_cast<long long>((n + kBlock - 1) / kBlock);
#pragma omp parallel num_threads(threads)
  {
    Cursor cursor;
    double dists[kBlock];
#pragma omp for schedule(dynamic, 1)
    for (long long b = 0; b < blocks; ++b) {
      const std::size_t begin = static_cast<std::size_t>(b) * kBlock;
      const std::size_t end = std::min(n, begin + kBlock);
      for (std::size_t k = begin; k < end; ++k) {
        double q[3];
        queries.point(k, q);
        // The previous query's nearest point bounds this one's distance (coherent order).
        std::uint32_t best_index = cursor.seed;
        double best = best_index == kNone ? kInf : targets.sqrDist(q, best_index);
        best = targets.nearest(q, best, best_index, cursor);
        cursor.seed = best_index;
        dists[k - begin] = std::sqrt(best);
      }
      block(static_cast<std::size_t>(b), begin, end, dists);
    }
  }
}

struct DirectedSums {
  double mean = kInf;
  double inlier_share = 0.0;
};

/// Mean distance and share below rho; both trees non-empty.
DirectedSums directedMetrics(const MortonTree& queries, const MortonTree& targets,
                             double rho, int threads)
{
  const std::size_t n = queries.size();
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<double> block_sum(blocks);
  std::vector<std::size_t> block_inliers(blocks);
  searchAll(queries, targets, threads,
            [&](std::size_t b, std::size_t begin, std::size_t end, const double* dists) {
              double sum = 0.0;
              std::size_t inliers = 0;
              for (std::size_t k = 0; k < end - begin; ++k) {
                sum += dists[k];
                inliers += dists[k] < rho;
              }
              block_sum[b] = sum;
              block_inliers[b] = inliers;
            });
  // Fixed blocks summed in block order: the same result for any thread count.
  double sum = 0.0;
  std::size_t inliers = 0;
  for (std::size_t b = 0; b < blocks; ++b) {
    sum += block_sum[b];
    inliers += block_inliers[b];
  }
  DirectedSums out;
  out.mean = sum / static_cast<double>(n);
  out.inlier_share = static_cast<double>(inliers) / static_cast<double>(n);
  return out;
}

void directedDistances(const MortonTree& queries, const MortonTree& targets, int threads,
                       std::vector<double>& out)
{
  out.assign(queries.cloudSize(), std::numeric_limits<double>::quiet_NaN());
  if (targets.size() == 0) {
    for (std::size_t k = 0; k < queries.size(); ++k)
      out[queries.cloudIndex(k)] = kInf;
    return;
  }
  searchAll(queries, targets, threads,
            [&](std::size_t, std::size_t begin, std::size_t end, const double* dists) {
              for (std::size_t k = begin; k < end; ++k)
                out[queries.cloudIndex(k)] = dists[k - begin];
            });
}

} // namespace

struct ReconstructionMetrics::Impl {
  MortonTree reference, reconstruction;
  bool has_reference = false, has_reconstruction = false;
};

ReconstructionMetrics::ReconstructionMetrics() : impl_(std::make_unique<Impl>()) {}
ReconstructionMetrics::~ReconstructionMetrics() = default;
ReconstructionMetrics::ReconstructionMetrics(ReconstructionMetrics&&) noexcept = default;
ReconstructionMetrics&
ReconstructionMetrics::operator=(ReconstructionMetrics&&) noexcept = default;

void ReconstructionMetrics::setReference(const CloudXYZConstPtr& reference)
{
  if (!reference)
    throw InvalidArgumentError("setReference: the reference cloud is null");
  if (!impl_)
    impl_ = std::make_unique<Impl>(); // moved-from object reused
  impl_->has_reference = false;       // stays unset if the build throws
  impl_->reference.build(*reference, threads_ > 0 ? threads_ : omp_get_max_threads());
  impl_->has_reference = true;
}

void ReconstructionMetrics::setReconstruction(const CloudXYZConstPtr& reconstruction)
{
  if (!reconstruction)
    throw InvalidArgumentError("setReconstruction: the reconstruction cloud is null");
  if (!impl_)
    impl_ = std::make_unique<Impl>();
  impl_->has_reconstruction = false;
  impl_->reconstruction.build(*reconstruction,
                              threads_ > 0 ? threads_ : omp_get_max_threads());
  impl_->has_reconstruction = true;
}

void ReconstructionMetrics::setThreshold(double rho)
{
  if (!std::isfinite(rho) || rho <= 0.0)
    throw InvalidArgumentError("setThreshold: rho = " + std::to_string(rho) +
                               " m, expected a finite value > 0");
  rho_ = rho;
}

void ReconstructionMetrics::setNumberOfThreads(int threads)
{
  if (threads < 0)
    throw InvalidArgumentError("setNumberOfThreads: " + std::to_string(threads) +
                               " threads, expected >= 0 (0 = OpenMP's default)");
  threads_ = threads;
}

namespace {
void requireClouds(bool has_reference, bool has_reconstruction, const char* caller)
{
  if (!has_reference)
    throw InvalidArgumentError(std::string(caller) +
                               ": no reference cloud (call setReference first)");
  if (!has_reconstruction)
    throw InvalidArgumentError(
        std::string(caller) + ": no reconstruction cloud (call setReconstruction first)");
}
} // namespace

MetricsResult ReconstructionMetrics::compute() const
{
  requireClouds(impl_ && impl_->has_reference, impl_ && impl_->has_reconstruction,
                "compute");
  const MortonTree& r = impl_->reconstruction;
  const MortonTree& t = impl_->reference;
  const int threads = threads_ > 0 ? threads_ : omp_get_max_threads();
  MetricsResult m;
  m.rho = rho_;
  m.reconstruction_points = r.size();
  m.reference_points = t.size();
  m.valid = r.size() > 0 && t.size() > 0;
  if (!m.valid) {
    m.mean_dist_reconstruction_to_reference = kInf;
    m.mean_dist_reference_to_reconstruction = kInf;
    m.chamfer = kInf;
    return m;
  }
  const DirectedSums accuracy = directedMetrics(r, t, rho_, threads);
  const DirectedSums completeness = directedMetrics(t, r, rho_, threads);
  m.mean_dist_reconstruction_to_reference = accuracy.mean;
  m.mean_dist_reference_to_reconstruction = completeness.mean;
  m.chamfer = accuracy.mean + completeness.mean;
  m.precision = accuracy.inlier_share;
  m.recall = completeness.inlier_share;
  const double pr = m.precision + m.recall;
  m.f1 = pr > 0.0 ? 2.0 * m.precision * m.recall / pr : 0.0;
  return m;
}

void ReconstructionMetrics::computeDistances(
    std::vector<double>& reconstruction_to_reference,
    std::vector<double>& reference_to_reconstruction) const
{
  requireClouds(impl_ && impl_->has_reference, impl_ && impl_->has_reconstruction,
                "computeDistances");
  const int threads = threads_ > 0 ? threads_ : omp_get_max_threads();
  directedDistances(impl_->reconstruction, impl_->reference, threads,
                    reconstruction_to_reference);
  directedDistances(impl_->reference, impl_->reconstruction, threads,
                    reference_to_reconstruction);
}

int viewsToReach(const std::vector<double>& curve, double tau)
{
  for (std::size_t i = 0; i < curve.size(); ++i)
    if (curve[i] >= tau) // false for NaN entries and a NaN tau
      return static_cast<int>(i + 1);
  return -1;
}

} // namespace plantnbv
