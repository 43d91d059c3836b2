#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <unistd.h>
#include <vector>

#include <gtest/gtest.h>
#include <octomap/OcTree.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/common/voxel_lattice.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/octree/occupancy_map_snapshot.h>
#include <plantnbv/octree/octree_conversion.h>
#include <plantnbv/octree/update_region.h>

using plantnbv::CloudXYZ;
using plantnbv::OccupancyMap;
using plantnbv::OccupancyMapSnapshot;
using plantnbv::OccupiedVoxelOptions;
using plantnbv::VoxelState;

namespace {

/// OctoMap's own insertion with the same parameters: the reference.
std::unique_ptr<octomap::OcTree> makeReference(const OccupancyMap::Config& c)
{
  auto tree = std::make_unique<octomap::OcTree>(c.resolution_m);
  tree->setProbHit(c.prob_hit);
  tree->setProbMiss(c.prob_miss);
  tree->setClampingThresMin(c.clamp_min);
  tree->setClampingThresMax(c.clamp_max);
  tree->setOccupancyThres(c.occupancy_threshold);
  return tree;
}

/// insertPointCloud(cloud, origin, max range), lazy_eval false, not discretized; the
/// non-finite points are left out (they crash OctoMap).
void referenceInsert(octomap::OcTree& tree, const CloudXYZ& cloud,
                     const Eigen::Vector3d& origin, double max_range_m)
{
  octomap::Pointcloud scan;
  for (const auto& p : cloud)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
      scan.push_back(p.x, p.y, p.z);
  tree.insertPointCloud(scan,
                        octomap::point3d(static_cast<float>(origin.x()),
                                         static_cast<float>(origin.y()),
                                         static_cast<float>(origin.z())),
                        max_range_m);
}

/// Every node (inner nodes and leaves, in the trees' own order) with the same key,
/// depth, log-odds and leaf-ness: the same tree, pruning included.
void expectSameTree(const octomap::OcTree& a, const octomap::OcTree& b)
{
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.getNumLeafNodes(), b.getNumLeafNodes());
  auto ia = a.begin_tree();
  auto ib = b.begin_tree();
  std::size_t differing = 0;
  for (; ia != a.end_tree() && ib != b.end_tree(); ++ia, ++ib) {
    const bool same = ia.getKey() == ib.getKey() && ia.getDepth() == ib.getDepth() &&
                      ia->getLogOdds() == ib->getLogOdds() && ia.isLeaf() == ib.isLeaf();
    if (!same && ++differing <= 5)
      ADD_FAILURE() << "node differs: depth " << ia.getDepth() << " / " << ib.getDepth()
                    << ", key (" << ia.getKey()[0] << ", " << ia.getKey()[1] << ", "
                    << ia.getKey()[2] << ") / (" << ib.getKey()[0] << ", "
                    << ib.getKey()[1] << ", " << ib.getKey()[2] << "), log-odds "
                    << ia->getLogOdds() << " / " << ib->getLogOdds();
  }
  EXPECT_EQ(differing, 0u);
  EXPECT_TRUE(ia == a.end_tree() && ib == b.end_tree());
}

pcl::PointXYZ point(double x, double y, double z)
{
  return pcl::PointXYZ(static_cast<float>(x), static_cast<float>(y),
                       static_cast<float>(z));
}

/// A hard frame for the traversal: random directions and distances (inside and beyond
/// the range), points on voxel faces, rays along the axes and the diagonals, points in
/// the sensor's voxel, duplicates, and a dense patch (many rays into the same voxels).
CloudXYZ randomFrame(plantnbv::Rng& rng, const Eigen::Vector3d& origin, double res,
                     double max_range, std::size_t n)
{
  CloudXYZ cloud;
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Vector3d d(rng.normal(), rng.normal(), rng.normal());
    d.normalize();
    const double r = rng.uniform(0.0, 1.4 * max_range);
    Eigen::Vector3d p = origin + r * d;
    switch (i % 8) {
    case 1: // on voxel faces
      p = (p / res).array().round().matrix() * res;
      break;
    case 2: // along an axis
      p = origin;
      p[static_cast<int>(rng.index(3))] += (rng.uniform() < 0.5 ? -r : r);
      break;
    case 3: { // along a diagonal
      const double s = r / std::sqrt(3.0);
      p = origin +
          Eigen::Vector3d(rng.uniform() < 0.5 ? -s : s, s, rng.uniform() < 0.5 ? -s : s);
      break;
    }
    case 4: // close to the sensor (often its own voxel)
      p = origin + d * rng.uniform(0.0, 1.5 * res);
      break;
    default:
      break;
    }
    cloud.push_back(point(p.x(), p.y(), p.z()));
    if (i % 50 == 0)
      cloud.push_back(cloud.back()); // duplicate
  }
  // A dense patch 0.6 range ahead.
  for (int u = 0; u < 30; ++u)
    for (int v = 0; v < 30; ++v)
      cloud.push_back(point(origin.x() + 0.6 * max_range,
                            origin.y() + (u - 15) * 0.3 * res,
                            origin.z() + (v - 15) * 0.3 * res));
  return cloud;
}

/// 4000 points seen from `origin`: three in four on a sphere of 0.25 m around `centre`,
/// the others beyond a range of 0.6 m (free space only).
CloudXYZ sphereFrame(plantnbv::Rng& rng, const Eigen::Vector3d& origin,
                     const Eigen::Vector3d& centre)
{
  CloudXYZ cloud;
  for (int i = 0; i < 4000; ++i) {
    Eigen::Vector3d d(rng.normal(), rng.normal(), rng.normal());
    d.normalize();
    const Eigen::Vector3d p =
        i % 4 == 0 ? origin + rng.uniform(0.62, 1.0) * d : centre + 0.25 * d;
    cloud.push_back(point(p.x(), p.y(), p.z()));
  }
  return cloud;
}

/// An organized depth frame (w x h pixels, focal length f px) from `origin` looking at
/// `target`: rays that hit a sphere (radius 0.2 m around `target`) give its point,
/// the others a background point 2 m away (beyond the range); every 7th pixel has no
/// return (NaN). Near the camera the rays cover every voxel: large uniform cubes.
CloudXYZ cameraFrame(const Eigen::Vector3d& origin, const Eigen::Vector3d& target, int w,
                     int h, double f)
{
  const Eigen::Vector3d z = (target - origin).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  CloudXYZ cloud;
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      if ((v * w + u) % 7 == 3) {
        const float nan = std::numeric_limits<float>::quiet_NaN();
        cloud.push_back(pcl::PointXYZ(nan, nan, nan));
        continue;
      }
      const Eigen::Vector3d d =
          (z + (u - w / 2.0) / f * x + (v - h / 2.0) / f * y).normalized();
      // |origin + t d - target| = 0.2
      const Eigen::Vector3d oc = origin - target;
      const double b = oc.dot(d);
      const double disc = b * b - (oc.squaredNorm() - 0.04);
      const double t = disc >= 0.0 ? -b - std::sqrt(disc) : 2.0;
      const Eigen::Vector3d p = origin + t * d;
      cloud.push_back(point(p.x(), p.y(), p.z()));
    }
  cloud.width = static_cast<std::uint32_t>(w);
  cloud.height = static_cast<std::uint32_t>(h);
  cloud.is_dense = false;
  return cloud;
}

