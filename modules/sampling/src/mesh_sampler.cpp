#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <omp.h>
#include <string>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/sampling/mesh_sampler.h>

namespace plantnbv {

void MeshSampler::setInputMesh(const MeshConstPtr& mesh)
{
  if (!mesh)
    throw InvalidArgumentError("MeshSampler: the input mesh is null");
  std::vector<double> cumulative(mesh->size());
  double total = 0.0;
  for (std::size_t t = 0; t < mesh->size(); ++t) {
    total += mesh->triangleArea(t);
    cumulative[t] = total;
  }
  if (!(total > 0.0) || !std::isfinite(total))
    throw InvalidArgumentError("MeshSampler: the mesh has " +
                               std::to_string(mesh->size()) +
                               " triangles and a total area of " + std::to_string(total) +
                               " m^2; expected a positive area");
  mesh_ = mesh;
  cumulative_area_ = std::move(cumulative);
  total_area_ = total;
  buildGuide();
}

void MeshSampler::buildGuide()
{
  // As many slices as triangles: a draw's slice holds about one triangle's boundary, so
  // that its search is a compare or two instead of log2(n) jumps across the whole table.
  const std::size_t n = cumulative_area_.size();
  guide_.clear();
  if (n > std::numeric_limits<std::uint32_t>::max())
    return; // draws search the whole table
  const std::size_t slices = n;
  slices_per_m2_ = static_cast<double>(slices) / total_area_;
  if (!std::isfinite(slices_per_m2_))
    return; // an area far below any real mesh's
  guide_.resize(slices + 1);
  std::size_t i = 0;
  for (std::size_t j = 0; j < slices; ++j) {
    const double start = static_cast<double>(j) / slices_per_m2_;
    while (i < n && cumulative_area_[i] <= start)
      ++i;
    guide_[j] = static_cast<std::uint32_t>(i);
  }
  guide_[slices] = static_cast<std::uint32_t>(n);
}

std::size_t MeshSampler::triangleAt(double u) const
{
  // The first triangle whose cumulative area exceeds u, as std::upper_bound over the
  // whole table finds it. The guide narrows the search to u's slice, [lo, hi] (hi: the
  // answer when no triangle of [lo, hi) exceeds u); its ends are checked, so that
  // rounding in the slice's index can only cost a search of the whole table.
  const auto first = cumulative_area_.begin(), last = cumulative_area_.end();
  const std::size_t n = cumulative_area_.size();
  if (!guide_.empty()) {
    const std::size_t slices = guide_.size() - 1;
    const std::size_t j =
        std::min(static_cast<std::size_t>(u * slices_per_m2_), slices - 1);
    const std::size_t lo = guide_[j], hi = guide_[j + 1];
    if ((lo == 0 || cumulative_area_[lo - 1] <= u) &&
        (hi == n || cumulative_area_[hi] > u))
      return static_cast<std::size_t>(
          std::upper_bound(first + static_cast<std::ptrdiff_t>(lo),
                           first + static_cast<std::ptrdiff_t>(hi), u) -
          first);
  }
  return static_cast<std::size_t>(std::upper_bound(first, last, u) - first);
}

void MeshSampler::setNumberOfPoints(std::size_t n)
{
  if (n == 0)
    throw InvalidArgumentError("MeshSampler: the number of points must be > 0");
  n_points_ = n;
}

void MeshSampler::setNumberOfThreads(int threads)
{
  if (threads < 0)
    throw InvalidArgumentError("MeshSampler: thread count must be >= 0, got " +
                               std::to_string(threads));
  threads_ = threads;
}

template <typename Store>
void MeshSampler::draw(Store&& store) const
{
  if (!mesh_)
    throw InvalidArgumentError("MeshSampler: no input mesh set (call setInputMesh)");
  Rng rng(seed_);
  // Rounding can make u reach the total: the last triangle with area takes it then.
  const auto last_with_area = static_cast<std::size_t>(
      std::lower_bound(cumulative_area_.begin(), cumulative_area_.end(), total_area_) -
      cumulative_area_.begin());
  const int threads = threads_ > 0 ? threads_ : omp_get_max_threads();
  // The random numbers are drawn on one thread, three per point in point order, a batch
  // at a time; the points are then made from them on `threads`: the same points for any
  // thread count. Within a batch they are made in increasing u (a counting sort on u's
  // bucket), so that the area table, the guide and the triangles are read front to back
  // instead of at random: the same points, stored at their own index.
  constexpr std::size_t kBatch = std::size_t{1} << 16;
  constexpr std::size_t kBuckets = std::size_t{1} << 12;
  const std::size_t batch = std::min(n_points_, kBatch);
  std::vector<double> draws(3 * batch);
  std::vector<std::uint32_t> order(batch);
  std::vector<std::uint32_t> next_in_bucket(kBuckets + 1); // the sort's next place
  for (std::size_t first = 0; first < n_points_; first += kBatch) {
    const std::size_t count = std::min(kBatch, n_points_ - first);
    for (std::size_t k = 0; k < 3 * count; ++k)
      draws[k] = rng.uniform();
    const auto bucketOf = [&](std::size_t k) {
      return static_cast<std::size_t>(draws[3 * k] * static_cast<double>(kBuckets));
    };
    std::fill(next_in_bucket.begin(), next_in_bucket.end(), 0u);
    for (std::size_t k = 0; k < count; ++k) // sizes, one slot on
      ++next_in_bucket[bucketOf(k) + 1];
    for (std::size_t b = 1; b <= kBuckets; ++b) // each bucket's first place
      next_in_bucket[b] += next_in_bucket[b - 1];
    for (std::size_t k = 0; k < count; ++k)
      order[next_in_bucket[bucketOf(k)]++] = static_cast<std::uint32_t>(k);
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
    for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(count); ++i) {
      const std::size_t k = order[static_cast<std::size_t>(i)];
      const double* d = &draws[3 * k];
      const double u = d[0] * total_area_;
      // The first triangle whose cumulative area exceeds u: zero-area ones never qualify.
      const std::size_t t = std::min(triangleAt(u), last_with_area);
      const auto& tri = mesh_->triangles[t];
      const Eigen::Vector3d a = mesh_->vertices[tri[0]].cast<double>();
      const Eigen::Vector3d b = mesh_->vertices[tri[1]].cast<double>();
      const Eigen::Vector3d c = mesh_->vertices[tri[2]].cast<double>();
      // Uniform in the triangle: sqrt warps the first coordinate (Osada et al. 2002).
      const double s = std::sqrt(d[1]);
      const double r = d[2];
      store(first + k, (1.0 - s) * a + s * (1.0 - r) * b + s * r * c, t);
    }
  }
}

