#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/sampling/mesh_sampler.h>

#include "synthetic_plant.h"

using plantnbv::MeshSampler;
using plantnbv::PartLabel;
using plantnbv::TriangleMesh;

namespace {
/// Three disjoint right triangles in planes z = 0, 1, 2 with areas 1 : 2 : 5, plus a
/// degenerate one (zero area) in z = 3.
std::shared_ptr<TriangleMesh> threeTriangles()
{
  auto m = std::make_shared<TriangleMesh>();
  const float legs[] = {1.0f, std::sqrt(2.0f), std::sqrt(5.0f)};
  for (int k = 0; k < 3; ++k) {
    const auto base = static_cast<std::uint32_t>(m->vertices.size());
    const float z = static_cast<float>(k);
    m->vertices.insert(m->vertices.end(),
                       {{0, 0, z}, {2 * legs[k], 0, z}, {0, legs[k], z}});
    m->triangles.push_back({base, base + 1, base + 2});
  }
  m->vertices.insert(m->vertices.end(), {{0, 0, 3}, {1, 0, 3}, {2, 0, 3}});
  m->triangles.push_back({9, 10, 11});
  m->labels = {PartLabel::stem, PartLabel::leaflet, PartLabel::fruit, PartLabel::petiole};
  return m;
}
} // namespace

TEST(MeshSampler, AreaWeightedShares)
{
  MeshSampler sampler;
  sampler.setInputMesh(threeTriangles());
  EXPECT_NEAR(sampler.getSurfaceArea(), 8.0, 1e-5);
  const std::size_t n = 80000;
  sampler.setNumberOfPoints(n);
  sampler.setSeed(3);
  sampler.setNumberOfThreads(2); // each point keeps its own triangle's label
  pcl::PointCloud<pcl::PointXYZL> cloud;
  sampler.sample(cloud);
  ASSERT_EQ(cloud.size(), n);
  std::size_t count[4] = {0, 0, 0, 0};
  for (const auto& p : cloud) {
    const int k = static_cast<int>(p.z);
    ASSERT_EQ(p.z, static_cast<float>(k));
    ++count[k];
    // The label is the triangle's: z = 0 stem, 1 leaflet, 2 fruit.
    EXPECT_EQ(p.label, static_cast<std::uint32_t>(k == 0   ? PartLabel::stem
                                                  : k == 1 ? PartLabel::leaflet
                                                           : PartLabel::fruit));
  }
  EXPECT_EQ(count[3], 0u); // zero area: never sampled
  const double shares[] = {1.0 / 8.0, 2.0 / 8.0, 5.0 / 8.0};
  for (int k = 0; k < 3; ++k) {
    // 5 standard deviations of a binomial count: fails by chance with p < 1e-6.
    const double sd = std::sqrt(n * shares[k] * (1.0 - shares[k]));
    EXPECT_NEAR(static_cast<double>(count[k]), n * shares[k], 5.0 * sd)
        << "triangle " << k;
  }
}

TEST(MeshSampler, PointsLieInsideTheirTriangleAndFillItUniformly)
{
  auto mesh = std::make_shared<TriangleMesh>();
  mesh->vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh->triangles = {{0, 1, 2}};
  MeshSampler sampler;
  sampler.setInputMesh(mesh);
  sampler.setNumberOfPoints(40000);
  pcl::PointCloud<pcl::PointXYZ> cloud;
  sampler.sample(cloud);
  std::size_t near_corner =
      0; // inside the sub-triangle x + y < 0.5: a quarter of the area
  for (const auto& p : cloud) {
    EXPECT_GE(p.x, 0.0f);
    EXPECT_GE(p.y, 0.0f);
    EXPECT_LE(p.x + p.y, 1.0f + 1e-6f);
    near_corner += (p.x + p.y < 0.5f);
  }
  EXPECT_NEAR(near_corner / 40000.0, 0.25, 5 * std::sqrt(0.25 * 0.75 / 40000.0));
}

TEST(MeshSampler, SameSeedSameCloudOtherSeedOtherCloud)
{
  auto plant = std::make_shared<TriangleMesh>(plantnbv::test::makeSyntheticPlant());
  MeshSampler sampler;
  sampler.setInputMesh(plant);
  sampler.setNumberOfPoints(5000);
  sampler.setSeed(11);
  pcl::PointCloud<pcl::PointXYZ> a, b, c;
  sampler.sample(a);
  sampler.sample(b);
  sampler.setSeed(12);
  sampler.sample(c);
  ASSERT_EQ(a.size(), b.size());
  bool differs = false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].getVector3fMap(), b[i].getVector3fMap());
    differs = differs || a[i].x != c[i].x;
  }
  EXPECT_TRUE(differs);
  EXPECT_TRUE(a.is_dense);
  EXPECT_EQ(a.width, 5000u);
  EXPECT_EQ(a.height, 1u);
}

