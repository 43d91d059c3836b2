#pragma once
/// \file morton_kdtree.h
/// \brief An exact nearest-neighbour search for pcl::search: the metrics module's
/// Morton-ordered KD-tree behind the pcl::search::Search interface.

#include <cstddef>
#include <memory>
#include <vector>

#include <pcl/search/search.h>

namespace plantnbv {

namespace detail {
class MortonTree; // modules/metrics/src/morton_tree.h (not installed)

// The non-template core of search::MortonKdTree, compiled once in plantnbv_metrics (with
// the module's floating-point flags); the template only reads the point type.

/// Builds the tree of the finite points of a cloud (x, y, z of point i at x + i *
/// stride_bytes, ...), or of `indices` (may be null) into it.
/// \throws InvalidArgumentError for an index outside [0, cloud_size) or a cloud of
/// more than 2^31 - 1 points.
std::shared_ptr<const MortonTree>
buildMortonTree(const float* x, const float* y, const float* z, std::size_t stride_bytes,
                std::size_t cloud_size, const pcl::Indices* indices, int threads);
/// `tree` may be null (no cloud set): 0 results.
int mortonNearestKSearch(const MortonTree* tree, const float point[3], int k,
                         pcl::Indices& k_indices, std::vector<float>& k_sqr_distances);
int mortonRadiusSearch(const MortonTree* tree, const float point[3], double radius,
                       unsigned int max_nn, bool sorted, pcl::Indices& k_indices,
                       std::vector<float>& k_sqr_distances);
} // namespace detail

namespace search {

/// \brief Exact k-nearest-neighbour and radius search over a point cloud: a KD-tree over
/// the points in Morton (Z-order) order, the same tree (one implementation) that
/// ReconstructionMetrics builds for each of its clouds. Pass it wherever PCL takes a
/// `pcl::search::Search<PointT>::Ptr` (pcl::NormalEstimation::setSearchMethod,
/// pcl::EuclideanClusterExtraction::setSearchMethod, ...), in place of
/// pcl::search::KdTree. PCL 1.13's registration (ICP, CorrespondenceEstimation) takes a
/// pcl::search::KdTree::Ptr instead, so it cannot use this class.
///
/// **Tree.** 48-bit Morton keys (16 bits per axis over the cubic bounding box), a stable
/// radix sort, then a binary radix tree (Karras 2012) that splits every range at the
/// highest differing key bit (a midpoint split cycling the axes); each node stores the
/// tight float boxes of its two children; leaves hold at most 64 points. The finite
/// points are copied into the tree (about 18 bytes per point); the cloud is not read
/// again, so changing it has no effect until setInputCloud() is called again. Building
/// costs O(n) after the O(n) radix sort, in parallel for clouds of 32k points and more
/// (setNumberOfThreads()); figures in docs/performance.md.
///
/// **Exact.** Every squared distance is dx * dx + dy * dy + dz * dz computed in double
/// from the float coordinates (no fused multiply-add), and pruning never drops a
/// candidate: results are those of a brute-force scan with the same arithmetic. The
/// distances are returned as float, as PCL's interface requires (the double value
/// rounded to nearest). pcl::search::KdTree (FLANN) computes them in float, so on general
/// data its distances can differ from ours in the last bits; on data where float
/// arithmetic is exact (coordinates on a dyadic grid) they are equal.
///
/// **Ties** are broken by cloud index: neighbours are ordered by their exact (double)
/// squared distance, then by their index in the cloud; the k nearest are the first k in
/// that order, so the result depends on the query alone (not on the order or the thread
/// of queries). A query point that is also a cloud point may find a coincident point
/// with a smaller index before itself.
///
/// **Indices.** setInputCloud(cloud, indices) searches only cloud[indices[i]]; results
/// are always indices into the cloud (as pcl::search::KdTree reports them), and
/// non-finite points are left out (whatever `is_dense` says). The index-based
/// overloads of pcl::search::Search work as documented there: nearestKSearch(i, ...)
/// queries cloud[indices[i]] when indices were given, cloud[i] otherwise.
///
/// **Edge cases** of the point queries (no exception, no assert): a non-finite query
/// point, k <= 0, radius <= 0 or NaN, no cloud set, or a cloud (or index list) without
/// finite points: 0 results and both output vectors empty. k larger than the number of
/// points: all of them. Outputs are resized by the search (no need to size them
/// beforehand). The index overloads are PCL's: they do not check the index (PCL asserts
/// in debug builds).
///
/// Thread safety: after setInputCloud(), every query is const and may run from several
/// threads at once; setInputCloud() and the setters must not run concurrently with
/// queries. Copies share the (immutable) tree.
template <typename PointT>
class MortonKdTree : public pcl::search::Search<PointT> {
  using Base = pcl::search::Search<PointT>;

public:
  using Ptr = std::shared_ptr<MortonKdTree<PointT>>;            ///< shared search
  using ConstPtr = std::shared_ptr<const MortonKdTree<PointT>>; ///< shared, read-only
  using PointCloud = typename Base::PointCloud;                 ///< the searched cloud
  using PointCloudConstPtr = typename Base::PointCloudConstPtr; ///< shared, read-only
  using IndicesConstPtr = typename Base::IndicesConstPtr; ///< indices into the cloud
  // The base class's index and batch overloads (they call the point queries below).
  using Base::nearestKSearch;
  using Base::radiusSearch;

