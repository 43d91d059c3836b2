#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <set>
#include <sstream>
#include <sys/stat.h>
#include <tuple>
#include <unistd.h>

#include <gtest/gtest.h>
#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/filters/voxel_grid_filter.h>
#include <plantnbv/octree/octree_conversion.h>

using plantnbv::CloudXYZ;
using plantnbv::OccupiedVoxelOptions;

namespace {

using Voxel = std::array<long, 3>;
using PointSet = std::set<std::array<float, 3>>;

PointSet toSet(const CloudXYZ& cloud)
{
  PointSet s;
  for (const auto& p : cloud)
    s.insert({p.x, p.y, p.z});
  return s;
}

/// The centre of voxel v as OctoMap and VoxelGridFilter compute it.
std::array<float, 3> centre(const Voxel& v, double res)
{
  return {static_cast<float>((v[0] + 0.5) * res), static_cast<float>((v[1] + 0.5) * res),
          static_cast<float>((v[2] + 0.5) * res)};
}

/// `per_voxel` points in each voxel, at least 10% of a voxel from its faces.
CloudXYZ::Ptr pointsIn(const std::set<Voxel>& voxels, double res, plantnbv::Rng& rng,
                       int per_voxel = 3)
{
  auto cloud = std::make_shared<CloudXYZ>();
  for (const Voxel& v : voxels)
    for (int k = 0; k < per_voxel; ++k)
      cloud->push_back(
          pcl::PointXYZ(static_cast<float>((v[0] + rng.uniform(0.1, 0.9)) * res),
                        static_cast<float>((v[1] + rng.uniform(0.1, 0.9)) * res),
                        static_cast<float>((v[2] + rng.uniform(0.1, 0.9)) * res)));
  return cloud;
}

std::set<Voxel> randomVoxels(plantnbv::Rng& rng, int n, long range)
{
  std::set<Voxel> voxels;
  while (static_cast<int>(voxels.size()) < n)
    voxels.insert({static_cast<long>(rng.index(2 * range)) - range,
                   static_cast<long>(rng.index(2 * range)) - range,
                   static_cast<long>(rng.index(2 * range)) - range});
  return voxels;
}

/// All voxels of the cube [lo, lo + 8)^3.
std::set<Voxel> block8(long lx, long ly, long lz)
{
  std::set<Voxel> voxels;
  for (long i = 0; i < 8; ++i)
    for (long j = 0; j < 8; ++j)
      for (long k = 0; k < 8; ++k)
        voxels.insert({lx + i, ly + j, lz + k});
  return voxels;
}

PointSet centres(const std::set<Voxel>& voxels, double res)
{
  PointSet s;
  for (const Voxel& v : voxels)
    s.insert(centre(v, res));
  return s;
}

CloudXYZ occupied(const octomap::OcTree& tree, const OccupiedVoxelOptions& options = {})
{
  CloudXYZ cloud;
  plantnbv::occupiedVoxelCentres(tree, cloud, options);
  return cloud;
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

} // namespace

TEST(OctreeConversion, RoundTripKeepsTheVoxelSet)
{
  plantnbv::Rng rng(3);
  const double res = 0.01;
  const auto voxels = randomVoxels(rng, 500, 30);
  const auto cloud = pointsIn(voxels, res, rng);
  const auto tree = plantnbv::cloudToOcTree(*cloud, res);
  EXPECT_DOUBLE_EQ(tree->getResolution(), res);
  const CloudXYZ out = occupied(*tree);
  EXPECT_EQ(out.size(), voxels.size());
  EXPECT_EQ(out.width, out.size());
  EXPECT_EQ(out.height, 1u);
  EXPECT_EQ(toSet(out), centres(voxels, res));
}

TEST(OctreeConversion, OccupiedCentresAreTheSameOnAnyNumberOfThreads)
{
  // Scattered voxels (many subtrees for the threads) and a full 64^3 block at keys
  // 32768-32831, which the tree prunes into one leaf above the threads' subtrees.
  plantnbv::Rng rng(5);
  const double res = 0.01;
  std::set<Voxel> voxels = randomVoxels(rng, 3000, 300);
  for (long x = 0; x < 64; ++x)
    for (long y = 0; y < 64; ++y)
      for (long z = 0; z < 64; ++z)
        voxels.insert({x, y, z});
  const auto tree = plantnbv::cloudToOcTree(*pointsIn(voxels, res, rng), res);
  for (const bool hold_max : {false, true}) {
    OccupiedVoxelOptions options;
    options.inner_nodes_hold_max = hold_max; // cloudToOcTree's inner nodes do
    const CloudXYZ one = occupied(*tree, options);
    ASSERT_EQ(one.size(), voxels.size());
    for (const int threads : {2, 3, 0}) {
      options.threads = threads;
      const CloudXYZ many = occupied(*tree, options);
      ASSERT_EQ(many.size(), one.size()) << threads;
      EXPECT_EQ(many.width, one.size());
      std::size_t differ = 0;
      for (std::size_t i = 0; i < one.size(); ++i)
        differ +=
            !(many[i].x == one[i].x && many[i].y == one[i].y && many[i].z == one[i].z);
      EXPECT_EQ(differ, 0u) << threads << " threads";
    }
  }
  OccupiedVoxelOptions negative;
  negative.threads = -1;
  CloudXYZ cloud;
  EXPECT_THROW(plantnbv::occupiedVoxelCentres(*tree, cloud, negative),
               plantnbv::InvalidArgumentError);
}

TEST(OctreeConversion, SameLatticeAsVoxelGridFilterCentres)
{
  // Uniform points, faces included (multiples of the resolution): VoxelGridFilter's
  // centre mode and OctoMap's keys compute the voxel index the same way, bit for bit.
  plantnbv::Rng rng(8);
  const double res = 0.003;
  auto cloud = std::make_shared<CloudXYZ>();
  for (int n = 0; n < 20000; ++n) {
    if (n % 4 == 0)
      cloud->push_back(pcl::PointXYZ(static_cast<float>((rng.index(200) - 100.0) * res),
                                     static_cast<float>((rng.index(200) - 100.0) * res),
                                     static_cast<float>((rng.index(200) - 100.0) * res)));
    else
      cloud->push_back(pcl::PointXYZ(static_cast<float>(rng.uniform(-0.3, 0.3)),
                                     static_cast<float>(rng.uniform(-0.3, 0.3)),
                                     static_cast<float>(rng.uniform(-0.3, 0.3))));
  }
  plantnbv::VoxelGridFilter<pcl::PointXYZ> grid;
  grid.setLeafSize(res);
  grid.setOutputVoxelCentres(true);
  grid.setInputCloud(cloud);
  CloudXYZ voxelized;
  grid.filter(voxelized);

  const CloudXYZ out = occupied(*plantnbv::cloudToOcTree(*cloud, res));
  EXPECT_GT(out.size(), 15000u);
  EXPECT_EQ(out.size(), voxelized.size());
  EXPECT_EQ(toSet(out), toSet(voxelized));
}

TEST(OctreeConversion, PrunedNodesAreExpanded)
{
  // Two full 8x8x8 blocks aligned with the octree (keys 32776.. and 32752..): OctoMap
  // prunes each into one node two levels above the voxels.
  const double res = 0.005;
  auto voxels = block8(8, 8, 8);
  const auto negative = block8(-16, -16, 8);
  voxels.insert(negative.begin(), negative.end());
  plantnbv::Rng rng(4);
  const auto tree = plantnbv::cloudToOcTree(*pointsIn(voxels, res, rng, 1), res);
  ASSERT_EQ(tree->getNumLeafNodes(), 2u); // pruned: the expansion is exercised
  for (auto it = tree->begin_leafs(); it != tree->end_leafs(); ++it)
    EXPECT_EQ(it.getDepth(), tree->getTreeDepth() - 3);

  const CloudXYZ out = occupied(*tree);
  EXPECT_EQ(out.size(), 1024u);
  EXPECT_EQ(toSet(out), centres(voxels, res));
  // Each expanded node in increasing (x, y, z) order, z fastest.
  for (std::size_t n = 1; n < out.size(); ++n)
    if (n != 512) {
      const auto& a = out[n - 1];
      const auto& b = out[n];
      EXPECT_LT(std::tie(a.x, a.y, a.z), std::tie(b.x, b.y, b.z)) << n;
    }
}

TEST(OctreeConversion, OneHitPerVoxelAndThreshold)
{
  const double res = 0.01;
  auto cloud = std::make_shared<CloudXYZ>();
  for (int k = 0; k < 5; ++k) // five points in voxel (0, 0, 0)
    cloud->push_back(pcl::PointXYZ(0.001f * (k + 1), 0.005f, 0.005f));
  cloud->push_back(pcl::PointXYZ(0.015f, 0.005f, 0.005f)); // one in voxel (1, 0, 0)
  cloud->push_back(pcl::PointXYZ(0.035f, 0.005f, 0.005f)); // one in voxel (3, 0, 0)
  auto tree = plantnbv::cloudToOcTree(*cloud, res);
  const auto* a = tree->search(0.005, 0.005, 0.005);
  const auto* b = tree->search(0.015, 0.005, 0.005);
  ASSERT_TRUE(a && b);
  EXPECT_FLOAT_EQ(a->getLogOdds(), b->getLogOdds()); // five points, still one hit
  EXPECT_NEAR(a->getOccupancy(), 0.7, 1e-6);

  // A second hit on voxel (3, 0, 0): occupancy 0.7^2 / (0.7^2 + 0.3^2) = 0.845.
  tree->updateNode(octomap::point3d(0.035f, 0.005f, 0.005f), true);
  OccupiedVoxelOptions options;
  EXPECT_EQ(occupied(*tree, options).size(), 3u); // tree threshold 0.5
  options.threshold = 0.69;
  EXPECT_EQ(occupied(*tree, options).size(), 3u);
  options.threshold = 0.7 + 1e-6; // strict >: the single hits drop out
  const CloudXYZ strong = occupied(*tree, options);
  ASSERT_EQ(strong.size(), 1u);
  EXPECT_FLOAT_EQ(strong[0].x, 0.035f);
  options.threshold = 0.9;
  EXPECT_EQ(occupied(*tree, options).size(), 0u);
  // A negative threshold uses the tree's own.
  tree->setOccupancyThres(0.8);
  options.threshold = -1.0;
  EXPECT_EQ(occupied(*tree, options).size(), 1u);

  options.threshold = std::nan("");
  EXPECT_THROW(occupied(*tree, options), plantnbv::InvalidArgumentError);
  options.threshold = 1.5;
  EXPECT_THROW(occupied(*tree, options), plantnbv::InvalidArgumentError);
}

TEST(OctreeConversion, RoiOption)
{
  // A pruned 8x8x8 block and a lone voxel; the ROI cuts 3 of the block's 8 x-layers.
  const double res = 0.005;
  auto voxels = block8(8, 8, 8);
  voxels.insert({-20, 0, 0});
  plantnbv::Rng rng(6);
  const auto tree = plantnbv::cloudToOcTree(*pointsIn(voxels, res, rng, 1), res);
  ASSERT_EQ(tree->getNumLeafNodes(), 2u);

  OccupiedVoxelOptions options;
  options.roi.addBox(plantnbv::Box::fromMinMax(Eigen::Vector3d(10 * res, -1, -1),
                                               Eigen::Vector3d(13 * res, 1, 1)));
  std::set<Voxel> expected;
  for (const Voxel& v : voxels)
    if (v[0] >= 10 && v[0] <= 12)
      expected.insert(v);
  ASSERT_EQ(expected.size(), 192u);
  const CloudXYZ out = occupied(*tree, options);
  EXPECT_EQ(toSet(out), centres(expected, res));

  // Two boxes: the lone voxel too.
  options.roi.addBox(plantnbv::Box(Eigen::Vector3d(-19.5 * res, 0.5 * res, 0.5 * res),
                                   Eigen::Vector3d(res, res, res) * 0.5));
  EXPECT_EQ(occupied(*tree, options).size(), 193u);
}

TEST(OctreeConversion, WriteAndReadBtAndOt)
{
  plantnbv::Rng rng(9);
  const double res = 0.004;
  auto voxels = randomVoxels(rng, 300, 25);
  const auto block = block8(24, 0, -8);
  voxels.insert(block.begin(), block.end());
  const auto tree = plantnbv::cloudToOcTree(*pointsIn(voxels, res, rng), res);
  const PointSet expected = centres(voxels, res);
  ASSERT_EQ(toSet(occupied(*tree)), expected);

  for (const std::string ext : {".bt", ".ot", ".BT"}) {
    const std::string path = tempPath("map" + ext);
    plantnbv::writeOcTree(path, *tree);
    const auto back = plantnbv::readOcTree(path);
    ASSERT_TRUE(back) << ext;
    EXPECT_DOUBLE_EQ(back->getResolution(), res) << ext;
    const CloudXYZ out = occupied(*back);
    EXPECT_EQ(out.size(), expected.size()) << ext;
    EXPECT_EQ(toSet(out), expected) << ext;
    // Byte for byte what OctoMap's own writers produce.
    std::ostringstream octomap_bytes;
    if (ext == ".ot")
      tree->write(octomap_bytes);
    else
      tree->writeBinaryConst(octomap_bytes);
    std::ifstream in(path, std::ios::binary);
    std::ostringstream our_bytes;
    our_bytes << in.rdbuf();
    EXPECT_EQ(our_bytes.str(), octomap_bytes.str()) << ext;
    std::filesystem::remove(path);
  }
  // Free leaves, unknown children and pruned inner nodes too (a ray's free voxels end
  // in an occupied one); the tree is not pruned, so its codes are mixed.
  octomap::OcTree mixed(res);
  mixed.insertRay(octomap::point3d(0.0f, 0.0f, 0.0f),
                  octomap::point3d(0.4f, 0.15f, 0.05f));
  mixed.updateNode(octomap::point3d(-0.1f, 0.02f, 0.0f), false);
  ASSERT_GT(mixed.size(), 20u);
  const std::string mixed_path = tempPath("mixed.bt");
  plantnbv::writeOcTree(mixed_path, mixed);
  std::ostringstream octomap_bytes, our_bytes;
  mixed.writeBinaryConst(octomap_bytes);
  our_bytes << std::ifstream(mixed_path, std::ios::binary).rdbuf();
  EXPECT_EQ(our_bytes.str(), octomap_bytes.str());
  std::filesystem::remove(mixed_path);

  // The caller's tree is not turned into maximum likelihood by writing .bt.
  const auto* node =
      tree->search(centre(*voxels.begin(), res)[0], centre(*voxels.begin(), res)[1],
                   centre(*voxels.begin(), res)[2]);
  ASSERT_TRUE(node);
  EXPECT_NEAR(node->getOccupancy(), 0.7, 1e-6);
}

TEST(OctreeConversion, ReadErrors)
{
  // Missing file and a directory: IoError naming the path.
  const std::string missing = tempPath("missing.bt");
  try {
    plantnbv::readOcTree(missing);
    ADD_FAILURE();
  } catch (const plantnbv::IoError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos);
  }
  EXPECT_THROW(plantnbv::readOcTree(std::filesystem::temp_directory_path().string()),
               plantnbv::IoError);
  // A FIFO is refused by name, without blocking on it.
  const std::string fifo = tempPath("fifo.bt");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  try {
    plantnbv::readOcTree(fifo);
    ADD_FAILURE();
  } catch (const plantnbv::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("is not a regular file"), std::string::npos);
  }
  std::filesystem::remove(fifo);

  // Not an octree (whatever the extension): FormatError.
  for (const std::string name : {"text.bt", "text.ot", "empty.ot"}) {
    const std::string path = tempPath(name);
    {
      std::ofstream f(path);
      if (name != "empty.ot")
        f << "ply\nformat ascii 1.0\nend_header\n";
    }
    EXPECT_THROW(plantnbv::readOcTree(path), plantnbv::FormatError) << name;
    std::filesystem::remove(path);
  }

  // An OctoMap file of another tree type: FormatError naming it.
  const std::string color_path = tempPath("color.ot");
  octomap::ColorOcTree color(0.01);
  color.updateNode(octomap::point3d(0.1f, 0.1f, 0.1f), true);
  ASSERT_TRUE(color.write(color_path));
  try {
    plantnbv::readOcTree(color_path);
    ADD_FAILURE();
  } catch (const plantnbv::FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("ColorOcTree"), std::string::npos) << e.what();
  }
  std::filesystem::remove(color_path);
}

