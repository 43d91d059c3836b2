#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/metrics/reconstruction_metrics.h>

using plantnbv::CloudXYZ;
using plantnbv::InvalidArgumentError;
using plantnbv::MetricsResult;
using plantnbv::ReconstructionMetrics;
using plantnbv::Rng;

namespace {

const double kInf = std::numeric_limits<double>::infinity();
const float kNaN = std::numeric_limits<float>::quiet_NaN();

using CloudPtr = std::shared_ptr<CloudXYZ>;

CloudPtr makeCloud(const std::vector<pcl::PointXYZ>& points = {})
{
  auto cloud = std::make_shared<CloudXYZ>();
  for (const auto& p : points)
    cloud->push_back(p);
  return cloud;
}

/// A 10 x 10 x 10 lattice with spacing 1/64 m: every coordinate, and every coordinate
/// offset by multiples of 1/4096 m, is exact in float.
CloudPtr lattice(float ox = 0.0f, float oy = 0.0f, float oz = 0.0f)
{
  auto cloud = makeCloud();
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 10; ++k)
        cloud->push_back(pcl::PointXYZ(1.0f + i / 64.0f + ox, -0.5f + j / 64.0f + oy,
                                       0.75f + k / 64.0f + oz));
  return cloud;
}

MetricsResult computeMetrics(const CloudPtr& reconstruction, const CloudPtr& reference,
                             double rho = 0.003, int threads = 0)
{
  ReconstructionMetrics metrics;
  metrics.setThreshold(rho);
  metrics.setNumberOfThreads(threads);
  metrics.setReference(reference);
  metrics.setReconstruction(reconstruction);
  return metrics.compute();
}

bool finite(const pcl::PointXYZ& p)
{
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

/// O(n^2) nearest-neighbour distances, computed like the specification says: in double
/// from the float coordinates, NaN for non-finite query points.
std::vector<double> bruteForce(const CloudXYZ& queries, const CloudXYZ& targets)
{
  std::vector<double> out(queries.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    if (!finite(queries[i]))
      continue;
    double best = kInf;
    for (const auto& t : targets) {
      if (!finite(t))
        continue;
      const double dx = double(queries[i].x) - double(t.x);
      const double dy = double(queries[i].y) - double(t.y);
      const double dz = double(queries[i].z) - double(t.z);
      best = std::min(best, dx * dx + dy * dy + dz * dz);
    }
    out[i] = std::sqrt(best);
  }
  return out;
}

void expectSameDistances(const std::vector<double>& expected,
                         const std::vector<double>& actual, const std::string& what)
{
  ASSERT_EQ(expected.size(), actual.size()) << what;
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const bool same =
        std::isnan(expected[i]) ? std::isnan(actual[i]) : expected[i] == actual[i];
    if (!same && mismatches++ < 5)
      ADD_FAILURE() << what << ": point " << i << " expected " << expected[i] << " got "
                    << actual[i];
  }
  EXPECT_EQ(mismatches, 0u) << what;
}

void expectIdentical(const MetricsResult& a, const MetricsResult& b)
{
  EXPECT_EQ(a.mean_dist_reconstruction_to_reference,
            b.mean_dist_reconstruction_to_reference);
  EXPECT_EQ(a.mean_dist_reference_to_reconstruction,
            b.mean_dist_reference_to_reconstruction);
  EXPECT_EQ(a.chamfer, b.chamfer);
  EXPECT_EQ(a.precision, b.precision);
  EXPECT_EQ(a.recall, b.recall);
  EXPECT_EQ(a.f1, b.f1);
  EXPECT_EQ(a.rho, b.rho);
  EXPECT_EQ(a.reference_points, b.reference_points);
  EXPECT_EQ(a.reconstruction_points, b.reconstruction_points);
  EXPECT_EQ(a.valid, b.valid);
}

void expectInvalid(const MetricsResult& m)
{
  EXPECT_FALSE(m.valid);
  EXPECT_EQ(m.precision, 0.0);
  EXPECT_EQ(m.recall, 0.0);
  EXPECT_EQ(m.f1, 0.0);
  EXPECT_EQ(m.mean_dist_reconstruction_to_reference, kInf);
  EXPECT_EQ(m.mean_dist_reference_to_reconstruction, kInf);
  EXPECT_EQ(m.chamfer, kInf);
}

