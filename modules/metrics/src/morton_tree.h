#pragma once
/// \file morton_tree.h
/// \brief Internal (not installed): the exact nearest-neighbour tree of the metrics
/// module, shared by ReconstructionMetrics and search::MortonKdTree.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

namespace plantnbv {
namespace detail {

/// \brief Where MortonTree::build reads the points: x, y and z of cloud point i at
/// `x`, `y`, `z` plus i * stride_bytes (a PCL cloud: &cloud[0].x, ..., sizeof(PointT)).
struct MortonTreeInput {
  const float* x = nullptr;
  const float* y = nullptr;
  const float* z = nullptr;
  std::size_t stride_bytes = 0;
  std::size_t cloud_size = 0;
  /// Whether only the points `indices[0, num_indices)` are used, in this order (each <
  /// cloud_size, checked by the caller); else all of them.
  bool has_indices = false;
  const std::int32_t* indices = nullptr;
  std::size_t num_indices = 0;
};

/// \brief Exact nearest-neighbour search over the finite points of one cloud.
///
/// The points are sorted by 48-bit Morton key (16 bits per axis over the cubic bounding
/// box). A binary radix tree over the sorted keys (Karras 2012) splits every range at
/// the highest key bit that differs, so each node is the set of all points of one
/// Morton cell; nodes store the tight float boxes of both children for pruning.
/// nearestOfEach() runs its queries in their own tree order and starts each from the
/// smallest cell that contains its search ball (found by walking up and down from the
/// previous query's cell), then runs a nearest-child-first depth-first search with box
/// pruning. Box distances are lower bounds of the computed point distances (same
/// operations on smaller per-axis gaps, monotone rounding), so pruning is exact.
///
/// Squared distances are dx * dx + dy * dy + dz * dz in double from the float
/// coordinates (the module is compiled with -ffp-contract=off). Queries are const and
/// thread-safe; build() is not.
class MortonTree {
public:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  /// Queries per block of nearestOfEach().
  static constexpr std::size_t kBlockSize = 1024;

  /// \brief A neighbour: exact squared distance (m²) and cloud index.
  struct Neighbor {
    double sqr_dist;
    std::uint32_t index;
  };

  /// \brief Builds the tree of the finite points of `input` (a copy: the input is not
  /// kept). \param[in] threads at least 1; clouds under 32768 points build on one.
  /// \throws InvalidArgumentError with 2^32 - 1 points or more.
  void build(const MortonTreeInput& input, int threads);

  /// Finite points in the tree.
  std::size_t size() const { return n_; }
  /// Points of the cloud it was built from (input.cloud_size).
  std::size_t cloudSize() const { return cloud_size_; }
  /// The cloud index of the point at tree position k (0 <= k < size()).
  std::uint32_t cloudIndex(std::size_t k) const { return orig_[k]; }
  /// \brief The tree's own points as a build input, in tree order (cloud index =
  /// tree position): a tree of some of them is built with `indices`.
  MortonTreeInput sortedPoints() const;
  /// The coordinates of the point at tree position k (0 <= k < size()).
  void point(std::size_t k, float p[3]) const
  {
    p[0] = xs_[k];
    p[1] = ys_[k];
    p[2] = zs_[k];
  }

  /// \brief For every point of `queries` (in its tree order), the distance (m, not
  /// squared) to the nearest point of this tree, which must not be empty. Blocks of
  /// kBlockSize queries run in parallel; block(b, begin, end, dists) gets the distances
  /// of queries [begin, end) of block b, from the thread that computed them.
  using BlockFn = std::function<void(std::size_t block, std::size_t begin,
                                     std::size_t end, const double* dists)>;
  /// With `max_dist` (> 0), only the distances below it are needed: those are exact,
  /// and every other is +infinity (the search for a point stops at max_dist).
  void nearestOfEach(const MortonTree& queries, int threads, const BlockFn& block,
                     double max_dist = std::numeric_limits<double>::infinity()) const;

