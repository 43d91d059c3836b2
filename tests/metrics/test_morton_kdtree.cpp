// search::MortonKdTree against pcl::search::KdTree (FLANN) on the same clouds and
// queries, against a brute force for the documented tie rule, and inside two PCL
// algorithms that take a pcl::search::Search<PointT>::Ptr.
//
// Every cloud and query lies on a dyadic lattice (multiples of 2^-10 m within +-1 m):
// there, FLANN's float arithmetic is exact (squared distances are integers below 2^24
// times 2^-20), so both searches must return exactly the same squared distances.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/features/normal_3d.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/metrics/morton_kdtree.h>

using plantnbv::InvalidArgumentError;
using plantnbv::Rng;
using plantnbv::search::MortonKdTree;

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInfF = std::numeric_limits<float>::infinity();
constexpr double kQuantum = 1.0 / 1024.0; // m

/// Rounds to the lattice, clamped to +-1 m.
float lattice(double v)
{
  return float(std::round(std::clamp(v, -1.0, 1.0) / kQuantum) * kQuantum);
}

pcl::PointXYZ latticePoint(double x, double y, double z)
{
  return {lattice(x), lattice(y), lattice(z)};
}

/// Surface-like clusters: three noisy spheres (radii 15-25 cm) and a plane patch, within
/// +-0.5 m, about 3 cm between neighbours at 3000 points.
std::shared_ptr<Cloud> surfaceCloud(std::size_t n, std::uint64_t seed)
{
  Rng rng(seed);
  struct Sphere {
    double cx, cy, cz, r;
  };
  const Sphere spheres[3] = {
      {-0.2, 0.1, 0.0, 0.25}, {0.25, -0.2, 0.1, 0.15}, {0.1, 0.25, -0.2, 0.2}};
  auto cloud = std::make_shared<Cloud>();
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t part = rng.index(4);
    if (part == 3) { // the plane z = -0.45 + noise
      cloud->push_back(latticePoint(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5),
                                    -0.45 + 0.002 * rng.normal()));
      continue;
    }
    const Sphere& s = spheres[part];
    const double z = rng.uniform(-1.0, 1.0), phi = rng.uniform(0.0, 2.0 * M_PI);
    const double r = s.r + 0.002 * rng.normal(), sz = std::sqrt(1.0 - z * z);
    cloud->push_back(latticePoint(s.cx + r * sz * std::cos(phi),
                                  s.cy + r * sz * std::sin(phi), s.cz + r * z));
  }
  return cloud;
}

/// The cloud sorted by coordinates, each position once.
std::shared_ptr<Cloud> withoutDuplicates(std::shared_ptr<Cloud> cloud)
{
  const auto key = [](const pcl::PointXYZ& p) { return std::make_tuple(p.x, p.y, p.z); };
  std::sort(cloud->begin(), cloud->end(),
            [&](const auto& a, const auto& b) { return key(a) < key(b); });
  cloud->erase(
      std::unique(cloud->begin(), cloud->end(),
                  [&](const auto& a, const auto& b) { return key(a) == key(b); }),
      cloud->end());
  return cloud;
}

/// Query points: every 7th cloud point, the same moved by a few lattice steps, and
/// random lattice points in +-1 m (most far from the cloud).
std::vector<pcl::PointXYZ> queriesFor(const Cloud& cloud, std::uint64_t seed)
{
  Rng rng(seed);
  std::vector<pcl::PointXYZ> queries;
  for (std::size_t i = 0; i < cloud.size(); i += 7) {
    const auto& p = cloud[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      continue;
    queries.push_back(p);
    queries.push_back(latticePoint(p.x + 5 * kQuantum * rng.normal(),
                                   p.y + 5 * kQuantum * rng.normal(),
                                   p.z + 5 * kQuantum * rng.normal()));
  }
  for (int i = 0; i < 200; ++i)
    queries.push_back(latticePoint(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0),
                                   rng.uniform(-1.0, 1.0)));
  return queries;
}

/// A 12 x 12 x 12 grid, spacing 1/64 m: many points at exactly the same distance.
std::shared_ptr<Cloud> gridCloud()
{
  auto cloud = std::make_shared<Cloud>();
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j)
      for (int k = 0; k < 12; ++k)
        cloud->push_back(pcl::PointXYZ(i / 64.0f - 0.125f, j / 64.0f, k / 64.0f + 0.25f));
  return cloud;
}

