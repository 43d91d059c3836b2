#pragma once
/// \file impl/morton_kdtree.hpp
/// \brief Template body of search::MortonKdTree; included by src/morton_kdtree.cpp only
/// (and by users who need a point type other than PointXYZ / PointXYZL: any type with
/// float x, y, z members).

#include <string>

#include <plantnbv/common/error.h>
#include <plantnbv/metrics/morton_kdtree.h>

namespace plantnbv {
namespace search {

template <typename PointT>
void MortonKdTree<PointT>::setInputCloud(const PointCloudConstPtr& cloud,
                                         const IndicesConstPtr& indices)
{
  if (!cloud)
    throw InvalidArgumentError("MortonKdTree::setInputCloud: the cloud is null");
  const PointT* first = cloud->empty() ? nullptr : &(*cloud)[0];
  tree_ =
      detail::buildMortonTree(first ? &first->x : nullptr, first ? &first->y : nullptr,
                              first ? &first->z : nullptr, sizeof(PointT), cloud->size(),
                              indices.get(), threads_);
  this->input_ = cloud;
  this->indices_ = indices;
}

template <typename PointT>
int MortonKdTree<PointT>::nearestKSearch(const PointT& point, int k,
                                         pcl::Indices& k_indices,
                                         std::vector<float>& k_sqr_distances) const
{
  const float q[3] = {point.x, point.y, point.z};
  return detail::mortonNearestKSearch(tree_.get(), q, k, k_indices, k_sqr_distances);
}

template <typename PointT>
int MortonKdTree<PointT>::radiusSearch(const PointT& point, double radius,
                                       pcl::Indices& k_indices,
                                       std::vector<float>& k_sqr_distances,
                                       unsigned int max_nn) const
{
  const float q[3] = {point.x, point.y, point.z};
  return detail::mortonRadiusSearch(tree_.get(), q, radius, max_nn, this->sorted_results_,
                                    k_indices, k_sqr_distances);
}

template <typename PointT>
void MortonKdTree<PointT>::setNumberOfThreads(int threads)
{
  if (threads < 0)
    throw InvalidArgumentError(
        "MortonKdTree::setNumberOfThreads: " + std::to_string(threads) +
        " threads, expected >= 0 (0 = OpenMP's default)");
  threads_ = threads;
}

} // namespace search
} // namespace plantnbv