using Generator = std::function<pcl::PointXYZ(Rng&)>;

CloudPtr randomCloud(std::size_t n, std::uint64_t seed, const Generator& gen)
{
  Rng rng(seed);
  auto cloud = makeCloud();
  for (std::size_t i = 0; i < n; ++i)
    cloud->push_back(gen(rng));
  return cloud;
}

pcl::PointXYZ uniformInBox(Rng& rng)
{
  return pcl::PointXYZ(float(rng.uniform(-0.2, 0.3)), float(rng.uniform(0.0, 0.1)),
                       float(rng.uniform(0.8, 1.5)));
}

/// A noisy sphere of radius 5 cm: a surface, like the clouds the metrics are made for.
pcl::PointXYZ noisySphere(Rng& rng)
{
  const double z = rng.uniform(-1.0, 1.0), phi = rng.uniform(0.0, 2.0 * M_PI);
  const double s = std::sqrt(1.0 - z * z);
  const double r = 0.05 + 0.001 * rng.normal();
  return pcl::PointXYZ(float(1.0 + r * s * std::cos(phi)), float(r * s * std::sin(phi)),
                       float(1.1 + r * z));
}

} // namespace

TEST(ReconstructionMetrics, OffsetCopyHasChamferTwiceTheOffset)
{
  // |v| = 13/4096 m (3-4-12-13), less than half the 1/64 m spacing: each point's nearest
  // neighbour is its own copy, every distance is exactly |v|.
  const double v = 13.0 / 4096.0;
  const auto reference = lattice();
  const auto reconstruction = lattice(3.0f / 4096, -4.0f / 4096, 12.0f / 4096);
  const MetricsResult m = computeMetrics(reconstruction, reference);
  EXPECT_TRUE(m.valid);
  EXPECT_EQ(m.mean_dist_reconstruction_to_reference, v);
  EXPECT_EQ(m.mean_dist_reference_to_reconstruction, v);
  EXPECT_EQ(m.chamfer, 2.0 * v);
  EXPECT_EQ(m.reference_points, 1000u);
  EXPECT_EQ(m.reconstruction_points, 1000u);
}

TEST(ReconstructionMetrics, ThresholdIsStrict)
{
  const double v = 13.0 / 4096.0;
  const auto reference = lattice();
  const auto reconstruction = lattice(3.0f / 4096, -4.0f / 4096, 12.0f / 4096);
  const MetricsResult at = computeMetrics(reconstruction, reference, v);
  EXPECT_EQ(at.precision, 0.0);
  EXPECT_EQ(at.recall, 0.0);
  EXPECT_EQ(at.f1, 0.0);
  EXPECT_EQ(at.rho, v);
  const MetricsResult inside =
      computeMetrics(reconstruction, reference, std::nextafter(v, 1.0));
  EXPECT_EQ(inside.precision, 1.0);
  EXPECT_EQ(inside.recall, 1.0);
  EXPECT_EQ(inside.f1, 1.0);
}

TEST(ReconstructionMetrics, IdenticalCloudsArePerfect)
{
  const auto cloud = randomCloud(3000, 1, noisySphere);
  const MetricsResult m = computeMetrics(cloud, cloud);
  EXPECT_TRUE(m.valid);
  EXPECT_EQ(m.chamfer, 0.0);
  EXPECT_EQ(m.precision, 1.0);
  EXPECT_EQ(m.recall, 1.0);
  EXPECT_EQ(m.f1, 1.0);
}