namespace {

/// An OctoMap file written by hand: the header's first line by extension, then `rest`
/// and "data", then the node data.
std::string writeOctreeFile(const std::string& name, const std::string& rest,
                            const std::string& data)
{
  const std::string path = tempPath(name);
  std::ofstream(path, std::ios::binary)
      << (std::filesystem::path(name).extension() == ".bt"
              ? "# Octomap OcTree binary file\n"
              : "# Octomap OcTree file\n")
      << "id OcTree\n"
      << rest << "data\n"
      << data;
  return path;
}

std::string formatErrorOf(const std::string& path)
{
  std::string what = "no error";
  try {
    plantnbv::readOcTree(path);
  } catch (const plantnbv::FormatError& e) {
    what = e.what();
  }
  std::filesystem::remove(path);
  return what;
}

} // namespace

TEST(OctreeConversion, NodeDataDeeperThanTheTreeOrUnlikeTheHeaderIsRefused)
{
  // OctoMap's readers recurse as deep as the node data says: a chain of inner nodes a
  // few megabytes long overflowed the stack. Each file is refused before OctoMap reads.
  // .bt: each inner node's first child is inner (bits 11), its last an occupied leaf.
  auto btChain = [](std::size_t levels) {
    std::string data;
    for (std::size_t i = 0; i < levels; ++i)
      data += std::string("\x03\x40", 2);
    return data + std::string("\x00\x40", 2); // the last inner node: one leaf only
  };
  // 16 inner nodes (the root at depth 0), a leaf on each, the deepest at depth 16: a
  // valid tree of 32 nodes.
  const auto valid = plantnbv::readOcTree(
      writeOctreeFile("chain15.bt", "size 32\nres 0.01\n", btChain(15)));
  ASSERT_TRUE(valid);
  EXPECT_EQ(valid->size(), 32u);
  EXPECT_NE(formatErrorOf(writeOctreeFile("chain16.bt", "res 0.01\n", btChain(16)))
                .find("deeper than OctoMap's 16"),
            std::string::npos);
  EXPECT_NE(formatErrorOf(writeOctreeFile("chain1M.bt", "res 0.01\n", btChain(1000000)))
                .find("deeper than"),
            std::string::npos);
  EXPECT_NE(formatErrorOf(writeOctreeFile("size.bt", "size 33\nres 0.01\n", btChain(15)))
                .find("holds 32 nodes, its header says size 33"),
            std::string::npos);
  EXPECT_NE(
      formatErrorOf(writeOctreeFile("cut.bt", "res 0.01\n", btChain(15).substr(0, 29)))
          .find("truncated"),
      std::string::npos);
  // .ot: log-odds then child bits; a chain of first children.
  std::string ot;
  for (std::size_t i = 0; i < 17; ++i)
    ot += std::string("\0\0\0\0\x01", 5);
  ot += std::string("\0\0\0\0\0", 5);
  EXPECT_NE(formatErrorOf(writeOctreeFile("chain.ot", "res 0.01\n", ot))
                .find("deeper than OctoMap's 16"),
            std::string::npos);
}