/// OctoMap's binary encoding (readBinaryData) of a tree whose nodes on the path to `key`
/// are inner down to depth `leaf_depth`; every other child is a pruned leaf, free,
/// occupied or unknown in turn.
std::string prunedPathTree(const octomap::OcTreeKey& key, int leaf_depth)
{
  constexpr unsigned kFree = 1, kOccupied = 2, kUnknown = 0, kInner = 3;
  const unsigned kinds[3] = {kFree, kOccupied, kUnknown};
  std::string data;
  for (int depth = 0; depth < leaf_depth; ++depth) {
    const unsigned on_path =
        octomap::computeChildIdx(key, plantnbv::VoxelLattice::kTreeDepth - 1 - depth);
    unsigned bits = 0; // two bits per child, child 0 lowest
    for (unsigned i = 0; i < 8; ++i) {
      const bool inner = i == on_path && depth + 1 < leaf_depth;
      bits |= (inner ? kInner : kinds[(i + static_cast<unsigned>(depth)) % 3]) << (2 * i);
    }
    data.push_back(static_cast<char>(bits & 0xffu));
    data.push_back(static_cast<char>(bits >> 8));
  }
  return data;
}

/// A fresh path in the temporary directory, unique per test and process.
std::string tempPath(const std::string& name)
{
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return (std::filesystem::temp_directory_path() /
          ("plantnbv_" + std::string(info->name()) + "_" + std::to_string(::getpid()) +
           "_" + name))
      .string();
}

using VoxelKey = std::array<int, 3>;

/// Every voxel the tree knows and its log-odds (pruned leaves as their voxels).
std::map<VoxelKey, float> knownVoxels(const octomap::OcTree& tree)
{
  std::map<VoxelKey, float> voxels;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    const octomap::OcTreeKey k = it.getIndexKey();
    const int size =
        1 << (plantnbv::VoxelLattice::kTreeDepth - static_cast<int>(it.getDepth()));
    for (int x = 0; x < size; ++x)
      for (int y = 0; y < size; ++y)
        for (int z = 0; z < size; ++z)
          voxels[{k[0] + x, k[1] + y, k[2] + z}] = it->getLogOdds();
  }
  return voxels;
}

std::size_t occupiedCount(const octomap::OcTree& tree)
{
  CloudXYZ cloud;
  plantnbv::occupiedVoxelCentres(tree, cloud);
  return cloud.size();
}

} // namespace

TEST(OccupancyMap, DefaultsAreThePapers)
{
  const OccupancyMap::Config c;
  EXPECT_EQ(c.resolution_m, 0.003);
  EXPECT_EQ(c.prob_hit, 0.7);
  EXPECT_EQ(c.prob_miss, 0.4);
  EXPECT_EQ(c.clamp_min, 0.12);
  EXPECT_EQ(c.clamp_max, 0.97);
  EXPECT_EQ(c.occupancy_threshold, 0.5);
  EXPECT_EQ(c.max_range_m, 0.75);
  OccupancyMap map(c);
  const octomap::OcTree& tree = map.getOcTree();
  EXPECT_DOUBLE_EQ(tree.getResolution(), 0.003);
  EXPECT_NEAR(tree.getProbHit(), 0.7, 1e-6);
  EXPECT_NEAR(tree.getProbMiss(), 0.4, 1e-6);
  EXPECT_NEAR(tree.getClampingThresMin(), 0.12, 1e-6);
  EXPECT_NEAR(tree.getClampingThresMax(), 0.97, 1e-6);
  EXPECT_NEAR(tree.getOccupancyThres(), 0.5, 1e-6);
  EXPECT_EQ(tree.size(), 0u);
}

TEST(OccupancyMap, PlaneSeenFromTheFront)
{
  // A 10 x 10 cm plane x = 0.301 m (inside a voxel layer), seen from the origin.
  OccupancyMap map;
  CloudXYZ plane;
  std::set<std::tuple<int, int, int>> plane_voxels;
  for (int u = -50; u <= 50; ++u)
    for (int v = -50; v <= 50; ++v) {
      plane.push_back(point(0.301, u * 0.001, v * 0.001));
      octomap::OcTreeKey key;
      ASSERT_TRUE(map.computeKey(Eigen::Vector3d(0.301, u * 0.001, v * 0.001), key));
      plane_voxels.insert({key[0], key[1], key[2]});
    }
  map.insert(plane, Eigen::Vector3d(0.0, 0.0, 0.0));

  // Occupied exactly on the plane's voxels.
  const auto counts = map.countVoxels();
  EXPECT_EQ(counts.occupied, plane_voxels.size());
  EXPECT_EQ(map.getLastInsertStats().occupied_voxels, plane_voxels.size());
  for (double y : {-0.04, -0.01, 0.0, 0.02, 0.045})
    for (double z : {-0.04, 0.0, 0.03}) {
      const Eigen::Vector3d on(0.301, y, z);
      EXPECT_EQ(map.state(on), VoxelState::occupied) << y << " " << z;
      EXPECT_NEAR(map.probability(on), 0.7, 1e-6);
      // Free in front (on the rays), unknown behind and beside.
      EXPECT_EQ(map.state(Eigen::Vector3d(0.15, y / 2, z / 2)), VoxelState::free);
      EXPECT_EQ(map.state(Eigen::Vector3d(0.29, y * 0.29 / 0.301, z * 0.29 / 0.301)),
                VoxelState::free);
      EXPECT_EQ(map.state(Eigen::Vector3d(0.31, y, z)), VoxelState::unknown);
      EXPECT_EQ(map.state(Eigen::Vector3d(0.5, y, z)), VoxelState::unknown);
    }
  EXPECT_EQ(map.state(Eigen::Vector3d(0.15, 0.1, 0.0)), VoxelState::unknown);
  EXPECT_EQ(map.state(Eigen::Vector3d(-0.1, 0.0, 0.0)), VoxelState::unknown);
  octomap::OcTreeKey free_key;
  ASSERT_TRUE(map.computeKey(Eigen::Vector3d(0.15, 0.0, 0.0), free_key));
  EXPECT_TRUE(map.isKnown(free_key));
  EXPECT_NEAR(map.probability(free_key), 0.4, 1e-6);
  EXPECT_FLOAT_EQ(map.logOdds(free_key), map.getOcTree().getProbMissLog());
  EXPECT_GT(counts.free, 20000u); // the pyramid from the origin to the plane
  EXPECT_EQ(map.getLastInsertStats().free_voxels, counts.free); // first frame

  // The plane voxels as a cloud, as the octree conversion gives them.
  CloudXYZ centres;
  map.getOccupiedVoxelCentres(centres);
  EXPECT_EQ(centres.size(), plane_voxels.size());
  for (const auto& c : centres)
    EXPECT_NEAR(c.x, 0.301, 0.003);
}