  /// \brief For every point of `queries` (in its tree order), out[k] = the smaller of
  /// bounds[k] and the squared distance (m²) to the nearest point of this tree (without
  /// `bounds`: that squared distance; the tree must then not be empty). The search for a
  /// point stops at its bound, so tight bounds are cheap. Parallel as nearestOfEach().
  void nearestSquaredOfEach(const MortonTree& queries, int threads, const double* bounds,
                            double* out) const;

  /// \brief The nearest point to q; ties go to the smallest cloud index.
  /// \return false when the tree is empty.
  bool nearest(const double q[3], Neighbor& out) const;

  /// \brief The k nearest points to q whose squared distance rounded to float is below
  /// sqr_limit (+infinity: no limit), sorted by squared distance then cloud index, into
  /// out (resized). Ties at the k-th distance go to the smallest cloud indices.
  void nearestK(const double q[3], std::size_t k, float sqr_limit,
                std::vector<Neighbor>& out) const;

  /// \brief Every point whose squared distance rounded to float is below sqr_limit,
  /// sorted as nearestK() if `sorted`, else in tree order, into out (resized).
  void withinRadius(const double q[3], float sqr_limit, bool sorted,
                    std::vector<Neighbor>& out) const;

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
  /// A node (count 0) or a leaf's points.
  struct Subtree {
    std::uint32_t ref, count;
  };
  struct Cursor;

  std::uint32_t quantize(double v, int axis) const;
  std::uint32_t buildRange(const std::uint64_t* keys, std::uint32_t begin,
                           std::uint32_t end, float lo[3], float hi[3], int depth);
  void leafBox(std::uint32_t begin, std::uint32_t end, float lo[3], float hi[3]) const;
  double sqrDist(const double q[3], std::uint32_t k) const;
  /// kTies: also take a point at the same distance with a smaller cloud index.
  template <bool kTies>
  void scanLeaf(std::uint32_t begin, std::uint32_t count, const double q[3], double& best,
                std::uint32_t& best_index) const;
  void boxSqrDists(const Node& node, const double q[3], double d[2]) const;
  /// The smallest subtree whose cell holds every point nearer than sqrt(best).
  Subtree startNode(const double q[3], double best, Cursor& cursor) const;
  template <bool kTies>
  void search(std::uint32_t start, const double q[3], double& best,
              std::uint32_t& best_index) const;
  /// Squared distance from q to the nearest point; `best` (a squared distance) and
  /// `best_index` hold a known candidate on entry (or +infinity and kNone).
  double seededNearest(const double q[3], double best, std::uint32_t& best_index,
                       Cursor& cursor) const;
  /// The queries in blocks of kBlockSize (tree order) on `threads` threads:
  /// block(b, begin, end, cursor) with each thread's own cursor.
  template <typename Block>
  void queryBlocks(const MortonTree& queries, int threads, Block&& block) const;
  /// The smaller of `bound` and the squared distance from q to the nearest point,
  /// seeded with the cursor's last nearest point (updated; best_index kNone when no
  /// point lies below the bound).
  double nearestBelow(const double q[3], double bound, std::uint32_t& best_index,
                      Cursor& cursor) const;
  /// Depth-first, nearer child first, from the root: leaf(begin, count) for every leaf
  /// whose box distance passes keep(sqr_dist), re-checked when a deferred child is
  /// resumed.
  template <typename Keep, typename Leaf>
  void visit(const double q[3], Keep&& keep, Leaf&& leaf) const;

  std::size_t n_ = 0, cloud_size_ = 0;
  std::uint32_t root_count_ = 0; ///< n_ when the whole tree is one leaf, else 0
  double lo_[3] = {0.0, 0.0, 0.0};
  double scale_ = 0.0;
  std::unique_ptr<float[]> xs_, ys_, zs_; ///< sorted points and one NaN pad (pair scans)
  std::unique_ptr<std::uint32_t[]> orig_; ///< cloud index of each sorted point
  std::vector<Node> nodes_;
  std::vector<NodeKey> node_keys_;
};

} // namespace detail
} // namespace plantnbv