TEST(OctreeConversion, WriteErrors)
{
  octomap::OcTree tree(0.01);
  tree.updateNode(octomap::point3d(0.0f, 0.0f, 0.0f), true);
  const std::string path = tempPath("map.pcd");
  EXPECT_THROW(plantnbv::writeOcTree(path, tree), plantnbv::FormatError);
  EXPECT_FALSE(std::filesystem::exists(path)); // checked before creating the file
  EXPECT_THROW(plantnbv::writeOcTree(tempPath("no_extension"), tree),
               plantnbv::FormatError);
  EXPECT_THROW(plantnbv::writeOcTree(tempPath("no_such_dir") + "/map.bt", tree),
               plantnbv::IoError);
}

TEST(OctreeConversion, CloudToOcTreeSkipsNonFinitePoints)
{
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  CloudXYZ cloud;
  cloud.push_back(pcl::PointXYZ(0.005f, 0.005f, 0.005f));
  cloud.push_back(pcl::PointXYZ(nan, 0.0f, 0.0f));
  cloud.push_back(pcl::PointXYZ(0.0f, inf, 0.0f));
  cloud.push_back(pcl::PointXYZ(nan, nan, nan));
  cloud.push_back(pcl::PointXYZ(-0.005f, 0.005f, 0.005f));
  cloud.is_dense = false;
  const auto tree = plantnbv::cloudToOcTree(cloud, 0.01);
  EXPECT_EQ(toSet(occupied(*tree)), centres({{0, 0, 0}, {-1, 0, 0}}, 0.01));
  // Nothing else is known.
  EXPECT_EQ(tree->getNumLeafNodes(), 2u);
  EXPECT_EQ(plantnbv::cloudToOcTree(CloudXYZ(), 0.01)->size(), 0u);
}