// The map's occupied centres skip subtrees whose node is not occupied (its inner nodes
// hold their children's maximum) and are still the full walk's points, in its order; on
// a tree whose inner nodes do not (a lazy update), the skip would miss a voxel, which is
// why occupiedVoxelCentres walks everything unless told.
TEST(OccupancyMap, OccupiedCentresSkipFreeSubtreesAndGiveTheFullWalksPoints)
{
  OccupancyMap::Config config;
  config.resolution_m = 0.01;
  OccupancyMap map(config);
  plantnbv::Rng rng(21);
  for (const Eigen::Vector3d& origin :
       {Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(0.2, -0.1, 0.05),
        Eigen::Vector3d(-0.15, 0.1, 0.0)}) // later frames carve some earlier hits
    map.insert(randomFrame(rng, origin, config.resolution_m, config.max_range_m, 4000),
               origin);
  const auto expectSame = [&](const OccupiedVoxelOptions& options) {
    CloudXYZ full, skipping;
    plantnbv::occupiedVoxelCentres(map.getOcTree(), full, options);
    map.getOccupiedVoxelCentres(skipping, options);
    EXPECT_EQ(skipping.size(), full.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < std::min(full.size(), skipping.size()); ++i)
      differ += !(skipping[i].x == full[i].x && skipping[i].y == full[i].y &&
                  skipping[i].z == full[i].z);
    EXPECT_EQ(differ, 0u);
    return full.size();
  };
  OccupiedVoxelOptions options;
  EXPECT_GT(expectSame(options), 1000u);
  // Both are OctoMap's leaf iteration, each pruned leaf expanded (z fastest).
  const octomap::OcTree& tree = map.getOcTree();
  CloudXYZ iterated, walked;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    if (!tree.isNodeOccupied(*it))
      continue;
    const int n = 1 << (tree.getTreeDepth() - it.getDepth());
    const octomap::OcTreeKey& key = it.getKey();
    for (int x = key[0] - n / 2; x < key[0] + n - n / 2; ++x)
      for (int y = key[1] - n / 2; y < key[1] + n - n / 2; ++y)
        for (int z = key[2] - n / 2; z < key[2] + n - n / 2; ++z)
          iterated.push_back(point(tree.keyToCoord(static_cast<octomap::key_type>(x)),
                                   tree.keyToCoord(static_cast<octomap::key_type>(y)),
                                   tree.keyToCoord(static_cast<octomap::key_type>(z))));
  }
  map.getOccupiedVoxelCentres(walked);
  ASSERT_EQ(walked.size(), iterated.size());
  for (std::size_t i = 0; i < walked.size(); ++i)
    ASSERT_TRUE(walked[i].x == iterated[i].x && walked[i].y == iterated[i].y &&
                walked[i].z == iterated[i].z)
        << i;
  options.threshold = 0.8; // two hits or more
  EXPECT_GT(expectSame(options), 10u);
  options.threshold = -1.0;
  options.roi.addBox(plantnbv::Box::fromMinMax(Eigen::Vector3d(0.0, -0.3, -0.3),
                                               Eigen::Vector3d(0.5, 0.3, 0.3)));
  EXPECT_GT(expectSame(options), 100u);

  octomap::OcTree lazy(0.01);
  const octomap::OcTreeKey free_key(32768, 32768, 32768), hit_key(32769, 32768, 32768);
  for (int i = 0; i < 3; ++i)
    lazy.updateNode(free_key, false);                 // the path above it holds "free"
  lazy.updateNode(hit_key, true, /*lazy_eval=*/true); // ... and still does
  CloudXYZ cloud;
  plantnbv::occupiedVoxelCentres(lazy, cloud);
  EXPECT_EQ(cloud.size(), 1u);
  OccupiedVoxelOptions trusting;
  trusting.inner_nodes_hold_max = true;
  plantnbv::occupiedVoxelCentres(lazy, cloud, trusting);
  EXPECT_EQ(cloud.size(), 0u);
}

TEST(OccupancyMap, PointsBeyondMaxRangeCarveFreeSpaceOnly)
{
  // The same plane at 1 m, beyond the 0.75 m range: free up to 0.75 m, nothing
  // occupied, unknown beyond.
  OccupancyMap map;
  CloudXYZ plane;
  for (int u = -20; u <= 20; ++u)
    for (int v = -20; v <= 20; ++v)
      plane.push_back(point(1.0, u * 0.002, v * 0.002));
  map.insert(plane, Eigen::Vector3d::Zero());
  EXPECT_EQ(map.countVoxels().occupied, 0u);
  EXPECT_EQ(map.getLastInsertStats().beyond_range, plane.size());
  EXPECT_EQ(map.state(Eigen::Vector3d(0.5, 0.0, 0.0)), VoxelState::free);
  EXPECT_EQ(map.state(Eigen::Vector3d(0.74, 0.0, 0.0)), VoxelState::free);
  EXPECT_EQ(map.state(Eigen::Vector3d(0.76, 0.0, 0.0)), VoxelState::unknown);
  EXPECT_EQ(map.state(Eigen::Vector3d(1.0, 0.0, 0.0)), VoxelState::unknown);
}

TEST(OccupancyMap, HitsAndMissesFollowTheLogOddsRuleWithClamping)
{
  // One voxel hit k times, another missed k times (one ray per frame through it): the
  // log-odds are the float sums of OctoMap's update, clamped, for every k.
  const OccupancyMap::Config config;
  OccupancyMap map(config);
  const float hit = static_cast<float>(std::log(0.7 / 0.3));
  const float miss = static_cast<float>(std::log(0.4 / 0.6));
  const float lo = static_cast<float>(std::log(0.12 / 0.88));
  const float hi = static_cast<float>(std::log(0.97 / 0.03));
  const Eigen::Vector3d target(0.2005, 0.0005, 0.0005);
  const Eigen::Vector3d passed(0.1005, 0.0005, 0.0005);
  CloudXYZ frame;
  frame.push_back(point(target.x(), target.y(), target.z()));
  octomap::OcTreeKey hit_key, miss_key;
  ASSERT_TRUE(map.computeKey(target, hit_key));
  ASSERT_TRUE(map.computeKey(passed, miss_key));
  float expected_hit = 0.0f, expected_miss = 0.0f;
  int clamped_hit_at = 0, clamped_miss_at = 0;
  for (int k = 1; k <= 8; ++k) {
    map.insert(frame, Eigen::Vector3d(0.0005, 0.0005, 0.0005));
    expected_hit += hit;
    if (expected_hit > hi) {
      expected_hit = hi;
      clamped_hit_at = clamped_hit_at ? clamped_hit_at : k;
    }
    expected_miss += miss;
    if (expected_miss < lo) {
      expected_miss = lo;
      clamped_miss_at = clamped_miss_at ? clamped_miss_at : k;
    }
    EXPECT_FLOAT_EQ(map.logOdds(hit_key), expected_hit) << k;
    EXPECT_FLOAT_EQ(map.logOdds(miss_key), expected_miss) << k;
    EXPECT_NEAR(map.probability(hit_key), 1.0 - 1.0 / (1.0 + std::exp(expected_hit)),
                1e-6);
  }
  // Clamped at 0.97 after 5 hits (5 x 0.847 > 3.476) and at 0.12 after 5 misses.
  EXPECT_EQ(clamped_hit_at, 5);
  EXPECT_EQ(clamped_miss_at, 5);
  EXPECT_NEAR(map.probability(hit_key), 0.97, 1e-6);
  EXPECT_NEAR(map.probability(miss_key), 0.12, 1e-6);
  EXPECT_EQ(map.state(hit_key), VoxelState::occupied);
  EXPECT_EQ(map.state(miss_key), VoxelState::free);

  // Now seen through: the hit voxel becomes a free one step by step from the clamp.
  CloudXYZ behind;
  behind.push_back(point(0.3005, 0.0005, 0.0005));
  float v = hi;
  for (int k = 1; k <= 12; ++k) {
    map.insert(behind, Eigen::Vector3d(0.0005, 0.0005, 0.0005));
    v = std::max(v + miss, lo);
    EXPECT_FLOAT_EQ(map.logOdds(hit_key), v) << k;
  }
  EXPECT_EQ(map.state(hit_key), VoxelState::free);
}

