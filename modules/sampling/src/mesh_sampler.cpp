#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
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

template <typename Emit>
void MeshSampler::draw(Emit&& emit) const
{
  if (!mesh_)
    throw InvalidArgumentError("MeshSampler: no input mesh set (call setInputMesh)");
  Rng rng(seed_);
  // Rounding can make u reach the total: the last triangle with area takes it then.
  const auto last_with_area = static_cast<std::size_t>(
      std::lower_bound(cumulative_area_.begin(), cumulative_area_.end(), total_area_) -
      cumulative_area_.begin());
  for (std::size_t i = 0; i < n_points_; ++i) {
    const double u = rng.uniform() * total_area_;
    // The first triangle whose cumulative area exceeds u: zero-area ones never qualify.
    const std::size_t t = std::min(triangleAt(u), last_with_area);
    const auto& tri = mesh_->triangles[t];
    const Eigen::Vector3d a = mesh_->vertices[tri[0]].cast<double>();
    const Eigen::Vector3d b = mesh_->vertices[tri[1]].cast<double>();
    const Eigen::Vector3d c = mesh_->vertices[tri[2]].cast<double>();
    // Uniform in the triangle: sqrt warps the first coordinate (Osada et al. 2002).
    const double s = std::sqrt(rng.uniform());
    const double r = rng.uniform();
    emit((1.0 - s) * a + s * (1.0 - r) * b + s * r * c, t);
  }
}

namespace {
template <typename PointT>
void startUnorganized(pcl::PointCloud<PointT>& cloud, std::size_t n)
{
  cloud.clear();
  cloud.reserve(n);
  cloud.is_dense = true;
}
} // namespace

void MeshSampler::sample(CloudXYZ& cloud) const
{
  startUnorganized(cloud, n_points_);
  draw([&](const Eigen::Vector3d& p, std::size_t) {
    cloud.push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                  static_cast<float>(p.z())));
  });
}

void MeshSampler::sample(CloudXYZL& cloud) const
{
  startUnorganized(cloud, n_points_);
  const bool labelled = mesh_ && mesh_->hasLabels();
  draw([&](const Eigen::Vector3d& p, std::size_t t) {
    pcl::PointXYZL q;
    q.x = static_cast<float>(p.x());
    q.y = static_cast<float>(p.y());
    q.z = static_cast<float>(p.z());
    q.label = labelled ? static_cast<std::uint32_t>(mesh_->labels[t]) : 0u;
    cloud.push_back(q);
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