namespace {
/// The points of MeshSampler::sample drawn as its documentation says, each triangle
/// found by std::upper_bound over the whole table of cumulative areas.
std::vector<Eigen::Vector3f> drawWithWholeTableSearch(const TriangleMesh& mesh,
                                                      std::size_t n, std::uint64_t seed)
{
  std::vector<double> cumulative;
  double total = 0.0;
  for (std::size_t t = 0; t < mesh.size(); ++t)
    cumulative.push_back(total += mesh.triangleArea(t));
  const auto last_with_area =
      std::lower_bound(cumulative.begin(), cumulative.end(), total);
  plantnbv::Rng rng(seed);
  std::vector<Eigen::Vector3f> points;
  for (std::size_t i = 0; i < n; ++i) {
    const double u = rng.uniform() * total;
    const auto t = static_cast<std::size_t>(
        std::min(std::upper_bound(cumulative.begin(), cumulative.end(), u),
                 last_with_area) -
        cumulative.begin());
    const auto& tri = mesh.triangles[t];
    const Eigen::Vector3d a = mesh.vertices[tri[0]].cast<double>();
    const Eigen::Vector3d b = mesh.vertices[tri[1]].cast<double>();
    const Eigen::Vector3d c = mesh.vertices[tri[2]].cast<double>();
    const double s = std::sqrt(rng.uniform());
    const double r = rng.uniform();
    points.push_back(((1.0 - s) * a + s * (1.0 - r) * b + s * r * c).cast<float>());
  }
  return points;
}

/// Triangles of areas spread over 16 orders of magnitude, with runs of zero-area ones
/// (the guide's slices then hold many triangles or none) and a run of equal areas (whose
/// cumulative sums can fall on a slice's start exactly).
TriangleMesh unevenTriangles()
{
  TriangleMesh m;
  plantnbv::Rng rng(5);
  for (int t = 0; t < 3000; ++t) {
    const auto base = static_cast<std::uint32_t>(m.vertices.size());
    const float z = static_cast<float>(t);
    float leg = 0.5f;
    if (t % 7 == 3 || (t >= 1000 && t < 1200))
      leg = 0.0f;
    else if (t < 2000)
      leg = static_cast<float>(std::pow(10.0, rng.uniform(-8.0, 0.0)));
    m.vertices.insert(m.vertices.end(), {{0, 0, z}, {leg, 0, z}, {0, 1, z}});
    m.triangles.push_back({base, base + 1, base + 2});
  }
  return m;
}
} // namespace

TEST(MeshSampler, TrianglesAreThoseOfASearchOverTheWholeAreaTable)
{
  const TriangleMesh meshes[] = {plantnbv::test::makeSyntheticPlant(), unevenTriangles(),
                                 *threeTriangles()};
  for (const TriangleMesh& mesh : meshes)
    for (std::uint64_t seed : {0u, 9u}) {
      const std::size_t n = 140000; // the random numbers are drawn in several batches
      const std::vector<Eigen::Vector3f> expected =
          drawWithWholeTableSearch(mesh, n, seed);
      for (int threads : {1, 3}) { // the points are made on several threads at once
        MeshSampler sampler;
        sampler.setInputMesh(std::make_shared<TriangleMesh>(mesh));
        sampler.setNumberOfPoints(n);
        sampler.setSeed(seed);
        sampler.setNumberOfThreads(threads);
        EXPECT_EQ(sampler.getNumberOfThreads(), threads);
        pcl::PointCloud<pcl::PointXYZ> cloud;
        sampler.sample(cloud);
        ASSERT_EQ(cloud.size(), n);
        std::size_t differ = 0;
        for (std::size_t i = 0; i < n; ++i)
          differ += cloud[i].getVector3fMap() != expected[i];
        EXPECT_EQ(differ, 0u) << mesh.size() << " triangles, seed " << seed << ", "
                              << threads << " threads";
      }
    }
}

TEST(MeshSampler, RejectsBadInput)
{
  MeshSampler sampler;
  pcl::PointCloud<pcl::PointXYZ> cloud;
  EXPECT_THROW(sampler.sample(cloud), plantnbv::InvalidArgumentError);
  EXPECT_THROW(sampler.setInputMesh(nullptr), plantnbv::InvalidArgumentError);
  EXPECT_THROW(sampler.setNumberOfPoints(0), plantnbv::InvalidArgumentError);
  EXPECT_THROW(sampler.setNumberOfThreads(-1), plantnbv::InvalidArgumentError);
  auto flat = std::make_shared<TriangleMesh>();
  flat->vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  flat->triangles = {{0, 1, 2}};
  EXPECT_THROW(sampler.setInputMesh(flat), plantnbv::InvalidArgumentError);
  EXPECT_THROW(sampler.setInputMesh(std::make_shared<TriangleMesh>()),
               plantnbv::InvalidArgumentError);
}