TEST(OccupancyMap, OneUpdatePerVoxelPerFrameAndHitWins)
{
  // Three points in one voxel: one hit. A point whose voxel another ray crosses: that
  // voxel is hit only (OctoMap's rule), once.
  OccupancyMap map;
  CloudXYZ frame;
  frame.push_back(point(0.1001, 0.0001, 0.0001));
  frame.push_back(point(0.1002, 0.0002, 0.0002));
  frame.push_back(point(0.1002, 0.0001, 0.0002));
  frame.push_back(point(0.2001, 0.0001, 0.0001)); // its ray crosses the voxel above
  map.insert(frame, Eigen::Vector3d(0.0001, 0.0001, 0.0001));
  octomap::OcTreeKey key;
  ASSERT_TRUE(map.computeKey(Eigen::Vector3d(0.1001, 0.0001, 0.0001), key));
  EXPECT_FLOAT_EQ(map.logOdds(key), map.getOcTree().getProbHitLog());
  EXPECT_EQ(map.getLastInsertStats().occupied_voxels, 2u);
}

TEST(OccupancyMap, NonFinitePointsNeverReachOctoMap)
{
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  CloudXYZ cloud;
  cloud.push_back(point(0.2, 0.01, 0.0));
  cloud.push_back(pcl::PointXYZ(nan, nan, nan));
  cloud.push_back(pcl::PointXYZ(0.2f, nan, 0.0f));
  cloud.push_back(pcl::PointXYZ(inf, 0.0f, 0.0f));
  cloud.push_back(pcl::PointXYZ(0.1f, 0.0f, -inf));
  cloud.push_back(point(0.1, -0.05, 0.02));
  cloud.push_back(point(2.0, 0.5, 0.1)); // beyond range
  cloud.is_dense = false;
  OccupancyMap map;
  map.insert(cloud, Eigen::Vector3d(0.0, 0.0, 0.0));
  EXPECT_EQ(map.getLastInsertStats().points, 7u);
  EXPECT_EQ(map.getLastInsertStats().non_finite, 4u);
  EXPECT_EQ(map.getLastInsertStats().beyond_range, 1u);
  EXPECT_EQ(map.countVoxels().occupied, 2u);

  // The same map as from the finite points alone, and as OctoMap's.
  CloudXYZ finite;
  for (const auto& p : cloud)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
      finite.push_back(p);
  OccupancyMap clean;
  clean.insert(finite, Eigen::Vector3d(0.0, 0.0, 0.0));
  expectSameTree(map.getOcTree(), clean.getOcTree());
  auto reference = makeReference(map.getConfig());
  referenceInsert(*reference, cloud, Eigen::Vector3d::Zero(), 0.75);
  expectSameTree(map.getOcTree(), *reference);

  // A frame of NaNs only changes nothing.
  CloudXYZ nans;
  nans.push_back(pcl::PointXYZ(nan, nan, nan));
  map.insert(nans, Eigen::Vector3d(0.0, 0.0, 0.0));
  expectSameTree(map.getOcTree(), *reference);
  map.insert(CloudXYZ(), Eigen::Vector3d(0.0, 0.0, 0.0));
  expectSameTree(map.getOcTree(), *reference);
}

TEST(OccupancyMap, EqualsOctoMapInsertPointCloudOneFrame)
{
  for (const double res : {0.003, 0.01, 0.05}) {
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
      plantnbv::Rng rng(seed);
      OccupancyMap::Config config;
      config.resolution_m = res;
      config.max_range_m = res == 0.003 ? 0.75 : 60 * res;
      const Eigen::Vector3d origin(rng.uniform(-1, 1), rng.uniform(-1, 1),
                                   rng.uniform(-1, 1));
      const CloudXYZ cloud =
          randomFrame(rng, origin, res, config.max_range_m, res == 0.003 ? 1000 : 3000);
      OccupancyMap map(config);
      map.setNumberOfThreads(2);
      map.insert(cloud, origin);
      auto reference = makeReference(config);
      referenceInsert(*reference, cloud, origin, config.max_range_m);
      SCOPED_TRACE("res " + std::to_string(res) + " seed " + std::to_string(seed));
      expectSameTree(map.getOcTree(), *reference);
      EXPECT_GT(map.getLastInsertStats().beyond_range, 0u);
    }
  }
}

TEST(OccupancyMap, EqualsOctoMapInsertPointCloudOverFrames)
{
  // Frames from different origins around a fixed surface (a sphere of radius 0.25 m
  // around the scene centre, and far points): voxels are hit and missed repeatedly,
  // reach both clamps, get pruned, then expanded again by later frames.
  plantnbv::Rng rng(11);
  OccupancyMap::Config config;
  config.resolution_m = 0.01;
  config.max_range_m = 0.6;
  OccupancyMap map(config);
  map.setNumberOfThreads(2);
  auto reference = makeReference(config);
  const Eigen::Vector3d centre(0.5, -0.2, 1.0);
  for (int frame = 0; frame < 12; ++frame) {
    const double yaw = 0.3 * frame;
    const Eigen::Vector3d origin =
        centre +
        Eigen::Vector3d(0.45 * std::cos(yaw), 0.45 * std::sin(yaw), 0.05 * (frame % 3));
    const CloudXYZ cloud = sphereFrame(rng, origin, centre);
    map.insert(cloud, origin);
    referenceInsert(*reference, cloud, origin, config.max_range_m);
    SCOPED_TRACE("frame " + std::to_string(frame));
    expectSameTree(map.getOcTree(), *reference);
  }
  // The walk met pruned nodes: the tree holds some.
  std::size_t pruned = 0;
  for (auto it = reference->begin_leafs(); it != reference->end_leafs(); ++it)
    pruned += it.getDepth() < reference->getTreeDepth();
  EXPECT_GT(pruned, 100u);
  // And clamped voxels of both kinds.
  std::size_t at_min = 0, at_max = 0;
  for (auto it = reference->begin_leafs(); it != reference->end_leafs(); ++it) {
    at_min += it->getLogOdds() == reference->getClampingThresMinLog();
    at_max += it->getLogOdds() == reference->getClampingThresMaxLog();
  }
  EXPECT_GT(at_min, 100u);
  EXPECT_GT(at_max, 10u);
}