TEST(OctreeConversion, CloudToOcTreeRejectsBadInput)
{
  CloudXYZ cloud;
  cloud.push_back(pcl::PointXYZ(0.0f, 0.0f, 0.0f));
  for (const double bad :
       {0.0, -0.01, std::nan(""), std::numeric_limits<double>::infinity()})
    EXPECT_THROW(plantnbv::cloudToOcTree(cloud, bad), plantnbv::InvalidArgumentError)
        << bad;
  try {
    plantnbv::cloudToOcTree(cloud, -0.25);
    ADD_FAILURE();
  } catch (const plantnbv::InvalidArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("-0.25"), std::string::npos) << e.what();
  }
  // Beyond OctoMap's +-32768 voxels: 1 km at 1 cm.
  cloud.push_back(pcl::PointXYZ(1000.0f, 0.0f, 0.0f));
  EXPECT_THROW(plantnbv::cloudToOcTree(cloud, 0.01), plantnbv::InvalidArgumentError);
  EXPECT_NO_THROW(plantnbv::cloudToOcTree(cloud, 0.1));
}

TEST(OctreeConversion, ResolutionOutsideTheSaneRangeIsRefusedNamingFileAndValue)
{
  const std::string leaf("\x02\x00", 2); // the root with one occupied leaf
  for (const std::string res : {"0", "-0.003", "nan", "-inf", "inf", "1e-300", "9e-5",
                                "10.5", "1e300", "0.01x", "abc"}) {
    for (const std::string ext : {".bt", ".ot"}) {
      const std::string data = ext == ".bt" ? leaf : std::string("\0\0\0\0\0", 5);
      const std::string path = writeOctreeFile("r" + ext, "res " + res + "\n", data);
      const std::string what = formatErrorOf(path);
      EXPECT_NE(what.find(path), std::string::npos) << res << ext << ": " << what;
      EXPECT_NE(what.find("resolution"), std::string::npos) << res << ext << ": " << what;
    }
  }
  for (const double res :
       {plantnbv::kMinMapResolutionM, 0.003, 1.0, plantnbv::kMaxMapResolutionM}) {
    std::ostringstream rest;
    rest << std::setprecision(17) << "res " << res << "\n";
    const std::string path = writeOctreeFile("ok.bt", rest.str(), leaf);
    EXPECT_EQ(plantnbv::readOcTree(path)->getResolution(), res);
    std::filesystem::remove(path);
  }
}

