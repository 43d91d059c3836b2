#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <mutex>
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
using detail::MortonTreeInput;

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

/// Mean distance and share below rho of squared distances (non-empty), summed in fixed
/// blocks of kBlock, the block sums in block order: the same for any thread count.
DirectedSums directedSums(const std::vector<double>& sqr_dists, double rho, int threads)
{
  const std::size_t n = sqr_dists.size();
  const auto blocks = static_cast<long long>((n + kBlock - 1) / kBlock);
  std::vector<double> block_sum(static_cast<std::size_t>(blocks));
  std::vector<std::size_t> block_inliers(static_cast<std::size_t>(blocks));
#pragma omp parallel for num_threads(threads) schedule(static)
  for (long long b = 0; b < blocks; ++b) {
    const std::size_t begin = static_cast<std::size_t>(b) * kBlock;
    const std::size_t end = std::min(n, begin + kBlock);
    double sum = 0.0;
    std::size_t inliers = 0;
    for (std::size_t k = begin; k < end; ++k) {
      const double d = std::sqrt(sqr_dists[k]);
      sum += d;
      inliers += d < rho;
    }
    block_sum[static_cast<std::size_t>(b)] = sum;
    block_inliers[static_cast<std::size_t>(b)] = inliers;
  }
  double sum = 0.0;
  std::size_t inliers = 0;
  for (std::size_t b = 0; b < block_sum.size(); ++b) {
    sum += block_sum[b];
    inliers += block_inliers[b];
  }
  DirectedSums out;
  out.mean = sum / static_cast<double>(n);
  out.inlier_share = static_cast<double>(inliers) / static_cast<double>(n);
  return out;
}

/// Points by their exact float coordinates, each with a squared distance (open
/// addressing; a point's key is its coordinates' bit patterns).
class PointTable {
public:
  /// Empties the table and makes room for n points.
  void reset(std::size_t n)
  {
    std::size_t capacity = 16;
    while (capacity < 2 * n)
      capacity *= 2;
    entries_.assign(capacity, Entry{});
    mask_ = capacity - 1;
  }
  /// Adds p with its squared distance (a point already there keeps its entry).
  void insert(const float p[3], double sqr_dist)
  {
    Entry& e = entries_[slot(p)];
    if (!e.used)
      e = {{bits(p[0]), bits(p[1]), bits(p[2])}, true, sqr_dist};
  }
  /// p's squared distance; false when p is not in the table.
  bool find(const float p[3], double& sqr_dist) const
  {
    const Entry& e = entries_[slot(p)];
    if (!e.used)
      return false;
    sqr_dist = e.sqr_dist;
    return true;
  }
  /// f(p) for every point p of the table.
  template <typename F>
  void forEach(F&& f) const
  {
    for (const Entry& e : entries_)
      if (e.used) {
        float p[3];
        for (int a = 0; a < 3; ++a)
          std::memcpy(&p[a], &e.key[a], sizeof(float));
        f(p);
      }
  }

private:
  struct Entry {
    std::uint32_t key[3] = {0, 0, 0};
    bool used = false;
    double sqr_dist = 0.0;
  };
  static std::uint32_t bits(float v)
  {
    std::uint32_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
  }
  /// The index of p's entry, or of the empty one where it would go.
  std::size_t slot(const float p[3]) const
  {
    const std::uint32_t x = bits(p[0]), y = bits(p[1]), z = bits(p[2]);
    std::uint64_t h = ((std::uint64_t{x} << 32) | y) * 0x9E3779B97F4A7C15ull ^
                      std::uint64_t{z} * 0xC2B2AE3D27D4EB4Full;
    h ^= h >> 29;
    for (std::size_t i = h & mask_;; i = (i + 1) & mask_) {
      const Entry& e = entries_[i];
      if (!e.used || (e.key[0] == x && e.key[1] == y && e.key[2] == z))
        return i;
    }
  }

  std::vector<Entry> entries_;
  std::size_t mask_ = 0;
};

/// What a compute() measured, kept for the next one (ReconstructionMetrics::
/// setReuseDistances): R's points with their squared distances to T, and the squared
/// distance of each point of T (in T's tree order) to R.
struct DistanceMemo {
  bool valid = false;
  PointTable reconstruction;
  std::vector<double> reference;
};

/// R's points (tree order) with their squared distances to T.
PointTable tableOf(const MortonTree& r, const std::vector<double>& r_to_t)
{
  PointTable table;
  table.reset(r.size());
  for (std::size_t k = 0; k < r.size(); ++k) {
    float p[3];
    r.point(k, p);
    table.insert(p, r_to_t[k]);
  }
  return table;
}