TEST(OccupancyMap, EqualsOctoMapForDenseCameraFrames)
{
  // Dense frames: most free space is updated as whole octree nodes, which must give
  // OctoMap's voxels exactly, on an empty map, on a map with pruned and clamped nodes,
  // and on partly known subtrees. Origins move around the target and come back.
  OccupancyMap::Config config;
  config.resolution_m = 0.01;
  config.max_range_m = 0.6;
  OccupancyMap map(config);
  map.setNumberOfThreads(2);
  auto reference = makeReference(config);
  const Eigen::Vector3d target(0.3, 0.1, 0.5);
  for (int frame = 0; frame < 10; ++frame) {
    const double yaw = 0.25 * (frame % 5) - 0.5;
    const Eigen::Vector3d origin =
        target +
        Eigen::Vector3d(-0.45 * std::cos(yaw), 0.45 * std::sin(yaw), 0.02 * frame - 0.05);
    const CloudXYZ cloud = cameraFrame(origin, target, 160, 120, 110.0);
    map.insert(cloud, origin);
    referenceInsert(*reference, cloud, origin, config.max_range_m);
    SCOPED_TRACE("frame " + std::to_string(frame));
    expectSameTree(map.getOcTree(), *reference);
    const auto& stats = map.getLastInsertStats();
    // Far fewer tree updates than voxels: cubes were used.
    EXPECT_LT(stats.tree_updates * 2, stats.free_voxels + stats.occupied_voxels);
    EXPECT_GT(stats.occupied_voxels, 500u);
  }
}

TEST(OccupancyMap, OrganizedAndUnorganizedFramesGiveOctoMapsMap)
{
  // The rays are walked in tiles of the image (32 x 16 pixels; an unorganized cloud in
  // runs of points): a frame whose size is no multiple of a tile either way, the same
  // points as one row, and a cloud whose width x height is not its size must each give
  // OctoMap's map, every ray walked once.
  OccupancyMap::Config config;
  config.resolution_m = 0.01;
  config.max_range_m = 0.6;
  const Eigen::Vector3d target(0.3, 0.1, 0.5);
  const Eigen::Vector3d origin = target + Eigen::Vector3d(-0.45, 0.05, 0.03);
  // Over 4,096 points per thread at two threads: both thread counts are used.
  CloudXYZ organized = cameraFrame(origin, target, 101, 83, 60.0);
  CloudXYZ row = organized;
  row.width = static_cast<std::uint32_t>(row.size());
  row.height = 1;
  CloudXYZ inconsistent = organized;
  inconsistent.push_back(point(0.3, 0.1, 0.5)); // PCL makes it one row: undo that
  inconsistent.width = organized.width;
  inconsistent.height = organized.height;
  for (const CloudXYZ* cloud : {&organized, &row, &inconsistent})
    for (int threads : {1, 2}) {
      SCOPED_TRACE("width " + std::to_string(cloud->width) + ", height " +
                   std::to_string(cloud->height) + ", " + std::to_string(cloud->size()) +
                   " points, " + std::to_string(threads) + " threads");
      OccupancyMap map(config);
      map.setNumberOfThreads(threads);
      auto reference = makeReference(config);
      map.insert(*cloud, origin);
      referenceInsert(*reference, *cloud, origin, config.max_range_m);
      expectSameTree(map.getOcTree(), *reference);
    }
}

TEST(OccupancyMap, EqualsOctoMapOnExactTies)
{
  // From a voxel centre along axes and diagonals, with a resolution whose multiples are
  // exact in binary, two or three axes cross their borders at the same t, where
  // OctoMap steps z before y before x: a walk that breaks ties otherwise visits other
  // voxels. (Random rays almost never tie exactly.)
  OccupancyMap::Config config;
  config.resolution_m = 0.25;
  config.max_range_m = 4.0;
  const Eigen::Vector3d centre(0.125, 0.125, 0.125);
  CloudXYZ rays;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z)
        for (const double r : {0.3, 1.0, 2.375, 3.0, 5.0})
          if (x || y || z)
            rays.push_back(
                point(centre.x() + r * x, centre.y() + r * y, centre.z() + r * z));
  OccupancyMap map(config);
  map.insert(rays, centre);
  auto reference = makeReference(config);
  referenceInsert(*reference, rays, centre, config.max_range_m);
  expectSameTree(map.getOcTree(), *reference);
}

/// A sphere of `radius` around `centre` as a triangle mesh (latitude-longitude grid).
plantnbv::TriangleMesh sphereMesh(const Eigen::Vector3d& centre, double radius)
{
  plantnbv::TriangleMesh mesh;
  const int rings = 24, sectors = 48;
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const double theta = M_PI * i / rings, phi = 2.0 * M_PI * j / sectors;
      mesh.vertices.push_back(
          (centre + radius * Eigen::Vector3d(std::sin(theta) * std::cos(phi),
                                             std::sin(theta) * std::sin(phi),
                                             std::cos(theta)))
              .cast<float>());
    }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const auto v = [&](int r, int c) {
        return static_cast<std::uint32_t>(r * sectors + (c % sectors));
      };
      mesh.triangles.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
      mesh.triangles.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  return mesh;
}

/// Every voxel of `region` within `bounds` has the same node state and log-odds in both
/// maps. \return the voxels of the region that were compared.
std::size_t expectSameInRegion(const OccupancyMap& map, const OccupancyMap& full,
                               const plantnbv::UpdateRegion& region,
                               const plantnbv::Box& bounds)
{
  octomap::OcTreeKey lo, hi;
  EXPECT_TRUE(full.computeKey(bounds.min(), lo));
  EXPECT_TRUE(full.computeKey(bounds.max(), hi));
  std::size_t compared = 0, differing = 0;
  for (int x = lo[0]; x <= hi[0]; ++x)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int z = lo[2]; z <= hi[2]; ++z) {
        if (!region.containsKey(x, y, z))
          continue;
        const octomap::OcTreeKey key(static_cast<octomap::key_type>(x),
                                     static_cast<octomap::key_type>(y),
                                     static_cast<octomap::key_type>(z));
        ++compared;
        const bool known = map.isKnown(key);
        if (known != full.isKnown(key) || map.logOdds(key) != full.logOdds(key)) {
          if (++differing <= 5)
            ADD_FAILURE() << "voxel (" << x << ", " << y << ", " << z << "): known "
                          << known << ", log-odds " << map.logOdds(key)
                          << "; full map: " << full.logOdds(key);
        }
      }
  EXPECT_EQ(differing, 0u);
  return compared;
}