TEST(ReconstructionMetrics, PartialReconstructionWithOutliers)
{
  // R = the half of T with i < 5, plus 100 points 2 m away: P = 500/600, R = 1/2.
  const auto reference = lattice();
  auto reconstruction = makeCloud();
  for (std::size_t i = 0; i < 500; ++i)
    reconstruction->push_back((*reference)[i]);
  for (std::size_t i = 0; i < 100; ++i) {
    auto p = (*reference)[i];
    p.x += 2.0f;
    reconstruction->push_back(p);
  }
  const double rho = 1.0 / 128; // half the spacing
  const MetricsResult m = computeMetrics(reconstruction, reference, rho);
  const double precision = 500.0 / 600.0, recall = 0.5;
  EXPECT_EQ(m.precision, precision);
  EXPECT_EQ(m.recall, recall);
  EXPECT_DOUBLE_EQ(m.f1, 2.0 * precision * recall / (precision + recall));

  const auto r_to_t = bruteForce(*reconstruction, *reference);
  const auto t_to_r = bruteForce(*reference, *reconstruction);
  double sum_r = 0.0, sum_t = 0.0;
  for (double d : r_to_t)
    sum_r += d;
  for (double d : t_to_r)
    sum_t += d;
  EXPECT_NEAR(m.mean_dist_reconstruction_to_reference, sum_r / 600, 1e-12);
  EXPECT_NEAR(m.mean_dist_reference_to_reconstruction, sum_t / 1000, 1e-12);
  EXPECT_NEAR(m.chamfer, sum_r / 600 + sum_t / 1000, 1e-12);
}

TEST(ReconstructionMetrics, EmptyOrNonFiniteCloudsAreInvalid)
{
  const auto cloud = lattice();
  const auto empty = makeCloud();
  const auto nan_only = makeCloud({{kNaN, kNaN, kNaN}, {kNaN, 0.0f, 1.0f}});

  MetricsResult m = computeMetrics(empty, cloud, 0.004);
  expectInvalid(m);
  EXPECT_EQ(m.reconstruction_points, 0u);
  EXPECT_EQ(m.reference_points, 1000u);
  EXPECT_EQ(m.rho, 0.004);

  m = computeMetrics(cloud, empty);
  expectInvalid(m);
  EXPECT_EQ(m.reconstruction_points, 1000u);
  EXPECT_EQ(m.reference_points, 0u);

  m = computeMetrics(nan_only, cloud);
  expectInvalid(m);
  EXPECT_EQ(m.reconstruction_points, 0u);
  expectInvalid(computeMetrics(cloud, nan_only));
  expectInvalid(computeMetrics(empty, empty));
}

TEST(ReconstructionMetrics, DistancesWithAnEmptyCloud)
{
  ReconstructionMetrics metrics;
  metrics.setReference(makeCloud());
  metrics.setReconstruction(makeCloud({{0.0f, 0.0f, 0.0f}, {kNaN, 1.0f, 1.0f}}));
  std::vector<double> r_to_t, t_to_r = {1.0};
  metrics.computeDistances(r_to_t, t_to_r);
  ASSERT_EQ(r_to_t.size(), 2u);
  EXPECT_EQ(r_to_t[0], kInf);
  EXPECT_TRUE(std::isnan(r_to_t[1]));
  EXPECT_TRUE(t_to_r.empty());
}

TEST(ReconstructionMetrics, NonFinitePointsAreIgnored)
{
  const auto reference = randomCloud(2000, 2, noisySphere);
  const auto reconstruction = randomCloud(1500, 3, noisySphere);
  auto reference_dirty = makeCloud();
  auto reconstruction_dirty = makeCloud();
  const float inf = std::numeric_limits<float>::infinity();
  const pcl::PointXYZ bad[] = {
      {kNaN, 0.0f, 0.0f}, {0.0f, inf, 0.0f}, {0.0f, 0.0f, -inf}, {kNaN, kNaN, kNaN}};
  for (std::size_t i = 0; i < reference->size(); ++i) {
    if (i % 100 == 0)
      reference_dirty->push_back(bad[(i / 100) % 4]);
    reference_dirty->push_back((*reference)[i]);
  }
  for (std::size_t i = 0; i < reconstruction->size(); ++i) {
    reconstruction_dirty->push_back((*reconstruction)[i]);
    if (i % 70 == 0)
      reconstruction_dirty->push_back(bad[(i / 70) % 4]);
  }
  const MetricsResult clean = computeMetrics(reconstruction, reference, 0.002);
  const MetricsResult dirty =
      computeMetrics(reconstruction_dirty, reference_dirty, 0.002);
  EXPECT_TRUE(dirty.valid);
  EXPECT_EQ(dirty.reference_points, 2000u);
  EXPECT_EQ(dirty.reconstruction_points, 1500u);
  EXPECT_EQ(dirty.precision, clean.precision);
  EXPECT_EQ(dirty.recall, clean.recall);
  EXPECT_EQ(dirty.chamfer, clean.chamfer); // same finite points, same order

  ReconstructionMetrics metrics;
  metrics.setReference(reference_dirty);
  metrics.setReconstruction(reconstruction_dirty);
  std::vector<double> r_to_t, t_to_r;
  metrics.computeDistances(r_to_t, t_to_r);
  expectSameDistances(bruteForce(*reconstruction_dirty, *reference_dirty), r_to_t,
                      "R to T");
  expectSameDistances(bruteForce(*reference_dirty, *reconstruction_dirty), t_to_r,
                      "T to R");
  std::vector<double> t_to_r_only = {1.0};
  metrics.computeDistances(t_to_r_only); // one direction: the same values
  ASSERT_EQ(t_to_r_only.size(), t_to_r.size());
  for (std::size_t i = 0; i < t_to_r.size(); ++i)
    EXPECT_TRUE(t_to_r_only[i] == t_to_r[i] ||
                (std::isnan(t_to_r_only[i]) && std::isnan(t_to_r[i])))
        << i;
}