/// Grid points, cell centres (8 nearest at one distance), edge and face midpoints.
std::vector<pcl::PointXYZ> gridQueries(const Cloud& grid)
{
  std::vector<pcl::PointXYZ> queries;
  const float h = 1 / 128.0f;
  for (std::size_t i = 0; i < grid.size(); i += 5) {
    const auto& p = grid[i];
    queries.push_back(p);
    queries.push_back(pcl::PointXYZ(p.x + h, p.y + h, p.z + h));
    queries.push_back(pcl::PointXYZ(p.x + h, p.y, p.z));
    queries.push_back(pcl::PointXYZ(p.x, p.y + h, p.z - h));
  }
  return queries;
}

double exactSqrDist(const pcl::PointXYZ& a, const pcl::PointXYZ& b)
{
  const double dx = double(a.x) - double(b.x), dy = double(a.y) - double(b.y),
               dz = double(a.z) - double(b.z);
  return dx * dx + dy * dy + dz * dz;
}

struct Neighbours {
  int found = 0;
  pcl::Indices indices;
  std::vector<float> sqr_dists;
};

/// The documented answer: the searched points ordered by (exact squared distance, cloud
/// index), those with float distance below sqr_limit, the first k.
Neighbours bruteForce(const Cloud& cloud, const pcl::Indices* indices,
                      const pcl::PointXYZ& q, std::size_t k, float sqr_limit)
{
  std::vector<std::pair<double, pcl::index_t>> all;
  const std::size_t m = indices ? indices->size() : cloud.size();
  for (std::size_t j = 0; j < m; ++j) {
    const pcl::index_t i = indices ? (*indices)[j] : pcl::index_t(j);
    const auto& p = cloud[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      continue;
    const double d = exactSqrDist(q, p);
    if (float(d) < sqr_limit)
      all.emplace_back(d, i);
  }
  if (k < all.size()) {
    std::nth_element(all.begin(), all.begin() + k, all.end());
    all.resize(k);
  }
  std::sort(all.begin(), all.end());
  Neighbours out;
  for (std::size_t j = 0; j < std::min(k, all.size()); ++j) {
    out.indices.push_back(all[j].second);
    out.sqr_dists.push_back(float(all[j].first));
  }
  out.found = int(out.indices.size());
  return out;
}

/// `ours` against pcl::search::KdTree's `ref`: the same count and exactly the same
/// squared distances; the same index sets within each distance, except at the last
/// distance of a result that was cut (k nearest, max_nn), where either may pick any of
/// the tied points. Unsorted results are compared after sorting.
void expectSameAsPcl(Neighbours ours, Neighbours ref, bool cut, const std::string& what)
{
  ASSERT_EQ(ours.found, ref.found) << what;
  ASSERT_EQ(ours.indices.size(), std::size_t(ours.found)) << what;
  ASSERT_EQ(ref.indices.size(), std::size_t(ref.found)) << what;
  const auto sortByDistance = [](Neighbours& n) {
    std::vector<std::pair<float, pcl::index_t>> v;
    for (std::size_t i = 0; i < n.indices.size(); ++i)
      v.emplace_back(n.sqr_dists[i], n.indices[i]);
    std::sort(v.begin(), v.end());
    for (std::size_t i = 0; i < v.size(); ++i)
      std::tie(n.sqr_dists[i], n.indices[i]) = v[i];
  };
  sortByDistance(ours);
  sortByDistance(ref);
  ASSERT_EQ(ours.sqr_dists, ref.sqr_dists) << what;
  for (std::size_t begin = 0; begin < ours.indices.size();) {
    std::size_t end = begin + 1;
    while (end < ours.indices.size() && ours.sqr_dists[end] == ours.sqr_dists[begin])
      ++end;
    if (!(cut && end == ours.indices.size())) {
      EXPECT_TRUE(std::equal(ours.indices.begin() + begin, ours.indices.begin() + end,
                             ref.indices.begin() + begin))
          << what << ": other points at squared distance " << ours.sqr_dists[begin];
    }
    begin = end;
  }
}

struct Scene {
  std::shared_ptr<Cloud> cloud;
  std::shared_ptr<pcl::Indices> indices; // may be null
  std::vector<pcl::PointXYZ> queries;
  std::vector<double> radii;
};

/// nearestKSearch for k = 1, 4, 16 and radiusSearch (max_nn 0 and 5, sorted and not):
/// as pcl::search::KdTree, and exactly as the brute force (tie rule included).
void compareWithPcl(const Scene& scene)
{
  for (const bool sorted : {true, false}) {
    MortonKdTree<pcl::PointXYZ> ours(sorted);
    pcl::search::KdTree<pcl::PointXYZ> ref(sorted);
    ours.setInputCloud(scene.cloud, scene.indices);
    ref.setInputCloud(scene.cloud, scene.indices);
    EXPECT_TRUE(ours.getInputCloud() == scene.cloud);
    EXPECT_TRUE(ours.getIndices() == scene.indices);
    for (std::size_t qi = 0; qi < scene.queries.size(); ++qi) {
      const pcl::PointXYZ& q = scene.queries[qi];
      const std::string at = "query " + std::to_string(qi) + (sorted ? "" : " unsorted");
      for (const int k : {1, 4, 16}) {
        Neighbours a, b;
        a.found = ours.nearestKSearch(q, k, a.indices, a.sqr_dists);
        b.found = ref.nearestKSearch(q, k, b.indices, b.sqr_dists);
        const Neighbours brute =
            bruteForce(*scene.cloud, scene.indices.get(), q, k, kInfF);
        EXPECT_EQ(a.indices, brute.indices) << at << " k " << k;
        EXPECT_EQ(a.sqr_dists, brute.sqr_dists) << at << " k " << k;
        expectSameAsPcl(a, b, true, at + " k " + std::to_string(k));
      }
      for (const double radius : scene.radii)
        for (const unsigned max_nn : {0u, 5u}) {
          Neighbours a, b;
          a.found = ours.radiusSearch(q, radius, a.indices, a.sqr_dists, max_nn);
          b.found = ref.radiusSearch(q, radius, b.indices, b.sqr_dists, max_nn);
          const std::string what = at + " radius " + std::to_string(radius) + " max_nn " +
                                   std::to_string(max_nn);
          Neighbours brute =
              bruteForce(*scene.cloud, scene.indices.get(), q,
                         max_nn ? max_nn : scene.cloud->size(), float(radius * radius));
          if (!sorted && max_nn == 0) { // tree order: compare as sets
            expectSameAsPcl(a, brute, false, what + " (brute force)");
          } else {
            EXPECT_EQ(a.indices, brute.indices) << what;
            EXPECT_EQ(a.sqr_dists, brute.sqr_dists) << what;
          }
          expectSameAsPcl(a, b, max_nn != 0, what);
        }
    }
  }
}

} // namespace