TEST(OccupancyMap, WithAnUpdateRegionItsVoxelsAreOctoMaps)
{
  // Frames of a sphere and of far points from around it, and hard random frames (axes,
  // diagonals, faces, the sensor's voxel): with a region of the sphere's surface and a
  // box, every voxel of the region equals OctoMap's full insertion, on 1 and 2 threads;
  // outside it, free space is left out.
  OccupancyMap::Config config;
  config.resolution_m = 0.01;
  config.max_range_m = 0.6;
  const Eigen::Vector3d centre(0.5, -0.2, 1.0);
  const plantnbv::Box bounds(centre, Eigen::Vector3d::Constant(1.6));
  auto region = std::make_shared<plantnbv::UpdateRegion>(config.resolution_m, bounds);
  region->addMesh(sphereMesh(centre, 0.25), config.resolution_m);
  region->addBox(plantnbv::Box(centre + Eigen::Vector3d(0.1, 0.3, -0.2),
                               Eigen::Vector3d(0.05, 0.1, 0.03)));
  // 1.6 m of 8 cm bricks: 20 bricks a side, one or two more where the bounds' faces fall
  // inside bricks.
  const std::size_t bounds_bricks =
      plantnbv::UpdateRegion::bricksOver(config.resolution_m, bounds);
  EXPECT_GE(bounds_bricks, 20u * 20u * 20u);
  EXPECT_LE(bounds_bricks, 22u * 22u * 22u);
  EXPECT_LT(region->brickCount() * 4, bounds_bricks);
  for (int threads : {1, 2}) {
    plantnbv::Rng rng(11);
    OccupancyMap map(config), full(config);
    map.setUpdateRegion(region);
    EXPECT_EQ(map.getUpdateRegion(), region);
    map.setNumberOfThreads(threads);
    full.setNumberOfThreads(threads);
    std::size_t outside = 0;
    for (int frame = 0; frame < 8; ++frame) {
      const double yaw = 0.7 * frame;
      const Eigen::Vector3d origin =
          centre +
          Eigen::Vector3d(0.45 * std::cos(yaw), 0.45 * std::sin(yaw), 0.05 * (frame % 3));
      const CloudXYZ cloud =
          frame % 4 == 3
              ? randomFrame(rng, origin, config.resolution_m, config.max_range_m, 3000)
              : sphereFrame(rng, origin, centre);
      map.insert(cloud, origin);
      full.insert(cloud, origin);
      const std::size_t hits_outside = map.getLastInsertStats().hits_outside_region;
      if (frame % 4 != 3) {
        EXPECT_EQ(hits_outside, 0u) << frame; // the sphere's points are in the region
      }
      outside += hits_outside;
    }
    EXPECT_GT(outside, 100u); // the random frames' hits are anywhere
    SCOPED_TRACE(threads);
    EXPECT_GT(expectSameInRegion(map, full, *region, bounds), 100000u);
    EXPECT_LT(map.countVoxels().free * 3, full.countVoxels().free * 2);
  }
  OccupancyMap other(OccupancyMap::Config{});
  EXPECT_THROW(other.setUpdateRegion(region), plantnbv::InvalidArgumentError);
  EXPECT_THROW(plantnbv::UpdateRegion(0.0, bounds), plantnbv::InvalidArgumentError);
  EXPECT_THROW(region->addBox(bounds, -1.0), plantnbv::InvalidArgumentError);
}

TEST(OccupancyMap, ChangedBricksHoldEveryVoxelThatAnInsertChanged)
{
  // Hard random frames, frames of far points (free space only) and dense camera frames
  // (large uniform cubes), around the origin where the bitset's 64^3-voxel blocks meet
  // on every axis, with and without an update region, on 1 and 2 threads: after each
  // insert every voxel that became known or whose log-odds changed lies in a brick
  // that getChangedBricks lists; each brick is listed once and holds a known voxel; the
  // bricks are given only for the revision just before the insert.
  OccupancyMap::Config config;
  config.resolution_m = 0.02;
  config.max_range_m = 0.4;
  const Eigen::Vector3d centre(0.01, -0.03, 0.02);
  const plantnbv::Box bounds(centre, Eigen::Vector3d::Constant(1.2));
  auto region = std::make_shared<plantnbv::UpdateRegion>(config.resolution_m, bounds);
  region->addBox(plantnbv::Box(centre, Eigen::Vector3d::Constant(0.3)));
  const int shift = OccupancyMap::kChangedBrickShift;
  for (int threads : {1, 2})
    for (bool with_region : {false, true}) {
      SCOPED_TRACE(std::to_string(threads) + " threads, region " +
                   std::to_string(with_region));
      plantnbv::Rng rng(21);
      OccupancyMap map(config);
      map.setNumberOfThreads(threads);
      if (with_region)
        map.setUpdateRegion(region);
      std::vector<VoxelKey> bricks{{1, 2, 3}};
      EXPECT_FALSE(map.getChangedBricks(0, bricks)); // nothing inserted
      EXPECT_FALSE(map.getChangedBricks(~std::uint64_t{0}, bricks));
      EXPECT_TRUE(bricks.empty());
      std::map<VoxelKey, float> before;
      for (int frame = 0; frame < 6; ++frame) {
        const double yaw = 1.1 * frame;
        const Eigen::Vector3d origin =
            centre + Eigen::Vector3d(0.25 * std::cos(yaw), 0.25 * std::sin(yaw),
                                     0.03 * (frame % 3));
        const CloudXYZ cloud =
            frame % 3 == 0
                ? randomFrame(rng, origin, config.resolution_m, config.max_range_m, 2000)
            : frame % 3 == 1 ? sphereFrame(rng, origin, centre)
                             : cameraFrame(origin, centre, 64, 48, 50.0);
        const std::uint64_t since = map.revision();
        map.insert(cloud, origin);
        ASSERT_TRUE(map.getChangedBricks(since, bricks)) << frame;
        EXPECT_FALSE(map.getChangedBricks(since - 1, bricks)) << frame;
        EXPECT_FALSE(map.getChangedBricks(since + 1, bricks)) << frame;
        ASSERT_TRUE(map.getChangedBricks(since, bricks)) << frame;
        const std::set<VoxelKey> listed(bricks.begin(), bricks.end());
        EXPECT_EQ(listed.size(), bricks.size()) << frame;
        const std::map<VoxelKey, float> after = knownVoxels(map.getOcTree());
        std::set<VoxelKey> known_bricks;
        std::size_t changed = 0, missed = 0;
        for (const auto& [key, log_odds] : after) {
          const VoxelKey brick{key[0] >> shift, key[1] >> shift, key[2] >> shift};
          known_bricks.insert(brick);
          const auto old = before.find(key);
          if (old != before.end() && old->second == log_odds)
            continue;
          ++changed;
          missed += listed.count(brick) == 0 ? 1 : 0;
        }
        EXPECT_GT(changed, 10u) << frame;
        EXPECT_EQ(missed, 0u) << frame;
        for (const VoxelKey& brick : listed)
          EXPECT_EQ(known_bricks.count(brick), 1u) << frame << ": (" << brick[0] << ", "
                                                   << brick[1] << ", " << brick[2] << ")";
        before = after;
      }
      map.clear();
      EXPECT_FALSE(map.getChangedBricks(map.revision() - 1, bricks));
      EXPECT_TRUE(bricks.empty());
    }
}