namespace {
/// computeDistancesBelow's contract against computeDistances: a distance below the
/// bound is the exact one, every other +infinity; NaN where the point is not finite.
void expectExactBelow(const std::vector<double>& exact, const std::vector<double>& below,
                      double bound, const std::string& what)
{
  std::vector<double> expected = exact;
  for (double& d : expected)
    if (!std::isnan(d) && !(d < bound))
      d = kInf;
  expectSameDistances(expected, below, what);
}
} // namespace

TEST(ReconstructionMetrics, DistancesBelowABoundAreTheExactOnesAndInfinityBeyond)
{
  // R covers one side of T only: most of T's points are far from it, as a map's after
  // its first views.
  auto reference = randomCloud(30000, 6, noisySphere);
  for (std::size_t i = 0; i < reference->size(); i += 499)
    (*reference)[i].z = kNaN;
  auto reconstruction = makeCloud();
  const CloudPtr sphere = randomCloud(20000, 7, noisySphere);
  for (const pcl::PointXYZ& p : *sphere)
    if (p.x > 0.3f)
      reconstruction->push_back(p);
  for (int threads : {1, 2}) {
    ReconstructionMetrics metrics;
    metrics.setNumberOfThreads(threads);
    metrics.setReference(reference);
    metrics.setReconstruction(reconstruction);
    std::vector<double> exact, below;
    metrics.computeDistances(exact);
    std::vector<double> finite_exact;
    for (double d : exact)
      if (std::isfinite(d))
        finite_exact.push_back(d);
    std::sort(finite_exact.begin(), finite_exact.end());
    // Bounds between the distances, on one of them (that point must get infinity), and
    // beyond them all.
    for (double bound : {0.003, 0.05, finite_exact[finite_exact.size() / 2],
                         finite_exact.back() * 2.0}) {
      metrics.computeDistancesBelow(bound, below);
      expectExactBelow(exact, below, bound,
                       "bound " + std::to_string(bound) + ", " + std::to_string(threads) +
                           " threads");
    }
  }
  // On a lattice every distance ties with many others, and a bound equal to the
  // spacing falls on them exactly.
  ReconstructionMetrics metrics;
  metrics.setReference(lattice());
  metrics.setReconstruction(lattice(1.0f / 64.0f, 0.0f, 0.0f));
  std::vector<double> exact, below;
  metrics.computeDistances(exact);
  for (double bound : {1.0 / 64.0, std::nextafter(1.0 / 64.0, 1.0), 0.001}) {
    metrics.computeDistancesBelow(bound, below);
    expectExactBelow(exact, below, bound, "lattice, bound " + std::to_string(bound));
  }
  EXPECT_THROW(metrics.computeDistancesBelow(0.0, below), InvalidArgumentError);
  EXPECT_THROW(metrics.computeDistancesBelow(kNaN, below), InvalidArgumentError);
  ReconstructionMetrics empty;
  EXPECT_THROW(empty.computeDistancesBelow(0.003, below), InvalidArgumentError);
}