/// squaredDistances() from a valid memo of an earlier R; `current` gets R's table.
void updateDistances(const MortonTree& r, const MortonTree& t, int threads,
                     const DistanceMemo& memo, std::vector<double>& r_to_t,
                     std::vector<double>& t_to_r, PointTable& current)
{
  // R's points the memo does not hold: their distances to T are searched.
  std::vector<std::int32_t> added;
  for (std::size_t k = 0; k < r.size(); ++k) {
    float p[3];
    r.point(k, p);
    if (!memo.reconstruction.find(p, r_to_t[k]))
      added.push_back(static_cast<std::int32_t>(k));
  }
  MortonTree added_tree;
  MortonTreeInput input = r.sortedPoints();
  input.has_indices = true;
  input.indices = added.data();
  input.num_indices = added.size();
  added_tree.build(input, threads);
  std::vector<double> sqr(added.size());
  t.nearestSquaredOfEach(added_tree, threads, nullptr, sqr.data());
  for (std::size_t j = 0; j < added_tree.size(); ++j)
    r_to_t[added_tree.cloudIndex(j)] = sqr[j];
  // The memo's points no longer in R.
  current = tableOf(r, r_to_t);
  std::vector<float> removed; // x, y, z of each
  memo.reconstruction.forEach([&](const float p[3]) {
    double unused;
    if (!current.find(p, unused))
      removed.insert(removed.end(), p, p + 3);
  });
  // T: a nearer point can only be a new one (searched below the earlier distance) ...
  const std::vector<double>& before = memo.reference;
  if (added_tree.size() > 0)
    added_tree.nearestSquaredOfEach(t, threads, before.data(), t_to_r.data());
  else
    t_to_r = before;
  // ... unless the earlier nearest point left R: a removed point at the earlier
  // distance or nearer (ties included) sends the point to a full search.
  if (removed.empty())
    return;
  MortonTree removed_tree;
  MortonTreeInput removed_input;
  removed_input.x = &removed[0];
  removed_input.y = &removed[1];
  removed_input.z = &removed[2];
  removed_input.stride_bytes = 3 * sizeof(float);
  removed_input.cloud_size = removed.size() / 3;
  removed_tree.build(removed_input, threads);
  std::vector<double> bound(t.size()), near_removed(t.size());
  for (std::size_t k = 0; k < t.size(); ++k)
    bound[k] = std::nextafter(before[k], kInf);
  removed_tree.nearestSquaredOfEach(t, threads, bound.data(), near_removed.data());
  for (std::size_t k = 0; k < t.size(); ++k)
    if (near_removed[k] < bound[k]) {
      float p[3];
      t.point(k, p);
      const double q[3] = {p[0], p[1], p[2]};
      MortonTree::Neighbor nearest;
      r.nearest(q, nearest);
      t_to_r[k] = nearest.sqr_dist;
    }
}

/// The squared distances of R's points to T and of T's points to R, both in their
/// trees' order; both trees non-empty. With a valid memo of an earlier R (the same T),
/// only what changed is searched (updateDistances): R's new points in T; for T, its
/// points' distances to R's new points, bounded by their earlier distances, and a full
/// search where an earlier nearest point may have left R. The memo is then R's. Each
/// distance is the one a full search finds: the minimum of the same exact squared
/// distances.
void squaredDistances(const MortonTree& r, const MortonTree& t, int threads,
                      DistanceMemo* memo, std::vector<double>& r_to_t,
                      std::vector<double>& t_to_r)
{
  r_to_t.resize(r.size());
  t_to_r.resize(t.size());
  if (memo &&
      r.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    memo->valid = false; // a tree's index list holds R's positions as int32: no reuse
    memo = nullptr;
  }
  if (memo && memo->valid) {
    PointTable current;
    updateDistances(r, t, threads, *memo, r_to_t, t_to_r, current);
    memo->reconstruction = std::move(current);
  } else {
    t.nearestSquaredOfEach(r, threads, nullptr, r_to_t.data());
    r.nearestSquaredOfEach(t, threads, nullptr, t_to_r.data());
    if (!memo)
      return;
    memo->reconstruction = tableOf(r, r_to_t);
  }
  memo->reference = t_to_r;
  memo->valid = true;
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
  bool reuse_distances = false;
  /// compute()'s memo (setReuseDistances); a compute() that finds it in use by another
  /// thread searches in full and leaves it.
  std::mutex memo_mutex;
  DistanceMemo memo;
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
  impl_->memo.valid = false;          // its distances are to the old reference
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

void ReconstructionMetrics::setReuseDistances(bool reuse)
{
  if (!impl_)
    impl_ = std::make_unique<Impl>();
  impl_->reuse_distances = reuse;
  if (!reuse)
    impl_->memo = DistanceMemo{}; // its memory back
}

bool ReconstructionMetrics::getReuseDistances() const
{
  return impl_ && impl_->reuse_distances;
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
  std::vector<double> r_to_t, t_to_r;
  {
    std::unique_lock<std::mutex> lock(impl_->memo_mutex, std::defer_lock);
    const bool memo = impl_->reuse_distances && lock.try_lock();
    squaredDistances(r, t, threads, memo ? &impl_->memo : nullptr, r_to_t, t_to_r);
  }
  const DirectedSums accuracy = directedSums(r_to_t, rho_, threads);
  const DirectedSums completeness = directedSums(t_to_r, rho_, threads);
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