TEST(OccupancyMap, SameMapWithAnyThreadCount)
{
  plantnbv::Rng rng(5);
  const Eigen::Vector3d origin(0.1, 0.2, 0.3);
  OccupancyMap::Config config;
  config.resolution_m = 0.01;
  const CloudXYZ a = randomFrame(rng, origin, 0.01, 0.75, 6000);
  const CloudXYZ b =
      randomFrame(rng, origin + Eigen::Vector3d(0.05, 0.0, 0.0), 0.01, 0.75, 6000);
  OccupancyMap one(config), two(config), three(config);
  one.setNumberOfThreads(1);
  two.setNumberOfThreads(2);
  three.setNumberOfThreads(3);
  EXPECT_EQ(two.getNumberOfThreads(), 2);
  for (OccupancyMap* map : {&one, &two, &three}) {
    map->insert(a, origin);
    map->insert(b, origin + Eigen::Vector3d(0.05, 0.0, 0.0));
  }
  expectSameTree(one.getOcTree(), two.getOcTree());
  expectSameTree(one.getOcTree(), three.getOcTree());
  EXPECT_THROW(one.setNumberOfThreads(-1), plantnbv::InvalidArgumentError);
}

TEST(OccupancyMap, ASnapshotRestoresTheSameMapThatTheSameFramesKeepTheSame)
{
  // A restored snapshot has the map's tree node for node, its parameters, threads and
  // region; the same frames then make the same map in both, and a frame into the
  // restored map leaves the original as it was. An empty map restores empty.
  plantnbv::Rng rng(8);
  OccupancyMap::Config config;
  config.resolution_m = 0.01;
  config.prob_hit = 0.8;
  const Eigen::Vector3d origin(0.1, 0.2, 0.3);
  const plantnbv::Box bounds(origin, Eigen::Vector3d::Constant(1.0));
  auto region = std::make_shared<plantnbv::UpdateRegion>(config.resolution_m, bounds);
  region->addBox(plantnbv::Box(origin, Eigen::Vector3d::Constant(0.3)));
  OccupancyMap map(config);
  map.setNumberOfThreads(2);
  map.setUpdateRegion(region);
  const OccupancyMapSnapshot empty(map);
  EXPECT_EQ(empty.nodeBytes(), 0u);
  EXPECT_EQ(empty.restore()->getOcTree().size(), 0u);

  map.insert(randomFrame(rng, origin, 0.01, 0.75, 6000), origin);
  const OccupancyMapSnapshot snapshot(map);
  EXPECT_EQ(snapshot.nodeBytes(), 5 * map.getOcTree().size());
  const std::unique_ptr<OccupancyMap> copy = snapshot.restore();
  expectSameTree(map.getOcTree(), copy->getOcTree());
  EXPECT_EQ(copy->getConfig().prob_hit, 0.8);
  EXPECT_EQ(copy->getNumberOfThreads(), 2);
  EXPECT_EQ(copy->getUpdateRegion(), region);

  const Eigen::Vector3d next = origin + Eigen::Vector3d(0.05, -0.02, 0.0);
  const CloudXYZ frame = randomFrame(rng, next, 0.01, 0.75, 6000);
  const OccupancyMap::VoxelCounts before = map.countVoxels();
  copy->insert(frame, next);
  EXPECT_EQ(map.countVoxels().free, before.free); // the original is its own
  EXPECT_EQ(map.countVoxels().occupied, before.occupied);
  map.insert(frame, next);
  expectSameTree(map.getOcTree(), copy->getOcTree());
  EXPECT_GT(map.countVoxels().known(), before.known());
  expectSameTree(map.getOcTree(), OccupancyMapSnapshot(map).restore()->getOcTree());
}

TEST(OccupancyMap, EqualsOctoMapBelowLargePrunedNodes)
{
  // Pruned nodes above the bitset's 64^3-voxel blocks (depths 1 to 9: cubes of 128
  // voxels and more), free at the lower clamping bound, occupied at the upper one, with
  // unknown space beside them. The paths to the blocks are opened before the blocks are
  // walked (on several threads), which expands such nodes whatever the updates below
  // them; the tree must still be OctoMap's, node for node.
  OccupancyMap::Config config;
  config.resolution_m = 0.01;
  config.max_range_m = 0.6;
  const Eigen::Vector3d target(0.3, -0.2, 0.4); // near the root's split at x = 0
  auto start = makeReference(config);
  octomap::OcTreeKey key;
  ASSERT_TRUE(start->coordToKeyChecked(octomap::point3d(static_cast<float>(target.x()),
                                                        static_cast<float>(target.y()),
                                                        static_cast<float>(target.z())),
                                       key));
  std::istringstream data(prunedPathTree(key, 9));
  start->readBinaryData(data);
  std::size_t free_leaves = 0, occupied_leaves = 0;
  for (auto it = start->begin_leafs(); it != start->end_leafs(); ++it) {
    ASSERT_LE(it.getDepth(), 9u);
    (start->isNodeOccupied(*it) ? occupied_leaves : free_leaves) += 1;
  }
  ASSERT_GT(free_leaves, 10u);
  ASSERT_GT(occupied_leaves, 10u);
  const std::string path = tempPath("pruned.ot");
  start->write(path);
  for (const int threads : {1, 2}) {
    auto map = OccupancyMap::read(path, config);
    map->setNumberOfThreads(threads);
    octomap::OcTree reference(map->getOcTree());
    for (int frame = 0; frame < 6; ++frame) {
      const double yaw = 0.9 * frame;
      const Eigen::Vector3d origin =
          target +
          Eigen::Vector3d(0.45 * std::cos(yaw), 0.45 * std::sin(yaw), 0.1 * (frame % 2));
      const CloudXYZ cloud = cameraFrame(origin, target, 160, 120, 150.0);
      map->insert(cloud, origin);
      referenceInsert(reference, cloud, origin, config.max_range_m);
      SCOPED_TRACE(std::to_string(threads) + " threads, frame " + std::to_string(frame));
      expectSameTree(map->getOcTree(), reference);
    }
  }
  std::filesystem::remove(path);
}