TEST(ReconstructionMetrics, ResultDoesNotDependOnThreadCount)
{
  // 40k points: trees built in parallel chunks, 40 blocks of queries shared out
  // differently by each thread count; some points are NaN.
  auto reference = randomCloud(40000, 4, noisySphere);
  for (std::size_t i = 0; i < reference->size(); i += 997)
    (*reference)[i].y = kNaN;
  const auto reconstruction = randomCloud(35000, 5, noisySphere);
  std::vector<MetricsResult> results;
  std::vector<std::vector<double>> r_to_t(3), t_to_r(3);
  for (int threads : {1, 2, 3}) {
    ReconstructionMetrics metrics; // set the threads first: they build the trees too
    metrics.setNumberOfThreads(threads);
    EXPECT_EQ(metrics.getNumberOfThreads(), threads);
    metrics.setReference(reference);
    metrics.setReconstruction(reconstruction);
    results.push_back(metrics.compute());
    metrics.computeDistances(r_to_t[threads - 1], t_to_r[threads - 1]);
  }
  for (int i : {1, 2}) {
    expectIdentical(results[0], results[i]);
    EXPECT_EQ(r_to_t[i], r_to_t[0]);
    expectSameDistances(t_to_r[0], t_to_r[i], "T to R"); // NaN entries: not ==
  }
  EXPECT_EQ(results[0].reference_points, 40000u - 41u);
  EXPECT_GT(results[0].precision, 0.0);
  EXPECT_LT(results[0].precision, 1.0);
}

TEST(ReconstructionMetrics, DistancesEqualBruteForce)
{
  struct Case {
    const char* name;
    CloudPtr reconstruction, reference;
  };
  // Far away: offset copies 3 m apart, so every query lies outside the other tree.
  auto far = randomCloud(2000, 8, uniformInBox);
  for (auto& p : *far)
    p.x += 3.0f;
  // Many duplicates (equal Morton keys) and a plane (one axis without extent).
  auto duplicates = randomCloud(2000, 9, [](Rng& rng) {
    return pcl::PointXYZ(float(rng.index(4)) * 0.01f, 0.5f, float(rng.index(3)) * 0.02f);
  });
  auto plane = randomCloud(2000, 10, [](Rng& rng) {
    return pcl::PointXYZ(float(rng.uniform()), float(rng.uniform()), 1.25f);
  });
  // Large coordinates with a small extent: float steps of 61 micrometres at 1000 m.
  auto offset = randomCloud(2000, 11, [](Rng& rng) {
    return pcl::PointXYZ(float(1000.0 + rng.uniform(0.0, 0.05)),
                         float(-1000.0 + rng.uniform(0.0, 0.05)), float(rng.uniform()));
  });
  auto offset2 = randomCloud(1000, 12, [](Rng& rng) {
    return pcl::PointXYZ(float(1000.0 + rng.uniform(0.0, 0.06)),
                         float(-1000.0 + rng.uniform(0.0, 0.04)), float(rng.uniform()));
  });
  // Large enough to be built in parallel chunks.
  auto sphere_with_nans = randomCloud(40000, 21, noisySphere);
  for (std::size_t i = 0; i < sphere_with_nans->size(); i += 1001)
    (*sphere_with_nans)[i].z = kNaN;
  const Case cases[] = {
      {"uniform", randomCloud(2000, 6, uniformInBox), randomCloud(2000, 7, uniformInBox)},
      {"sphere", randomCloud(2000, 13, noisySphere), randomCloud(1800, 14, noisySphere)},
      {"far apart", randomCloud(2000, 8, uniformInBox), far},
      {"duplicates", duplicates, randomCloud(500, 15, uniformInBox)},
      {"plane", plane, randomCloud(2000, 16, uniformInBox)},
      {"large coordinates", offset, offset2},
      {"single point", makeCloud({{0.1f, 0.2f, 0.3f}}),
       randomCloud(2000, 17, uniformInBox)},
      {"tiny", randomCloud(16, 18, uniformInBox), randomCloud(17, 19, uniformInBox)},
      // Leaves hold at most 64 points: one leaf, and a root with two leaves.
      {"one leaf", randomCloud(64, 22, uniformInBox), randomCloud(65, 23, uniformInBox)},
      {"large reference", randomCloud(2000, 20, noisySphere), sphere_with_nans},
  };
  for (const Case& c : cases) {
    ReconstructionMetrics metrics;
    metrics.setNumberOfThreads(2);
    metrics.setReference(c.reference);
    metrics.setReconstruction(c.reconstruction);
    std::vector<double> r_to_t, t_to_r;
    metrics.computeDistances(r_to_t, t_to_r);
    expectSameDistances(bruteForce(*c.reconstruction, *c.reference), r_to_t,
                        std::string(c.name) + " R to T");
    expectSameDistances(bruteForce(*c.reference, *c.reconstruction), t_to_r,
                        std::string(c.name) + " T to R");

    // compute() agrees with the distances (it sums in another order: not bit-equal).
    const MetricsResult m = metrics.compute();
    const auto summary = [&m](const std::vector<double>& dists, double& mean,
                              double& share) {
      double sum = 0.0;
      std::size_t finite = 0, inliers = 0;
      for (double d : dists)
        if (!std::isnan(d)) {
          sum += d;
          ++finite;
          inliers += d < m.rho;
        }
      mean = sum / double(finite);
      share = double(inliers) / double(finite);
    };
    double mean_r, mean_t, precision, recall;
    summary(r_to_t, mean_r, precision);
    summary(t_to_r, mean_t, recall);
    EXPECT_NEAR(m.mean_dist_reconstruction_to_reference, mean_r, 1e-12 * mean_r)
        << c.name;
    EXPECT_NEAR(m.mean_dist_reference_to_reconstruction, mean_t, 1e-12 * mean_t)
        << c.name;
    EXPECT_EQ(m.precision, precision) << c.name;
    EXPECT_EQ(m.recall, recall) << c.name;
  }
}