TEST(MortonKdTree, SurfaceCloudMatchesPclKdTree)
{
  Scene scene;
  scene.cloud = surfaceCloud(3000, 11);
  scene.queries = queriesFor(*scene.cloud, 12);
  scene.radii = {0.02, 0.05, 0.1};
  compareWithPcl(scene);
}

TEST(MortonKdTree, DuplicatePointsMatchPclKdTree)
{
  Scene scene;
  scene.cloud = surfaceCloud(1500, 21);
  Rng rng(22);
  for (int i = 0; i < 600; ++i) // some points twice, some three times or more
    scene.cloud->push_back((*scene.cloud)[rng.index(400)]);
  scene.queries = queriesFor(*scene.cloud, 23);
  scene.radii = {0.03, 0.08};
  compareWithPcl(scene);
}

TEST(MortonKdTree, GridWithExactTiesMatchesPclKdTree)
{
  Scene scene;
  scene.cloud = gridCloud();
  scene.queries = gridQueries(*scene.cloud);
  // Exactly the grid spacing (points on the sphere are excluded: strict), and between.
  scene.radii = {1 / 64.0, 1.5 / 64.0, 2 / 64.0};
  compareWithPcl(scene);
}

TEST(MortonKdTree, NonFinitePointsAndAnIndexSubsetMatchPclKdTree)
{
  Scene scene;
  scene.cloud = surfaceCloud(2500, 31);
  Rng rng(32);
  for (auto& p : *scene.cloud) {
    const std::uint64_t r = rng.index(20);
    if (r == 0)
      p.x = kNaN;
    else if (r == 1)
      p.z = -kInfF;
  }
  scene.cloud->is_dense = false;
  scene.queries = queriesFor(*scene.cloud, 33);
  scene.radii = {0.04};
  compareWithPcl(scene);

  // 60 % of the points, shuffled, non-finite ones included.
  scene.indices = std::make_shared<pcl::Indices>();
  for (std::size_t i = 0; i < scene.cloud->size(); ++i)
    if (rng.uniform() < 0.6)
      scene.indices->push_back(pcl::index_t(i));
  for (std::size_t i = scene.indices->size(); i > 1; --i)
    std::swap((*scene.indices)[i - 1], (*scene.indices)[rng.index(i)]);
  compareWithPcl(scene);
}

