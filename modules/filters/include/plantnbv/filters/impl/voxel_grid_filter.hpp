#pragma once
/// \file impl/voxel_grid_filter.hpp
/// \brief Template body of VoxelGridFilter; included by src/voxel_grid_filter.cpp only
/// (and by users who need a point type other than PointXYZ / PointXYZL).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <tuple>
#include <vector>

#include <pcl/common/point_tests.h>
#include <pcl/filters/voxel_grid.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/voxel_lattice.h>
#include <plantnbv/filters/voxel_grid_filter.h>

namespace plantnbv {

namespace detail {

/// True if pcl::VoxelGrid (PCL 1.13, filters/impl/voxel_grid.hpp) can grid the points
/// within [min_p, max_p] at `leaf` without overflowing its int32 voxel indices. It
/// repeats pcl's float arithmetic: its own check, dx = int(span * inv) + 1 per axis with
/// dx * dy * dz <= INT_MAX, is not enough, since the grid it then allocates has
/// floor(max * inv) - floor(min * inv) + 1 cells per axis, up to one more than dx, and it
/// casts floor(p * inv) to int. We allow one more cell per axis than pcl's dx.
inline bool pclVoxelGridFits(const Eigen::Array3f& min_p, const Eigen::Array3f& max_p,
                             float leaf)
{
  const float inv = 1.0f / leaf; // pcl: inverse_leaf_size_ = Ones / leaf_size_, in float
  constexpr double int_max = std::numeric_limits<std::int32_t>::max();
  double cells = 1.0;
  for (int a = 0; a < 3; ++a) {
    const float span = (max_p[a] - min_p[a]) * inv;
    const double lo = std::floor(min_p[a] * inv);
    const double hi = std::floor(max_p[a] * inv);
    if (!std::isfinite(span) || !(std::abs(lo) < int_max) || !(std::abs(hi) < int_max))
      return false;
    cells *= std::max(std::trunc(static_cast<double>(span)) + 2.0, hi - lo + 1.0);
  }
  return cells <= int_max;
}

/// The most frequent label, the smallest on a tie (pcl::VoxelGrid's AccumulatorLabel).
/// \param[in,out] labels the labels of one voxel's points; sorted on return.
inline std::uint32_t majorityLabel(std::vector<std::uint32_t>& labels)
{
  std::sort(labels.begin(), labels.end());
  std::uint32_t best = labels.front();
  std::size_t best_count = 0;
  for (std::size_t i = 0; i < labels.size();) {
    std::size_t j = i + 1;
    while (j < labels.size() && labels[j] == labels[i])
      ++j;
    if (j - i > best_count) { // strict: the smaller label wins a tie
      best = labels[i];
      best_count = j - i;
    }
    i = j;
  }
  return best;
}

/// A point (its position in the index list) and its voxel's sort key.
struct VoxelEntry {
  std::uint64_t key;
  std::uint32_t pos;
};

/// Stable LSD radix sort by key, 11 bits per pass, only as many passes as `max_key`
/// needs (two for a bounding box of up to 4 million voxels).
inline void radixSortByKey(std::vector<VoxelEntry>& entries, std::uint64_t max_key)
{
  constexpr int bits = 11;
  constexpr std::size_t buckets = std::size_t{1} << bits;
  std::vector<VoxelEntry> buffer(entries.size());
  std::vector<std::size_t> count(buckets);
  for (int shift = 0; shift < 64 && (max_key >> shift) != 0; shift += bits) {
    std::fill(count.begin(), count.end(), 0);
    for (const VoxelEntry& e : entries)
      ++count[(e.key >> shift) & (buckets - 1)];
    std::size_t sum = 0;
    for (std::size_t& c : count) {
      const std::size_t c0 = c;
      c = sum;
      sum += c0;
    }
    for (const VoxelEntry& e : entries)
      buffer[count[(e.key >> shift) & (buckets - 1)]++] = e;
    entries.swap(buffer);
  }
}

} // namespace detail

template <typename PointT>
void VoxelGridFilter<PointT>::setLeafSize(double leaf)
{
  const float leaf_f = static_cast<float>(leaf);
  if (!(std::isfinite(leaf) && leaf > 0.0 && std::isfinite(leaf_f) && leaf_f > 0.0f)) {
    std::ostringstream s;
    s << "VoxelGridFilter: leaf size " << leaf
      << " must be finite, > 0 and a finite, non-zero float (metres)";
    throw InvalidArgumentError(s.str());
  }
  leaf_ = leaf;
}

template <typename PointT>
void VoxelGridFilter<PointT>::applyFilter(PointCloud& output)
{
  used_fallback_ = false;
  output.clear(); // width = height = 0
  output.is_dense = true;

  // The finite points, and their bounds as pcl::getMinMax3D computes them. pcl checks
  // finiteness only when the cloud says it is not dense; we always do.
  pcl::Indices finite;
  finite.reserve(this->indices_->size());
  Eigen::Array3f min_p = Eigen::Array3f::Constant(std::numeric_limits<float>::max());
  Eigen::Array3f max_p = Eigen::Array3f::Constant(std::numeric_limits<float>::lowest());
  for (const auto index : *this->indices_) {
    const PointT& p = (*this->input_)[index];
    if (!pcl::isXYZFinite(p))
      continue;
    finite.push_back(index);
    const Eigen::Array3f a(p.x, p.y, p.z);
    min_p = min_p.min(a);
    max_p = max_p.max(a);
  }
  if (finite.empty())
    return;

  if (centres_) {
    applyOwnGrid(finite, output);
    return;
  }
  if (!detail::pclVoxelGridFits(min_p, max_p, static_cast<float>(leaf_))) {
    used_fallback_ = true;
    applyOwnGrid(finite, output);
    return;
  }
  pcl::VoxelGrid<PointT> grid;
  const float leaf_f = static_cast<float>(leaf_);
  grid.setLeafSize(leaf_f, leaf_f, leaf_f);
  grid.setInputCloud(this->input_);
  grid.setIndices(std::make_shared<const pcl::Indices>(std::move(finite)));
  grid.filter(output);
}

template <typename PointT>
void VoxelGridFilter<PointT>::applyOwnGrid(const pcl::Indices& indices,
                                           PointCloud& output) const
{
  using Ijk = std::array<std::int64_t, 3>;
  // The voxel lattice of OctoMap's keys (unbounded indices: the cloud may reach beyond
  // the octree).
  const VoxelLattice lattice(leaf_);
  // Beyond 2^62 the index (and the voxel centre) no longer means anything.
  constexpr double index_limit = 4.611686018427387904e18;
  const auto voxelIndex = [&](float c) {
    const double i = lattice.indexOf(static_cast<double>(c));
    if (!(std::abs(i) < index_limit)) {
      std::ostringstream s;
      s << "VoxelGridFilter: coordinate " << c << " at leaf size " << leaf_
        << " gives a voxel index beyond 2^62";
      throw InvalidArgumentError(s.str());
    }
    return static_cast<std::int64_t>(i);
  };

  const PointCloud& input = *this->input_;
  const std::size_t n = indices.size();
  Ijk lo, hi;
  lo.fill(std::numeric_limits<std::int64_t>::max());
  hi.fill(std::numeric_limits<std::int64_t>::min());
  for (const auto index : indices) {
    const PointT& p = input[index];
    const Ijk v{voxelIndex(p.x), voxelIndex(p.y), voxelIndex(p.z)};
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], v[a]);
      hi[a] = std::max(hi[a], v[a]);
    }
  }

  // The points in voxel order (z, y, x), ties in input order: voxels come out in
  // pcl::VoxelGrid's order and the "first point" of a voxel is well defined. `key` is
  // equal exactly for points of the same voxel.
  std::vector<detail::VoxelEntry> entries(n);
  std::vector<Ijk> ijk; // per point, only where keys cannot be decoded
  const auto nx = static_cast<std::uint64_t>(hi[0] - lo[0] + 1);
  const auto ny = static_cast<std::uint64_t>(hi[1] - lo[1] + 1);
  const double cells = static_cast<double>(hi[0] - lo[0] + 1) *
                       static_cast<double>(hi[1] - lo[1] + 1) *
                       static_cast<double>(hi[2] - lo[2] + 1);
  const bool linear = cells < 0x1p63; // keys then fit in 64 bits
  if (linear) {
    // Usual case: a linear index over the bounding box, then a radix sort.
    std::uint64_t max_key = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const PointT& p = input[indices[k]];
      const std::uint64_t key =
          (static_cast<std::uint64_t>(voxelIndex(p.z) - lo[2]) * ny +
           static_cast<std::uint64_t>(voxelIndex(p.y) - lo[1])) *
              nx +
          static_cast<std::uint64_t>(voxelIndex(p.x) - lo[0]);
      entries[k] = {key, static_cast<std::uint32_t>(k)};
      max_key = std::max(max_key, key);
    }
    detail::radixSortByKey(entries, max_key);
  } else {
    // Extents beyond 2^63 voxels: compare the indices, then number the voxels.
    ijk.resize(n);
    std::vector<std::uint32_t> order(n);
    for (std::size_t k = 0; k < n; ++k) {
      const PointT& p = input[indices[k]];
      ijk[k] = {voxelIndex(p.x), voxelIndex(p.y), voxelIndex(p.z)};
      order[k] = static_cast<std::uint32_t>(k);
    }
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
      return std::tie(ijk[a][2], ijk[a][1], ijk[a][0], a) <
             std::tie(ijk[b][2], ijk[b][1], ijk[b][0], b);
    });
    std::uint64_t rank = 0;
    for (std::size_t k = 0; k < n; ++k) {
      if (k > 0 && ijk[order[k]] != ijk[order[k - 1]])
        ++rank;
      entries[k] = {rank, order[k]};
    }
  }
  const auto voxelOf = [&](const detail::VoxelEntry& e) -> Ijk {
    if (!linear)
      return ijk[e.pos];
    return {static_cast<std::int64_t>(e.key % nx) + lo[0],
            static_cast<std::int64_t>(e.key / nx % ny) + lo[1],
            static_cast<std::int64_t>(e.key / nx / ny) + lo[2]};
  };

  std::size_t voxels = 0;
  for (std::size_t k = 0; k < n; ++k)
    voxels += k == 0 || entries[k].key != entries[k - 1].key;
  output.resize(voxels);

  std::vector<std::uint32_t> labels;
  std::size_t out_index = 0;
  for (std::size_t begin = 0; begin < n; ++out_index) {
    std::size_t end = begin + 1;
    while (end < n && entries[end].key == entries[begin].key)
      ++end;

    PointT& out = output[out_index];
    out = input[indices[entries[begin].pos]]; // other fields: the first point's
    if (centres_) {
      const Ijk v = voxelOf(entries[begin]);
      out.x = static_cast<float>(lattice.indexToCoord(v[0]));
      out.y = static_cast<float>(lattice.indexToCoord(v[1]));
      out.z = static_cast<float>(lattice.indexToCoord(v[2]));
    } else {
      double sx = 0.0, sy = 0.0, sz = 0.0;
      for (std::size_t k = begin; k < end; ++k) {
        const PointT& p = input[indices[entries[k].pos]];
        sx += p.x;
        sy += p.y;
        sz += p.z;
      }
      const double count = static_cast<double>(end - begin);
      out.x = static_cast<float>(sx / count);
      out.y = static_cast<float>(sy / count);
      out.z = static_cast<float>(sz / count);
    }
    if constexpr (pcl::traits::has_label_v<PointT>) {
      labels.clear();
      for (std::size_t k = begin; k < end; ++k)
        labels.push_back(input[indices[entries[k].pos]].label);
      out.label = detail::majorityLabel(labels);
    }
    begin = end;
  }
  output.width = static_cast<std::uint32_t>(output.size());
  output.height = 1;
  output.is_dense = true;
}

} // namespace plantnbv