TEST(ReconstructionMetrics, NearestPointJustAcrossACellBoundaryIsFound)
{
  // A search starts in the smallest Morton cell that holds its ball, seeded by the
  // previous query's nearest point. Here the ball of q2 (radius |q2 - A|) crosses the
  // cell boundary x = X by half a key step (1/65535 m, the reference spans 1 m) and the
  // true nearest point B lies 0.3 steps beyond it: a key range half a step too narrow
  // would start in the cell below X and miss B.
  const double step = 1.0 / 65535.0, r = 0.01;
  const double boundary = 32768 * step;
  const pcl::PointXYZ q2(float(boundary + 0.5 * step - r), 0.25f, 0.25f);
  const pcl::PointXYZ a(q2.x, q2.y, float(0.25 - r));
  const pcl::PointXYZ b(float(boundary + 0.3 * step), q2.y, q2.z);
  auto reference = makeCloud({{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}, a, b});
  for (int i = 0; i < 100; ++i) // more than a leaf below X: that cell gets a subtree
    reference->push_back(pcl::PointXYZ(0.05f + 0.001f * i, 0.05f, 0.05f));
  const auto reconstruction = makeCloud({a, q2}); // a first in Morton order: the seed
  ReconstructionMetrics metrics;
  metrics.setReference(reference);
  metrics.setReconstruction(reconstruction);
  std::vector<double> r_to_t, t_to_r;
  metrics.computeDistances(r_to_t, t_to_r);
  EXPECT_EQ(r_to_t[0], 0.0);
  EXPECT_LT(r_to_t[1], r - 0.1 * step); // B, not the seed A
  expectSameDistances(bruteForce(*reconstruction, *reference), r_to_t, "R to T");
}

TEST(ReconstructionMetrics, SettingACloudAgainReplacesIt)
{
  const auto reference = lattice();
  ReconstructionMetrics metrics;
  metrics.setReference(reference);
  metrics.setReconstruction(lattice(3.0f / 4096, -4.0f / 4096, 12.0f / 4096));
  EXPECT_EQ(metrics.compute().chamfer, 2.0 * 13.0 / 4096);
  metrics.setReconstruction(reference);
  EXPECT_EQ(metrics.compute().chamfer, 0.0);

  ReconstructionMetrics moved(std::move(metrics));
  EXPECT_EQ(moved.compute().f1, 1.0);
}

/// The voxel centre (3 mm voxels) nearest to p: clouds like a map's occupied voxels,
/// where many points lie at equal distances from each other.
pcl::PointXYZ voxelCentre(const pcl::PointXYZ& p)
{
  const auto centre = [](float v) {
    return float((std::floor(v / 0.003) + 0.5) * 0.003);
  };
  return pcl::PointXYZ(centre(p.x), centre(p.y), centre(p.z));
}