TEST(MortonKdTree, IndexAndBatchOverloadsMatchPclKdTree)
{
  const auto cloud = surfaceCloud(2000, 41);
  auto indices = std::make_shared<pcl::Indices>();
  for (pcl::index_t i = 0; i < pcl::index_t(cloud->size()); i += 3)
    indices->push_back(i);
  for (const bool with_indices : {false, true}) {
    MortonKdTree<pcl::PointXYZ> ours;
    pcl::search::KdTree<pcl::PointXYZ> ref;
    const auto used = with_indices ? indices : nullptr;
    ours.setInputCloud(cloud, used);
    ref.setInputCloud(cloud, used);
    // nearestKSearch(i, ...) queries cloud[indices[i]] when indices were given.
    const pcl::index_t n = with_indices ? pcl::index_t(indices->size()) : 100;
    for (pcl::index_t i = 0; i < n; i += 9) {
      Neighbours a, b;
      a.found = ours.nearestKSearch(i, 4, a.indices, a.sqr_dists);
      b.found = ref.nearestKSearch(i, 4, b.indices, b.sqr_dists);
      expectSameAsPcl(a, b, true, "index " + std::to_string(i));
      a.found = ours.radiusSearch(i, 0.05, a.indices, a.sqr_dists);
      b.found = ref.radiusSearch(i, 0.05, b.indices, b.sqr_dists);
      expectSameAsPcl(a, b, false, "radius, index " + std::to_string(i));
      a.found = ours.nearestKSearch(*cloud, i, 1, a.indices, a.sqr_dists);
      b.found = ref.nearestKSearch(*cloud, i, 1, b.indices, b.sqr_dists);
      expectSameAsPcl(a, b, true, "cloud, index " + std::to_string(i));
    }
    // The batch overloads (every point of `cloud` listed in `queries`).
    const pcl::Indices queries = {0, 5, 17, 1999};
    std::vector<pcl::Indices> ia, ib;
    std::vector<std::vector<float>> da, db;
    ours.nearestKSearch(*cloud, queries, 16, ia, da);
    ref.nearestKSearch(*cloud, queries, 16, ib, db);
    ASSERT_EQ(ia.size(), queries.size());
    for (std::size_t j = 0; j < queries.size(); ++j)
      expectSameAsPcl({int(ia[j].size()), ia[j], da[j]},
                      {int(ib[j].size()), ib[j], db[j]}, true,
                      "batch " + std::to_string(j));
    ours.radiusSearch(*cloud, queries, 0.05, ia, da, 3);
    ref.radiusSearch(*cloud, queries, 0.05, ib, db, 3);
    for (std::size_t j = 0; j < queries.size(); ++j)
      expectSameAsPcl({int(ia[j].size()), ia[j], da[j]},
                      {int(ib[j].size()), ib[j], db[j]}, true,
                      "radius batch " + std::to_string(j));
  }
}

