// The non-template core of search::MortonKdTree, and the template compiled once for the
// point types plantnbv uses (PCL's precompile scheme): users of these types include
// only morton_kdtree.h.
#include <cmath>
#include <cstdint>
#include <limits>
#include <omp.h>
#include <string>
#include <type_traits>

#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/metrics/impl/morton_kdtree.hpp>

#include "morton_tree.h"

namespace plantnbv {
namespace detail {

static_assert(std::is_same<pcl::index_t, std::int32_t>::value,
              "MortonTreeInput reads the indices as int32 (PCL_INDEX_SIZE 32)");

namespace {

constexpr float kFloatInf = std::numeric_limits<float>::infinity();

bool isFinite(const float p[3])
{
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

int noResult(pcl::Indices& k_indices, std::vector<float>& k_sqr_distances)
{
  k_indices.clear();
  k_sqr_distances.clear();
  return 0;
}

int copyOut(const std::vector<MortonTree::Neighbor>& found, pcl::Indices& k_indices,
            std::vector<float>& k_sqr_distances)
{
  k_indices.resize(found.size());
  k_sqr_distances.resize(found.size());
  for (std::size_t i = 0; i < found.size(); ++i) {
    k_indices[i] = static_cast<pcl::index_t>(found[i].index);
    k_sqr_distances[i] = static_cast<float>(found[i].sqr_dist);
  }
  return static_cast<int>(found.size());
}

/// Per-thread buffer of the k > 1 and radius searches (no allocation once warm).
std::vector<MortonTree::Neighbor>& scratch()
{
  thread_local std::vector<MortonTree::Neighbor> buffer;
  return buffer;
}

} // namespace

std::shared_ptr<const MortonTree>
buildMortonTree(const float* x, const float* y, const float* z, std::size_t stride_bytes,
                std::size_t cloud_size, const pcl::Indices* indices, int threads)
{
  constexpr auto kMaxPoints =
      static_cast<std::size_t>(std::numeric_limits<pcl::index_t>::max());
  if (cloud_size > kMaxPoints)
    throw InvalidArgumentError("MortonKdTree::setInputCloud: a cloud of " +
                               std::to_string(cloud_size) +
                               " points is too large (at most 2147483647)");
  MortonTreeInput input;
  input.x = x;
  input.y = y;
  input.z = z;
  input.stride_bytes = stride_bytes;
  input.cloud_size = cloud_size;
  if (indices) {
    for (std::size_t j = 0; j < indices->size(); ++j) {
      const pcl::index_t i = (*indices)[j];
      if (i < 0 || static_cast<std::size_t>(i) >= cloud_size)
        throw InvalidArgumentError("MortonKdTree::setInputCloud: indices[" +
                                   std::to_string(j) + "] = " + std::to_string(i) +
                                   ", expected an index in [0, " +
                                   std::to_string(cloud_size) + ")");
    }
    input.has_indices = true;
    input.indices = indices->data();
    input.num_indices = indices->size();
  }
  auto tree = std::make_shared<MortonTree>();
  tree->build(input, threads > 0 ? threads : omp_get_max_threads());
  return tree;
}

int mortonNearestKSearch(const MortonTree* tree, const float point[3], int k,
                         pcl::Indices& k_indices, std::vector<float>& k_sqr_distances)
{
  if (!tree || tree->size() == 0 || k <= 0 || !isFinite(point))
    return noResult(k_indices, k_sqr_distances);
  const double q[3] = {point[0], point[1], point[2]};
  if (k == 1) { // the fast path: one nearest point, no heap
    MortonTree::Neighbor nearest;
    tree->nearest(q, nearest);
    k_indices.resize(1);
    k_sqr_distances.resize(1);
    k_indices[0] = static_cast<pcl::index_t>(nearest.index);
    k_sqr_distances[0] = static_cast<float>(nearest.sqr_dist);
    return 1;
  }
  std::vector<MortonTree::Neighbor>& found = scratch();
  tree->nearestK(q, static_cast<std::size_t>(k), kFloatInf, found);
  return copyOut(found, k_indices, k_sqr_distances);
}

int mortonRadiusSearch(const MortonTree* tree, const float point[3], double radius,
                       unsigned int max_nn, bool sorted, pcl::Indices& k_indices,
                       std::vector<float>& k_sqr_distances)
{
  if (!tree || tree->size() == 0 || !(radius > 0.0) || !isFinite(point))
    return noResult(k_indices, k_sqr_distances);
  const double q[3] = {point[0], point[1], point[2]};
  // As pcl::KdTreeFLANN: the squared radius in double, rounded to float.
  const auto sqr_limit = static_cast<float>(radius * radius);
  std::vector<MortonTree::Neighbor>& found = scratch();
  if (max_nn > 0 && max_nn < tree->size())
    tree->nearestK(q, max_nn, sqr_limit, found); // sorted
  else
    tree->withinRadius(q, sqr_limit, sorted, found);
  return copyOut(found, k_indices, k_sqr_distances);
}

} // namespace detail
} // namespace plantnbv

template class plantnbv::search::MortonKdTree<pcl::PointXYZ>;
template class plantnbv::search::MortonKdTree<pcl::PointXYZL>;