TEST(ReconstructionMetrics, ReusedDistancesGiveTheResultsOfAFreshCompute)
{
  // A reconstruction that changes as a map's does from view to view: points added and
  // removed (ties everywhere on the voxel lattice, so a removed nearest point often has
  // a twin at the same distance, and often not), unchanged, reordered, duplicated, with
  // NaN, empty; the reference changed half-way. Every compute() of the object that
  // reuses distances must equal a fresh object's, bit for bit, at 1 and 2 threads.
  std::vector<pcl::PointXYZ> pool;
  Rng pool_rng(21);
  for (int i = 0; i < 6000; ++i)
    pool.push_back(voxelCentre(noisySphere(pool_rng)));
  const auto reference_a =
      randomCloud(5000, 22, [](Rng& rng) { return voxelCentre(noisySphere(rng)); });
  const auto reference_b = randomCloud(3000, 23, noisySphere);
  for (int threads : {1, 2}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    ReconstructionMetrics reusing;
    reusing.setNumberOfThreads(threads);
    EXPECT_FALSE(reusing.getReuseDistances());
    reusing.setReuseDistances(true);
    EXPECT_TRUE(reusing.getReuseDistances());
    reusing.setReference(reference_a);
    auto reference = reference_a;
    Rng rng(24);
    std::vector<pcl::PointXYZ> points(pool.begin(), pool.begin() + 300);
    for (int step = 0; step < 24; ++step) {
      SCOPED_TRACE("step " + std::to_string(step));
      if (step == 12) { // another reference: nothing kept may be reused
        reference = reference_b;
        reusing.setReference(reference);
      }
      if (step == 18) {
        reusing.setReuseDistances(false);
        reusing.setReuseDistances(true);
      }
      // Remove a share of the points, add new ones from the pool.
      std::vector<pcl::PointXYZ> next;
      const double keep = step % 5 == 3 ? 1.0 : 0.9;
      for (const pcl::PointXYZ& p : points)
        if (rng.uniform() < keep)
          next.push_back(p);
      if (step % 5 != 3)
        for (int i = 0; i < 250; ++i)
          next.push_back(pool[rng.index(pool.size())]); // duplicates too
      for (std::size_t i = next.size(); i > 1; --i)     // reordered
        std::swap(next[i - 1], next[rng.index(i)]);
      points = next;
      auto cloud = makeCloud(step == 7 ? std::vector<pcl::PointXYZ>{} : points);
      if (step % 4 == 1)
        cloud->push_back(pcl::PointXYZ(kNaN, 0.0f, 1.0f));
      reusing.setReconstruction(cloud);
      expectIdentical(reusing.compute(),
                      computeMetrics(cloud, reference, 0.003, threads));
    }
  }
}

TEST(ReconstructionMetrics, ComputesFromSeveralThreadsWhileReusingDistances)
{
  // compute() stays callable from several threads at once: one of them uses and updates
  // the kept distances, the others search in full; all get the fresh result.
  const auto reference = randomCloud(4000, 25, noisySphere);
  auto first = randomCloud(3000, 26, noisySphere);
  auto second = std::make_shared<CloudXYZ>(*first);
  second->resize(2500);
  const auto added = randomCloud(400, 27, noisySphere);
  for (const pcl::PointXYZ& p : *added)
    second->push_back(p);
  ReconstructionMetrics metrics;
  metrics.setNumberOfThreads(1);
  metrics.setReuseDistances(true);
  metrics.setReference(reference);
  metrics.setReconstruction(first);
  metrics.compute();
  metrics.setReconstruction(second);
  const MetricsResult expected = computeMetrics(second, reference, 0.003, 1);
  std::vector<MetricsResult> results(4 * 8);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int i = 0; i < 8; ++i)
        results[static_cast<std::size_t>(t * 8 + i)] = metrics.compute();
    });
  for (std::thread& thread : threads)
    thread.join();
  for (const MetricsResult& m : results)
    expectIdentical(m, expected);
}