TEST(MortonKdTree, PointXYZLMatchesPclKdTree)
{
  const auto xyz = surfaceCloud(1000, 51);
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZL>>();
  for (std::size_t i = 0; i < xyz->size(); ++i) {
    pcl::PointXYZL p;
    p.x = (*xyz)[i].x;
    p.y = (*xyz)[i].y;
    p.z = (*xyz)[i].z;
    p.label = std::uint32_t(i % 5);
    cloud->push_back(p);
  }
  MortonKdTree<pcl::PointXYZL> ours;
  pcl::search::KdTree<pcl::PointXYZL> ref;
  ours.setInputCloud(cloud);
  ref.setInputCloud(cloud);
  for (const auto& qxyz : queriesFor(*xyz, 52)) {
    pcl::PointXYZL q;
    q.x = qxyz.x;
    q.y = qxyz.y;
    q.z = qxyz.z;
    Neighbours a, b;
    a.found = ours.nearestKSearch(q, 4, a.indices, a.sqr_dists);
    b.found = ref.nearestKSearch(q, 4, b.indices, b.sqr_dists);
    expectSameAsPcl(a, b, true, "k 4");
    a.found = ours.radiusSearch(q, 0.06, a.indices, a.sqr_dists);
    b.found = ref.radiusSearch(q, 0.06, b.indices, b.sqr_dists);
    expectSameAsPcl(a, b, false, "radius");
  }
}

TEST(MortonKdTree, EdgeCasesGiveNoResults)
{
  MortonKdTree<pcl::PointXYZ> tree;
  EXPECT_EQ(tree.getName(), "MortonKdTree");
  EXPECT_TRUE(tree.getSortedResults());
  pcl::Indices indices = {7, 8};
  std::vector<float> sqr_dists = {1.0f, 2.0f};
  const pcl::PointXYZ origin(0.0f, 0.0f, 0.0f);
  // No cloud set.
  EXPECT_EQ(tree.nearestKSearch(origin, 1, indices, sqr_dists), 0);
  EXPECT_TRUE(indices.empty());
  EXPECT_TRUE(sqr_dists.empty());

  const auto cloud = std::make_shared<Cloud>();
  cloud->push_back(pcl::PointXYZ(1.0f, 0.0f, 0.0f));
  cloud->push_back(pcl::PointXYZ(kNaN, 0.0f, 0.0f));
  cloud->push_back(pcl::PointXYZ(0.0f, 2.0f, 0.0f));
  cloud->push_back(pcl::PointXYZ(0.0f, 0.0f, -3.0f));
  cloud->is_dense = false;
  tree.setInputCloud(cloud);
  const auto expectNothing = [&](int found, const std::string& what) {
    EXPECT_EQ(found, 0) << what;
    EXPECT_TRUE(indices.empty()) << what;
    EXPECT_TRUE(sqr_dists.empty()) << what;
    indices = {7};
    sqr_dists = {1.0f};
  };
  for (const pcl::PointXYZ q :
       {pcl::PointXYZ(kNaN, 0.0f, 0.0f), pcl::PointXYZ(0.0f, kInfF, 0.0f),
        pcl::PointXYZ(0.0f, 0.0f, -kInfF)}) {
    expectNothing(tree.nearestKSearch(q, 1, indices, sqr_dists), "non-finite, k 1");
    expectNothing(tree.nearestKSearch(q, 3, indices, sqr_dists), "non-finite, k 3");
    expectNothing(tree.radiusSearch(q, 10.0, indices, sqr_dists), "non-finite, radius");
  }
  expectNothing(tree.nearestKSearch(origin, 0, indices, sqr_dists), "k 0");
  expectNothing(tree.nearestKSearch(origin, -2, indices, sqr_dists), "k -2");
  expectNothing(tree.radiusSearch(origin, 0.0, indices, sqr_dists), "radius 0");
  expectNothing(tree.radiusSearch(origin, -5.0, indices, sqr_dists), "radius -5");
  expectNothing(tree.radiusSearch(origin, std::nan(""), indices, sqr_dists), "NaN");
  expectNothing(tree.radiusSearch(origin, 1.0, indices, sqr_dists), "strict radius");

  // k beyond the finite points: all three, sorted; an infinite radius: all three.
  EXPECT_EQ(tree.nearestKSearch(origin, 10, indices, sqr_dists), 3);
  EXPECT_EQ(indices, (pcl::Indices{0, 2, 3}));
  EXPECT_EQ(sqr_dists, (std::vector<float>{1.0f, 4.0f, 9.0f}));
  EXPECT_EQ(tree.radiusSearch(origin, std::numeric_limits<double>::infinity(), indices,
                              sqr_dists),
            3);
  EXPECT_EQ(indices, (pcl::Indices{0, 2, 3}));
  EXPECT_EQ(tree.radiusSearch(origin, 2.5, indices, sqr_dists, 1), 1);
  EXPECT_EQ(indices, (pcl::Indices{0}));

  // An empty index list, an empty cloud, and a cloud without finite points.
  tree.setInputCloud(cloud, std::make_shared<pcl::Indices>());
  expectNothing(tree.nearestKSearch(origin, 1, indices, sqr_dists), "no indices, k 1");
  expectNothing(tree.radiusSearch(origin, 1e9, indices, sqr_dists), "no indices, radius");
  tree.setInputCloud(std::make_shared<Cloud>());
  expectNothing(tree.nearestKSearch(origin, 1, indices, sqr_dists), "empty, k 1");
  expectNothing(tree.radiusSearch(origin, 1e9, indices, sqr_dists), "empty, radius");
  auto nan_cloud = std::make_shared<Cloud>();
  nan_cloud->push_back(pcl::PointXYZ(kNaN, kNaN, kNaN));
  nan_cloud->is_dense = false;
  tree.setInputCloud(nan_cloud);
  expectNothing(tree.nearestKSearch(origin, 4, indices, sqr_dists), "all NaN, k 4");
}

