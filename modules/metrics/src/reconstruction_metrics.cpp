#include <algorithm>
#include <cmath>
#include <limits>
#include <omp.h>
#include <string>

#include <Eigen/Core>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/metrics/reconstruction_metrics.h>

#include "morton_tree.h"

namespace plantnbv {

using detail::MortonTree;

namespace {

constexpr std::size_t kBlock = MortonTree::kBlockSize; // queries per partial sum
constexpr double kInf = std::numeric_limits<double>::infinity();

/// The tree of a cloud's finite points (the cloud is not kept).
void buildTree(MortonTree& tree, const CloudXYZ& cloud, int threads)
{
  detail::MortonTreeInput input;
  if (!cloud.empty()) {
    input.x = &cloud[0].x;
    input.y = &cloud[0].y;
    input.z = &cloud[0].z;
  }
  input.stride_bytes = sizeof(pcl::PointXYZ);
  input.cloud_size = cloud.size();
  tree.build(input, threads);
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
  targets.nearestOfEach(
      queries, threads,
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
                       std::vector<double>& out, double max_dist = kInf)
{
  out.assign(queries.cloudSize(), std::numeric_limits<double>::quiet_NaN());
  if (targets.size() == 0) {
    for (std::size_t k = 0; k < queries.size(); ++k)
      out[queries.cloudIndex(k)] = kInf;
    return;
  }
  targets.nearestOfEach(
      queries, threads,
      [&](std::size_t, std::size_t begin, std::size_t end, const double* dists) {
        for (std::size_t k = begin; k < end; ++k)
          out[queries.cloudIndex(k)] = dists[k - begin];
      },
      max_dist);
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
  buildTree(impl_->reference, *reference, threadCount());
  impl_->has_reference = true;
}

void ReconstructionMetrics::setReconstruction(const CloudXYZConstPtr& reconstruction)
{
  if (!reconstruction)
    throw InvalidArgumentError("setReconstruction: the reconstruction cloud is null");
  if (!impl_)
    impl_ = std::make_unique<Impl>();
  impl_->has_reconstruction = false;
  buildTree(impl_->reconstruction, *reconstruction, threadCount());
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
  const int threads = threadCount();
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
  computeDistances(reference_to_reconstruction); // checks the clouds
  directedDistances(impl_->reconstruction, impl_->reference, threadCount(),
                    reconstruction_to_reference);
}

void ReconstructionMetrics::computeDistances(
    std::vector<double>& reference_to_reconstruction) const
{
  referenceDistances("computeDistances", kInf, reference_to_reconstruction);
}

void ReconstructionMetrics::computeDistancesBelow(
    double max_distance_m, std::vector<double>& reference_to_reconstruction) const
{
  if (!(max_distance_m > 0.0))
    throw InvalidArgumentError("computeDistancesBelow: max_distance_m = " +
                               std::to_string(max_distance_m) + ", expected > 0");
  referenceDistances("computeDistancesBelow", max_distance_m,
                     reference_to_reconstruction);
}

int ReconstructionMetrics::threadCount() const
{
  return threads_ > 0 ? threads_ : omp_get_max_threads();
}

void ReconstructionMetrics::referenceDistances(
    const char* caller, double max_distance_m,
    std::vector<double>& reference_to_reconstruction) const
{
  requireClouds(impl_ && impl_->has_reference, impl_ && impl_->has_reconstruction,
                caller);
  directedDistances(impl_->reference, impl_->reconstruction, threadCount(),
                    reference_to_reconstruction, max_distance_m);
}

int viewsToReach(const std::vector<double>& curve, double tau)
{
  for (std::size_t i = 0; i < curve.size(); ++i)
    if (curve[i] >= tau) // false for NaN entries and a NaN tau
      return static_cast<int>(i + 1);
  return -1;
}

namespace {

/// The bounds of the finite points; false when there is none.
bool finiteBounds(const CloudXYZ& cloud, Eigen::Array3d& lo, Eigen::Array3d& hi)
{
  lo.setConstant(std::numeric_limits<double>::infinity());
  hi.setConstant(-std::numeric_limits<double>::infinity());
  bool any = false;
  for (const pcl::PointXYZ& p : cloud)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) {
      const Eigen::Array3d q(p.x, p.y, p.z);
      lo = lo.min(q);
      hi = hi.max(q);
      any = true;
    }
  return any;
}

} // namespace

double boundingBoxOverlap(const CloudXYZ& a, const CloudXYZ& b, double margin_m)
{
  if (!(margin_m >= 0.0) || !std::isfinite(margin_m))
    throw InvalidArgumentError("boundingBoxOverlap: margin " + std::to_string(margin_m) +
                               " must be a finite distance >= 0 (metres)");
  Eigen::Array3d a_lo, a_hi, b_lo, b_hi;
  if (!finiteBounds(a, a_lo, a_hi) || !finiteBounds(b, b_lo, b_hi))
    return 0.0;
  a_lo -= margin_m, a_hi += margin_m, b_lo -= margin_m, b_hi += margin_m;
  const Eigen::Array3d common = (a_hi.min(b_hi) - a_lo.max(b_lo)).max(0.0);
  const double smaller = std::min((a_hi - a_lo).prod(), (b_hi - b_lo).prod());
  return smaller > 0.0 ? std::min(1.0, common.prod() / smaller) : 0.0;
}

} // namespace plantnbv
