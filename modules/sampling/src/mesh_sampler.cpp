#include <algorithm>
#include <cmath>
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
  const auto first = cumulative_area_.begin();
  // Rounding can make u reach the total: the last triangle with area takes it then.
  const auto last_with_area =
      std::lower_bound(first, cumulative_area_.end(), total_area_);
  for (std::size_t i = 0; i < n_points_; ++i) {
    const double u = rng.uniform() * total_area_;
    // The first triangle whose cumulative area exceeds u: zero-area ones never qualify.
    auto it = std::upper_bound(first, cumulative_area_.end(), u);
    if (it > last_with_area)
      it = last_with_area;
    const auto t = static_cast<std::size_t>(it - first);
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