TEST(MortonKdTree, InvalidInputThrowsAndKeepsTheTree)
{
  MortonKdTree<pcl::PointXYZ> tree;
  const auto cloud = std::make_shared<Cloud>();
  cloud->push_back(pcl::PointXYZ(1.0f, 0.0f, 0.0f));
  cloud->push_back(pcl::PointXYZ(0.0f, 1.0f, 0.0f));
  tree.setInputCloud(cloud);
  EXPECT_THROW(tree.setInputCloud(nullptr), InvalidArgumentError);
  EXPECT_THROW(
      tree.setInputCloud(cloud, std::make_shared<pcl::Indices>(pcl::Indices{0, 2})),
      InvalidArgumentError);
  EXPECT_THROW(
      tree.setInputCloud(cloud, std::make_shared<pcl::Indices>(pcl::Indices{-1})),
      InvalidArgumentError);
  EXPECT_THROW(tree.setNumberOfThreads(-1), InvalidArgumentError);
  EXPECT_TRUE(tree.getInputCloud() == cloud);
  EXPECT_FALSE(tree.getIndices());
  pcl::Indices indices;
  std::vector<float> sqr_dists;
  EXPECT_EQ(tree.nearestKSearch(pcl::PointXYZ(0.0f, 0.9f, 0.0f), 1, indices, sqr_dists),
            1);
  EXPECT_EQ(indices, (pcl::Indices{1}));
}

TEST(MortonKdTree, ResultsDoNotDependOnThreads)
{
  // 120k points: a parallel build; queries from four threads at once, coherent or not.
  const auto cloud = surfaceCloud(120000, 61);
  const auto queries = queriesFor(*cloud, 62);
  MortonKdTree<pcl::PointXYZ> serial, parallel;
  serial.setNumberOfThreads(1);
  parallel.setNumberOfThreads(3);
  serial.setInputCloud(cloud);
  parallel.setInputCloud(cloud);
  const auto run = [&](const MortonKdTree<pcl::PointXYZ>& tree, std::size_t begin,
                       std::size_t step, std::vector<Neighbours>& out) {
    for (std::size_t i = begin; i < queries.size(); i += step) {
      out[i].found = tree.nearestKSearch(queries[i], i % 2 ? 1 : 8, out[i].indices,
                                         out[i].sqr_dists);
      Neighbours r;
      r.found = tree.radiusSearch(queries[i], 0.01, r.indices, r.sqr_dists);
      out[i].indices.insert(out[i].indices.end(), r.indices.begin(), r.indices.end());
    }
  };
  std::vector<Neighbours> expected(queries.size()), actual(queries.size());
  run(serial, 0, 1, expected);
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < 4; ++t)
    threads.emplace_back([&, t] { run(parallel, t, 4, actual); });
  for (auto& t : threads)
    t.join();
  for (std::size_t i = 0; i < queries.size(); ++i) {
    EXPECT_EQ(actual[i].indices, expected[i].indices) << "query " << i;
    EXPECT_EQ(actual[i].sqr_dists, expected[i].sqr_dists) << "query " << i;
  }
  // And the parallel tree's nearest points are the brute force's.
  for (std::size_t i = 0; i < queries.size(); i += 97) {
    const Neighbours brute = bruteForce(*cloud, nullptr, queries[i], 1, kInfF);
    EXPECT_EQ(actual[i].indices.front(), brute.indices.front()) << "query " << i;
  }
}