TEST(ReconstructionMetrics, InvalidSettingsThrow)
{
  ReconstructionMetrics metrics;
  EXPECT_EQ(metrics.getThreshold(), 0.003);
  for (double rho : {0.0, -1.0, std::nan(""), kInf})
    EXPECT_THROW(metrics.setThreshold(rho), InvalidArgumentError) << rho;
  EXPECT_EQ(metrics.getThreshold(), 0.003);
  EXPECT_THROW(metrics.setNumberOfThreads(-1), InvalidArgumentError);
  EXPECT_THROW(metrics.setReference(nullptr), InvalidArgumentError);
  EXPECT_THROW(metrics.setReconstruction(nullptr), InvalidArgumentError);
}

TEST(ReconstructionMetrics, ComputeWithoutCloudsThrows)
{
  ReconstructionMetrics metrics;
  std::vector<double> a, b;
  EXPECT_THROW(metrics.compute(), InvalidArgumentError);
  EXPECT_THROW(metrics.computeDistances(a, b), InvalidArgumentError);
  metrics.setReference(lattice());
  EXPECT_THROW(metrics.compute(), InvalidArgumentError);
  ReconstructionMetrics only_reconstruction;
  only_reconstruction.setReconstruction(lattice());
  EXPECT_THROW(only_reconstruction.compute(), InvalidArgumentError);
}

TEST(ViewsToReach, FirstViewNeverAndNaN)
{
  using plantnbv::viewsToReach;
  EXPECT_EQ(viewsToReach({0.85, 0.9, 0.95}, 0.8), 1);
  EXPECT_EQ(viewsToReach({0.5, 0.7, 0.8, 0.95}, 0.8), 3); // reaching = equal or above
  EXPECT_EQ(viewsToReach({0.5, 0.7, 0.79}, 0.8), -1);
  EXPECT_EQ(viewsToReach({}, 0.8), -1);
  const double nan = std::nan("");
  EXPECT_EQ(viewsToReach({nan, 0.6, nan, 0.91}, 0.9), 4);
  EXPECT_EQ(viewsToReach({nan, nan}, 0.0), -1);
  EXPECT_EQ(viewsToReach({0.95}, nan), -1);
}

TEST(BoundingBoxOverlap, IntersectionOverTheSmallerBoxGrownByTheMargin)
{
  using plantnbv::boundingBoxOverlap;
  auto box = [](float x0, float x1, float y1, float z1) { // two opposite corners
    CloudXYZ c;
    c.push_back(pcl::PointXYZ(x0, 0.0f, 0.0f));
    c.push_back(pcl::PointXYZ(x1, y1, z1));
    return c;
  };
  const CloudXYZ unit = box(0.0f, 1.0f, 1.0f, 1.0f);
  EXPECT_EQ(boundingBoxOverlap(unit, unit, 0.0), 1.0);
  EXPECT_EQ(boundingBoxOverlap(unit, box(0.25f, 0.75f, 0.5f, 0.5f), 0.0), 1.0); // inside
  EXPECT_EQ(boundingBoxOverlap(unit, box(0.5f, 1.5f, 1.0f, 1.0f), 0.0), 0.5);
  EXPECT_EQ(boundingBoxOverlap(box(0.5f, 1.5f, 1.0f, 1.0f), unit, 0.0), 0.5);
  EXPECT_EQ(boundingBoxOverlap(unit, box(2.0f, 3.0f, 1.0f, 1.0f), 0.0), 0.0); // apart
  // A flat cloud has no volume without a margin; with 0.5 its box is 2 x 2 x 1 and
  // the unit box grown alike (2 x 2 x 2) holds it.
  const CloudXYZ flat = box(0.0f, 1.0f, 1.0f, 0.0f);
  EXPECT_EQ(boundingBoxOverlap(unit, flat, 0.0), 0.0);
  EXPECT_EQ(boundingBoxOverlap(unit, flat, 0.5), 1.0);
  // Non-finite points are left out; a cloud without a finite point overlaps nothing.
  CloudXYZ with_nan = unit;
  with_nan.push_back(pcl::PointXYZ(std::nanf(""), 9.0f, 9.0f));
  EXPECT_EQ(boundingBoxOverlap(with_nan, unit, 0.0), 1.0);
  EXPECT_EQ(boundingBoxOverlap(CloudXYZ(), unit, 0.1), 0.0);
  for (const double bad : {-0.1, std::numeric_limits<double>::quiet_NaN()})
    EXPECT_THROW(boundingBoxOverlap(unit, unit, bad), InvalidArgumentError);
}