  /// \param[in] sorted whether radiusSearch sorts its results by distance (default true,
  /// as pcl::search::KdTree); nearestKSearch always does.
  explicit MortonKdTree(bool sorted = true) : Base("MortonKdTree", sorted) {}

  /// \brief Builds the tree of the finite points of `cloud`, or of cloud[indices[i]]
  /// when `indices` is given (duplicate indices are searched twice).
  /// \throws InvalidArgumentError if `cloud` is null, an index is outside [0, size), or
  /// the cloud has more than 2^31 - 1 points; the search is then left as it was.
  void setInputCloud(const PointCloudConstPtr& cloud,
                     const IndicesConstPtr& indices = IndicesConstPtr()) override;

  /// \brief The k nearest points to `point`, sorted by squared distance (then index).
  /// \param[in] point the query (x, y, z in the cloud's frame, metres)
  /// \param[in] k how many neighbours; k = 1 takes the fast single-nearest path
  /// \param[out] k_indices their cloud indices (resized to the number found)
  /// \param[out] k_sqr_distances their squared distances (m², resized)
  /// \return the number found: min(k, finite points searched), 0 in the edge cases above
  int nearestKSearch(const PointT& point, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override;

  /// \brief Every point whose squared distance to `point`, as returned (float), is below
  /// radius * radius rounded to float: the strict test of pcl::search::KdTree (FLANN).
  /// \param[in] point the query (metres)
  /// \param[in] radius metres; <= 0 or NaN: 0 results; +infinity: every point
  /// \param[out] k_indices their cloud indices, sorted by distance (then index) when
  /// getSortedResults(), else in tree order
  /// \param[out] k_sqr_distances their squared distances (m²)
  /// \param[in] max_nn if > 0 and below the number of points, only the max_nn nearest
  /// of them (ties by index); 0 (default): all
  /// \return the number found
  int radiusSearch(const PointT& point, double radius, pcl::Indices& k_indices,
                   std::vector<float>& k_sqr_distances,
                   unsigned int max_nn = 0) const override;

  /// \param[in] threads OpenMP threads for building the tree (clouds of 32k points and
  /// more; set it before setInputCloud); 0 (default) = OpenMP's default. The tree and
  /// the results do not depend on it. \throws InvalidArgumentError if negative.
  void setNumberOfThreads(int threads);
  /// \brief The OpenMP threads for building the tree; 0 = OpenMP's default.
  int getNumberOfThreads() const { return threads_; }

private:
  std::shared_ptr<const detail::MortonTree> tree_;
  int threads_ = 0;
};

} // namespace search
} // namespace plantnbv