// Normals from pcl::NormalEstimation with our search and with pcl::search::KdTree.
// The neighbourhoods are equal as sets and start with the query point itself (sorted, no
// duplicates); on the lattice PCL's covariance sums are exact in float, so the order of
// the other neighbours cannot change a bit.
TEST(MortonKdTree, NormalEstimationGivesTheSameNormals)
{
  const auto cloud = withoutDuplicates(surfaceCloud(3000, 71));
  const auto normals = [&](const pcl::search::Search<pcl::PointXYZ>::Ptr& search) {
    pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
    estimation.setInputCloud(cloud);
    estimation.setSearchMethod(search);
    estimation.setRadiusSearch(0.08);
    pcl::PointCloud<pcl::Normal> out;
    estimation.compute(out);
    return out;
  };
  const auto ours = normals(std::make_shared<MortonKdTree<pcl::PointXYZ>>());
  const auto ref = normals(std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  ASSERT_EQ(ours.size(), cloud->size());
  ASSERT_EQ(ref.size(), cloud->size());
  std::size_t finite = 0;
  for (std::size_t i = 0; i < ours.size(); ++i) {
    const float a[4] = {ours[i].normal_x, ours[i].normal_y, ours[i].normal_z,
                        ours[i].curvature};
    const float b[4] = {ref[i].normal_x, ref[i].normal_y, ref[i].normal_z,
                        ref[i].curvature};
    finite += std::isfinite(a[0]);
    for (int c = 0; c < 4; ++c)
      EXPECT_TRUE(a[c] == b[c] || (std::isnan(a[c]) && std::isnan(b[c])))
          << "point " << i << " component " << c << ": " << a[c] << " vs " << b[c];
  }
  EXPECT_GT(finite, cloud->size() * 9 / 10);
}

// Clusters do not depend on the order of a radius search's results (PCL sorts each
// cluster's indices); sorted results skip the first neighbour, the query itself.
TEST(MortonKdTree, EuclideanClusterExtractionGivesTheSameClusters)
{
  auto cloud = surfaceCloud(2000, 81);
  Rng rng(82);
  for (int i = 0; i < 100; ++i) // isolated points: clusters of one, filtered out
    cloud->push_back(latticePoint(rng.uniform(-1.0, 1.0), rng.uniform(0.6, 1.0),
                                  rng.uniform(-1.0, 1.0)));
  cloud = withoutDuplicates(cloud); // else "the first neighbour is the query" may fail
  for (const bool sorted : {false, true}) {
    const auto clusters = [&](const pcl::search::Search<pcl::PointXYZ>::Ptr& search) {
      pcl::EuclideanClusterExtraction<pcl::PointXYZ> extraction;
      extraction.setInputCloud(cloud);
      extraction.setSearchMethod(search);
      extraction.setClusterTolerance(0.045);
      extraction.setMinClusterSize(2);
      std::vector<pcl::PointIndices> out;
      extraction.extract(out);
      return out;
    };
    const auto ours = clusters(std::make_shared<MortonKdTree<pcl::PointXYZ>>(sorted));
    const auto ref =
        clusters(std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>(sorted));
    ASSERT_EQ(ours.size(), ref.size()) << "sorted " << sorted;
    EXPECT_GT(ours.size(), 1u);
    for (std::size_t c = 0; c < ours.size(); ++c)
      EXPECT_EQ(ours[c].indices, ref[c].indices) << "cluster " << c;
  }
}