namespace {
template <typename PointT>
void startUnorganized(pcl::PointCloud<PointT>& cloud, std::size_t n)
{
  cloud.clear();
  cloud.resize(n); // width n, height 1
  cloud.is_dense = true;
}
} // namespace

void MeshSampler::sample(CloudXYZ& cloud) const
{
  startUnorganized(cloud, mesh_ ? n_points_ : 0);
  draw([&](std::size_t i, const Eigen::Vector3d& p, std::size_t) {
    cloud[i] = pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                             static_cast<float>(p.z()));
  });
}

void MeshSampler::sample(CloudXYZL& cloud) const
{
  startUnorganized(cloud, mesh_ ? n_points_ : 0);
  const bool labelled = mesh_ && mesh_->hasLabels();
  draw([&](std::size_t i, const Eigen::Vector3d& p, std::size_t t) {
    pcl::PointXYZL& q = cloud[i];
    q.x = static_cast<float>(p.x());
    q.y = static_cast<float>(p.y());
    q.z = static_cast<float>(p.z());
    q.label = labelled ? static_cast<std::uint32_t>(mesh_->labels[t]) : 0u;
  });
}

double sampledCloudMemoryBytes(double points, std::size_t point_bytes)
{
  return points * (2.0 * static_cast<double>(point_bytes) + 16.0);
}

std::size_t groundTruthSampleCount(double area_m2, double resolution)
{
  const double n = std::ceil(8.0 * area_m2 / (resolution * resolution));
  return static_cast<std::size_t>(std::clamp(n, 1e4, 2e7));
}

} // namespace plantnbv