TEST(OccupancyMap, LabelledCloudGivesTheSameMap)
{
  plantnbv::Rng rng(6);
  const CloudXYZ xyz = randomFrame(rng, Eigen::Vector3d::Zero(), 0.003, 0.75, 2000);
  plantnbv::CloudXYZL xyzl;
  for (const auto& p : xyz) {
    pcl::PointXYZL q;
    q.x = p.x;
    q.y = p.y;
    q.z = p.z;
    q.label = 3;
    xyzl.push_back(q);
  }
  OccupancyMap a, b;
  a.insert(xyz, Eigen::Vector3d::Zero());
  b.insert(xyzl, Eigen::Vector3d::Zero());
  expectSameTree(a.getOcTree(), b.getOcTree());
}

TEST(OccupancyMap, SavedBtReloadsWithTheSameOccupiedCount)
{
  plantnbv::Rng rng(7);
  OccupancyMap map;
  for (int f = 0; f < 3; ++f) {
    const Eigen::Vector3d origin(0.02 * f, 0.0, 0.0);
    map.insert(randomFrame(rng, origin, 0.003, 0.75, 1500), origin);
  }
  const auto counts = map.countVoxels();
  ASSERT_GT(counts.occupied, 1000u);
  EXPECT_EQ(occupiedCount(map.getOcTree()), counts.occupied);

  const std::string bt = tempPath("map.bt");
  map.write(bt);
  const auto back = plantnbv::readOcTree(bt);
  EXPECT_DOUBLE_EQ(back->getResolution(), 0.003);
  EXPECT_EQ(occupiedCount(*back), counts.occupied);
  std::filesystem::remove(bt);

  // .ot keeps the log-odds: the same tree.
  const std::string ot = tempPath("map.ot");
  map.write(ot);
  const auto full = plantnbv::readOcTree(ot);
  expectSameTree(*full, map.getOcTree());
  std::filesystem::remove(ot);
  EXPECT_THROW(map.write(tempPath("map.pcd")), plantnbv::FormatError);
}

TEST(OccupancyMap, QueriesOnUnknownAndOutsideVoxels)
{
  OccupancyMap map;
  octomap::OcTreeKey key;
  ASSERT_TRUE(map.computeKey(Eigen::Vector3d(0.1, 0.2, 0.3), key));
  EXPECT_EQ(key[0], 32768 + 33); // floor(0.1 / 0.003)
  EXPECT_EQ(map.state(key), VoxelState::unknown);
  EXPECT_FALSE(map.isKnown(key));
  EXPECT_EQ(map.logOdds(key), 0.0f);
  EXPECT_EQ(map.probability(key), 0.5);
  // Outside the octree (+-98.3 m at 3 mm) or not finite: no key, unknown.
  EXPECT_FALSE(map.computeKey(Eigen::Vector3d(100.0, 0.0, 0.0), key));
  EXPECT_FALSE(map.computeKey(Eigen::Vector3d(0.0, std::nan(""), 0.0), key));
  EXPECT_EQ(map.state(Eigen::Vector3d(0.0, -1e9, 0.0)), VoxelState::unknown);
  EXPECT_EQ(map.probability(Eigen::Vector3d(1e30, 0.0, 0.0)), 0.5);
  EXPECT_EQ(map.countVoxels().known(), 0u);

  CloudXYZ frame;
  frame.push_back(point(0.2, 0.0, 0.0));
  map.insert(frame, Eigen::Vector3d::Zero());
  EXPECT_GT(map.countVoxels().known(), 60u);
  map.clear();
  EXPECT_EQ(map.countVoxels().known(), 0u);
  EXPECT_EQ(map.getOcTree().size(), 0u);
  map.insert(frame, Eigen::Vector3d::Zero()); // usable after clear
  EXPECT_EQ(map.countVoxels().occupied, 1u);
}

TEST(OccupancyMap, CountsExpandPrunedNodes)
{
  // Free space near the sensor is pruned into larger nodes; the counts are in voxels.
  plantnbv::Rng rng(8);
  OccupancyMap map;
  map.insert(randomFrame(rng, Eigen::Vector3d::Zero(), 0.003, 0.75, 5000),
             Eigen::Vector3d::Zero());
  const octomap::OcTree& tree = map.getOcTree();
  std::size_t occupied = 0, free = 0, pruned = 0;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    const std::size_t voxels = std::size_t{1} << (3 * (16 - it.getDepth()));
    pruned += it.getDepth() < 16;
    (tree.isNodeOccupied(*it) ? occupied : free) += voxels;
  }
  EXPECT_GT(pruned, 0u);
  EXPECT_EQ(map.countVoxels().occupied, occupied);
  EXPECT_EQ(map.countVoxels().free, free);
  EXPECT_GT(free, tree.getNumLeafNodes());
}

TEST(OccupancyMap, RejectsBadOrigins)
{
  OccupancyMap map;
  CloudXYZ frame;
  frame.push_back(point(0.2, 0.0, 0.0));
  EXPECT_THROW(map.insert(frame, Eigen::Vector3d(std::nan(""), 0.0, 0.0)),
               plantnbv::InvalidArgumentError);
  EXPECT_THROW(map.insert(frame, Eigen::Vector3d(0.0, 200.0, 0.0)),
               plantnbv::InvalidArgumentError);
  EXPECT_EQ(map.getOcTree().size(), 0u);
}

TEST(OccupancyMap, ConfigValidationNamesTheField)
{
  const auto expectBad = [](const char* field, auto set) {
    OccupancyMap::Config c;
    set(c);
    try {
      OccupancyMap map(c);
      ADD_FAILURE() << field << " accepted";
    } catch (const plantnbv::InvalidArgumentError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  const double nan = std::nan("");
  for (double v : {0.0, -0.003, nan, std::numeric_limits<double>::infinity(), 1e-300,
                   0.99e-4, 10.01, 1e300})
    expectBad("resolution_m", [v](OccupancyMap::Config& c) { c.resolution_m = v; });
  for (double v : {0.5, 1.0, 0.3, nan})
    expectBad("prob_hit", [v](OccupancyMap::Config& c) { c.prob_hit = v; });
  for (double v : {0.0, 0.5, 0.7, nan})
    expectBad("prob_miss", [v](OccupancyMap::Config& c) { c.prob_miss = v; });
  for (double v : {0.0, 0.5, 0.6, nan})
    expectBad("clamp_min", [v](OccupancyMap::Config& c) { c.clamp_min = v; });
  for (double v : {0.5, 1.0, 0.2, nan})
    expectBad("clamp_max", [v](OccupancyMap::Config& c) { c.clamp_max = v; });
  for (double v : {0.0, 1.0, -0.5, nan})
    expectBad("occupancy_threshold",
              [v](OccupancyMap::Config& c) { c.occupancy_threshold = v; });
  for (double v : {0.0, -1.0, nan, 25.0})
    expectBad("max_range_m", [v](OccupancyMap::Config& c) { c.max_range_m = v; });
  OccupancyMap::Config ok;
  ok.max_range_m = 20.0; // 6667 voxels at 3 mm
  EXPECT_NO_THROW(ok.validate());
}