TEST(OctreeConversion, NonFiniteLogOddsInOtAreRefused)
{
  for (const float v :
       {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
        -std::numeric_limits<float>::infinity()}) {
    // The root with one child (bit 0), the child a leaf holding v.
    char bytes[4];
    std::memcpy(bytes, &v, 4);
    const std::string data =
        std::string("\0\0\0\0\x01", 5) + std::string(bytes, 4) + std::string(1, '\0');
    const std::string what = formatErrorOf(writeOctreeFile("v.ot", "res 0.01\n", data));
    EXPECT_NE(what.find("node (number 1 from 0) with log-odds"), std::string::npos)
        << what;
  }
}

TEST(OctreeConversion, PrunedLeavesAreCountedAndRefusedOverTheCapBeforeExpanding)
{
  // A chain of inner nodes from the root to depth d - 1, the last with k occupied leaf
  // children at depth d: k 8^(16 - d) voxels from 2 d bytes of node data.
  const double cap_points = 4096.0;
  for (int d = 1; d <= 16; ++d)
    for (const int k : {1, 3, 8}) {
      std::string data;
      for (int i = 1; i < d; ++i)
        data += std::string("\x03\x00", 2); // child 0 inner
      unsigned char last[2] = {0, 0};
      for (int c = 0; c < k; ++c)
        last[c / 4] = static_cast<unsigned char>(last[c / 4] | 2u << (2 * (c % 4)));
      data += std::string(reinterpret_cast<const char*>(last), 2);
      const std::string path = writeOctreeFile("p.bt", "res 0.003\n", data);
      const auto tree = plantnbv::readOcTree(path);
      std::filesystem::remove(path);
      const double expected = k * std::pow(8.0, 16 - d);
      EXPECT_EQ(plantnbv::occupiedVoxelCount(*tree), expected) << d << " " << k;
      OccupiedVoxelOptions options;
      options.memory_cap_bytes = cap_points * sizeof(pcl::PointXYZ);
      CloudXYZ cloud;
      if (expected > cap_points) {
        try {
          plantnbv::occupiedVoxelCentres(*tree, cloud, options);
          ADD_FAILURE() << d << " " << k << " expanded";
        } catch (const plantnbv::InvalidArgumentError& e) {
          EXPECT_NE(std::string(e.what()).find("over the memory cap"), std::string::npos)
              << e.what();
        }
        EXPECT_TRUE(cloud.empty());
        // An ROI holding the centres of keys 0 and 1 per axis (the chain of first
        // children ends at the tree's lowest corner) cuts the count to the ROI's key
        // range (conservative by one key), and the expansion to its 8 voxels.
        const double c = (0.5 - 32768) * 0.003 + 0.0015;
        options.roi.addBox(plantnbv::Box(Eigen::Vector3d(c, c, c),
                                         Eigen::Vector3d(0.004, 0.004, 0.004)));
        const double in_roi = plantnbv::occupiedVoxelCount(*tree, options);
        EXPECT_GE(in_roi, 8.0);
        EXPECT_LE(in_roi, 3.0 * 3 * 3);
        plantnbv::occupiedVoxelCentres(*tree, cloud, options);
        EXPECT_EQ(cloud.size(), 8u) << d << " " << k;
      } else {
        plantnbv::occupiedVoxelCentres(*tree, cloud, options);
        EXPECT_EQ(static_cast<double>(cloud.size()), expected) << d << " " << k;
      }
    }
  // The same one-node tree as a .ot: the root itself a leaf, 8^16 voxels; the default
  // cap (8 GiB) refuses it.
  float one = 1.0f;
  char bytes[4];
  std::memcpy(bytes, &one, 4);
  const std::string path =
      writeOctreeFile("root.ot", "res 0.003\n", std::string(bytes, 4) + '\0');
  const auto root = plantnbv::readOcTree(path);
  std::filesystem::remove(path);
  EXPECT_EQ(plantnbv::occupiedVoxelCount(*root), std::pow(8.0, 16));
  CloudXYZ cloud;
  EXPECT_THROW(plantnbv::occupiedVoxelCentres(*root, cloud),
               plantnbv::InvalidArgumentError);
}
