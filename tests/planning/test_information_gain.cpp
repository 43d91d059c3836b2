#include <cmath>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <octomap/OcTree.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/planning/information_gain.h>

#include "planning_test_util.h"

using namespace plantnbv;
using test::lookingAlong;

namespace {

constexpr double kRes = 0.003;

/// The voxel centre of key k (OctoMap's keyToCoord).
double centre(int k)
{
  return (k - 32768 + 0.5) * kRes;
}

/// A plane of points at x = x0 spanning y, z in [-half, half] around (y0, z0), 1 mm
/// apart: every voxel of one layer gets a hit.
CloudXYZ wall(double x0, double y0, double z0, double half)
{
  CloudXYZ cloud;
  const int n = static_cast<int>(2.0 * half / 0.001);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      cloud.push_back(pcl::PointXYZ(static_cast<float>(x0),
                                    static_cast<float>(y0 - half + 0.001 * i),
                                    static_cast<float>(z0 - half + 0.001 * j)));
  return cloud;
}

/// The gains of `views` with InformationGain at `threads`.
std::vector<ViewGain> fastGains(std::shared_ptr<const OccupancyMap> map, const Roi& roi,
                                const GainConfig& config,
                                const std::vector<Viewpoint>& views, int threads)
{
  InformationGain gain;
  gain.setConfig(GainConfig::paper());
  gain.setInputMap(std::move(map));
  gain.setRoi(roi);
  gain.setConfig(config);
  gain.setNumberOfThreads(threads);
  std::vector<ViewGain> out;
  gain.compute(views, out);
  return out;
}

std::vector<ViewGain> referenceGains(const OccupancyMap& map, const Roi& roi,
                                     const GainConfig& config,
                                     const std::vector<Viewpoint>& views)
{
  std::vector<ViewGain> out(views.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (std::size_t i = 0; i < views.size(); ++i)
    out[i] = referenceInformationGain(map, roi, config, views[i]);
  return out;
}

void expectSameGains(const std::vector<ViewGain>& fast, const std::vector<ViewGain>& ref,
                     const std::string& what)
{
  ASSERT_EQ(fast.size(), ref.size());
  for (std::size_t i = 0; i < fast.size(); ++i) {
    EXPECT_EQ(fast[i].voxels_seen, ref[i].voxels_seen) << what << " candidate " << i;
    EXPECT_EQ(fast[i].unknown_seen, ref[i].unknown_seen) << what << " candidate " << i;
    EXPECT_NEAR(fast[i].gain, ref[i].gain, 1e-9 * std::max(1.0, ref[i].gain))
        << what << " candidate " << i;
  }
}

/// A line of voxels along x (keys kLineK0 + i, centres at y = kLineY, z = kLineZ): a
/// frame seen from voxel 0 with a hit in voxel 5 made voxels 0-4 free (p 0.4 after one
/// miss) and voxel 5 occupied (p 0.7); the others are unknown.
const int kLineK0 = 32768 + 200;
const double kLineY = centre(32768 + 10), kLineZ = centre(32768 + 20);

/// The centre of the line's voxel i (key kLineK0 + i).
Eigen::Vector3d lineVoxel(int i)
{
  return Eigen::Vector3d(centre(kLineK0 + i), kLineY, kLineZ);
}

std::shared_ptr<OccupancyMap> lineWithAHitAt5()
{
  auto map = std::make_shared<OccupancyMap>();
  CloudXYZ hit;
  const Eigen::Vector3f end = lineVoxel(5).cast<float>();
  hit.push_back(pcl::PointXYZ(end.x(), end.y(), end.z()));
  map->insert(hit, lineVoxel(0));
  return map;
}

/// The paper's gain with one ray, `voxels` voxels long: from a voxel centre along the
/// line, it ends at another voxel's centre.
GainConfig oneRayConfig(int voxels)
{
  GainConfig config = GainConfig::paper();
  config.rays_x = config.rays_y = 1;
  config.raycast_range_m = voxels * kRes;
  return config;
}

/// The ROI of the line's voxels first..last (keys kLineK0 + i).
Roi lineVoxels(int first, int last)
{
  return Roi({Box(0.5 * (lineVoxel(first) + lineVoxel(last)),
                  Eigen::Vector3d((last - first) * kRes + 1e-6, 1e-6, 1e-6))});
}

/// One view per cell of the paper's sector (seeded), then the paper's v0.
std::vector<Viewpoint> sectorViewsAndV0(std::uint64_t seed)
{
  CylindricalSectorSampler sampler;
  sampler.setSamplesPerCell(1);
  Rng rng(seed);
  std::vector<Viewpoint> views;
  sampler.sample(rng, views);
  views.push_back(test::paperV0());
  return views;
}

/// The gains whose snapshots differ (16 x 12 rays): the paper's entropy (the ROI and
/// the occupied voxels), unknown voxels only with a depth (the defaults' gain; values
/// worth 0), visibility weighting (every known voxel).
std::vector<std::pair<const char*, GainConfig>> snapshotVariants()
{
  GainConfig paper = GainConfig::paper();
  paper.rays_x = 16;
  paper.rays_y = 12;
  GainConfig unknown_only = paper;
  unknown_only.unknown_only = true;
  unknown_only.unknown_depth = 3;
  GainConfig weighted = paper;
  weighted.visibility_weighted = true;
  return {{"paper", paper}, {"unknown_only", unknown_only}, {"weighted", weighted}};
}

/// A large ROI box, small ones, and none.
std::vector<std::pair<const char*, Roi>> snapshotRois(const Plant& plant)
{
  return {{"whole_plant", wholePlantRoi(plant)},
          {"leaf_nodes", leafNodeRoi(plant)},
          {"no_roi", Roi()}};
}

} // namespace

TEST(InformationGain, OccupancyEntropyValues)
{
  EXPECT_EQ(occupancyEntropy(0.0), 0.0);
  EXPECT_EQ(occupancyEntropy(1.0), 0.0);
  EXPECT_EQ(occupancyEntropy(0.5), 1.0);
  EXPECT_NEAR(occupancyEntropy(0.7), 0.8812908992306927, 1e-15);
  EXPECT_NEAR(occupancyEntropy(0.12), 0.5293608652873644, 1e-15);
  EXPECT_DOUBLE_EQ(occupancyEntropy(0.3), occupancyEntropy(0.7));
  EXPECT_TRUE(std::isnan(occupancyEntropy(-0.1)));
  EXPECT_TRUE(std::isnan(occupancyEntropy(1.5)));
  EXPECT_TRUE(std::isnan(occupancyEntropy(std::nan(""))));
}

TEST(InformationGain, UnknownMapGainCountsTheDistinctFrustumVoxelsInTheRoi)
{
  const auto map = std::make_shared<const OccupancyMap>();
  const Viewpoint view = lookingAlong(Eigen::Vector3d(0.61, 0.02, 1.1), 0.1);
  const Roi roi({Box(Eigen::Vector3d(1.0, 0.0, 1.15), Eigen::Vector3d(0.3, 0.3, 0.7))});
  GainConfig config = GainConfig::paper();
  config.rays_x = 40;
  config.rays_y = 30;

  // The voxels, counted here with OctoMap itself from the documented ray geometry.
  const octomap::OcTree& tree = map->getOcTree();
  const Eigen::Matrix3d R = view.orientation.toRotationMatrix();
  const double th = std::tan(0.5 * config.horizontal_fov_rad);
  const double tv = std::tan(0.5 * config.vertical_fov_rad);
  const octomap::point3d origin(static_cast<float>(view.position.x()),
                                static_cast<float>(view.position.y()),
                                static_cast<float>(view.position.z()));
  std::set<std::tuple<int, int, int>> voxels;
  octomap::KeyRay ray;
  for (int j = 0; j < config.rays_y; ++j)
    for (int i = 0; i < config.rays_x; ++i) {
      const double x_o = th * ((2.0 * i + 1.0) / config.rays_x - 1.0);
      const double y_o = tv * ((2.0 * j + 1.0) / config.rays_y - 1.0);
      const Eigen::Vector3d d = Eigen::Vector3d(1.0, -x_o, -y_o).normalized();
      float e[3];
      for (int a = 0; a < 3; ++a)
        e[a] = static_cast<float>(view.position[a] +
                                  config.raycast_range_m *
                                      (R(a, 0) * d[0] + R(a, 1) * d[1] + R(a, 2) * d[2]));
      const octomap::point3d end(e[0], e[1], e[2]);
      ASSERT_TRUE(tree.computeRayKeys(origin, end, ray));
      std::vector<octomap::OcTreeKey> keys(ray.begin(), ray.end());
      keys.push_back(tree.coordToKey(end));
      for (const auto& k : keys)
        if (roi.contains(Eigen::Vector3d(centre(k[0]), centre(k[1]), centre(k[2]))))
          voxels.insert({k[0], k[1], k[2]});
    }
  ASSERT_GT(voxels.size(), 10000u);

  InformationGain gain;
  gain.setConfig(GainConfig::paper());
  gain.setInputMap(map);
  gain.setRoi(roi);
  gain.setConfig(config);
  const ViewGain g = gain.compute(view);
  EXPECT_EQ(g.voxels_seen, voxels.size());
  EXPECT_EQ(g.unknown_seen, voxels.size());
  EXPECT_EQ(g.gain, static_cast<double>(voxels.size())); // 1 bit each
  const ViewGain ref = referenceInformationGain(*map, roi, config, view);
  EXPECT_EQ(ref.voxels_seen, voxels.size());
  EXPECT_EQ(ref.gain, g.gain);
  EXPECT_EQ(ref.rays_cast, 1200u);
  EXPECT_LE(g.rays_cast, 1200u);
}

TEST(InformationGain, CandidateLookingAwayFromTheRoiGainsNothing)
{
  const auto map = std::make_shared<const OccupancyMap>();
  const Roi roi({Box(Eigen::Vector3d(1.0, 0.0, 1.15), Eigen::Vector3d(0.3, 0.3, 0.7))});
  InformationGain gain;
  gain.setConfig(GainConfig::paper());
  gain.setInputMap(map);
  gain.setRoi(roi);
  const ViewGain away = gain.compute(lookingAlong(Eigen::Vector3d(0.6, 0.0, 1.1), M_PI));
  EXPECT_EQ(away.gain, 0.0);
  EXPECT_EQ(away.voxels_seen, 0u);
  EXPECT_EQ(away.rays_cast, 0u);
  EXPECT_EQ(referenceInformationGain(*map, roi, GainConfig::paper(),
                                     lookingAlong(Eigen::Vector3d(0.6, 0.0, 1.1), M_PI))
                .gain,
            0.0);
  // Beyond the range: 0.75 m, Table 1.
  const ViewGain far = gain.compute(lookingAlong(Eigen::Vector3d(-0.2, 0.0, 1.1), 0.0));
  EXPECT_EQ(far.gain, 0.0);
}

TEST(InformationGain, AnRoiOutOfEveryCandidatesReachGainsNothingHoweverFar)
{
  // A box 50 m from the plant's map (an ROI in the wrong frame or units): no ray reaches
  // it, so every gain is 0, as the reference says, and no snapshot spans the 50 m.
  const auto map = test::plantMap();
  const Roi roi({Box(Eigen::Vector3d(50.0, 50.0, 50.0), Eigen::Vector3d(0.1, 0.1, 0.1))});
  // v0, and a camera 0.76 m + 2 voxels from the box's face, looking at it.
  const std::vector<Viewpoint> views = {
      test::paperV0(),
      lookingAlong(Eigen::Vector3d(49.95 - 0.76 - 2 * kRes, 50.0, 50.0), 0.0)};
  InformationGain gain;
  gain.setConfig(GainConfig::paper());
  gain.setInputMap(map);
  gain.setRoi(roi);
  std::vector<ViewGain> out;
  gain.compute(views, out);
  ASSERT_EQ(out.size(), 2u);
  for (std::size_t i = 0; i < views.size(); ++i) {
    EXPECT_EQ(out[i].gain, 0.0) << i;
    EXPECT_EQ(out[i].voxels_seen, 0u) << i;
    EXPECT_EQ(out[i].rays_cast, 0u) << i;
    EXPECT_EQ(
        referenceInformationGain(*map, roi, GainConfig::paper(), views[i]).voxels_seen,
        0u);
  }
  EXPECT_EQ(gain.getLastStats().rays_cast, 0u);
}

TEST(InformationGain, AFarBoxOfAnRoiChangesNoGainAndNoSnapshot)
{
  // One box on the plant, one 50 m away: the gains are those of the near box alone (the
  // far one is out of every ray's reach), and the snapshot does not span the 50 m.
  const auto map = test::plantMap();
  const Box near(Eigen::Vector3d(1.0, 0.0, 1.15), Eigen::Vector3d(0.1, 0.1, 0.2));
  const Box far(Eigen::Vector3d(50.0, 50.0, 50.0), Eigen::Vector3d(0.1, 0.1, 0.1));
  const std::vector<Viewpoint> views = {test::paperV0()};
  InformationGain both, alone;
  both.setConfig(GainConfig::paper());
  alone.setConfig(GainConfig::paper());
  both.setInputMap(map);
  alone.setInputMap(map);
  both.setRoi(Roi({near, far}));
  alone.setRoi(Roi({near}));
  std::vector<ViewGain> a, b;
  both.compute(views, a);
  alone.compute(views, b);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_GT(a[0].gain, 0.0);
  EXPECT_EQ(a[0].gain, b[0].gain);
  EXPECT_EQ(a[0].voxels_seen, b[0].voxels_seen);
  EXPECT_EQ(both.getLastStats().bricks, alone.getLastStats().bricks);
  EXPECT_NEAR(
      a[0].gain,
      referenceInformationGain(*map, Roi({near, far}), GainConfig::paper(), views[0])
          .gain,
      1e-6 * a[0].gain);
  // The same candidates again: the snapshot is reused.
  both.compute(views, a);
  EXPECT_FALSE(both.getLastStats().rebuilt);
}

TEST(InformationGain, VoxelsBehindAWallDoNotCount)
{
  auto map = std::make_shared<OccupancyMap>();
  map->insert(wall(0.9, 0.0, 1.1, 0.3), Eigen::Vector3d(0.3, 0.0, 1.1));
  const Viewpoint view = lookingAlong(Eigen::Vector3d(0.5, 0.0, 1.1), 0.0);
  const Roi behind({Box(Eigen::Vector3d(1.1, 0.0, 1.1), Eigen::Vector3d(0.2, 0.2, 0.2))});
  const Roi before({Box(Eigen::Vector3d(0.8, 0.0, 1.1), Eigen::Vector3d(0.1, 0.1, 0.1))});
  const Roi across({Box(Eigen::Vector3d(0.9, 0.0, 1.1), Eigen::Vector3d(0.1, 0.1, 0.1))});
  const GainConfig config = GainConfig::paper();

  InformationGain gain;
  gain.setConfig(GainConfig::paper());
  gain.setInputMap(map);
  gain.setRoi(behind);
  EXPECT_EQ(gain.compute(view).gain, 0.0);
  EXPECT_EQ(referenceInformationGain(*map, behind, config, view).gain, 0.0);
  // Without the wall the same ROI is worth a lot.
  InformationGain empty;
  empty.setConfig(GainConfig::paper());
  empty.setInputMap(std::make_shared<const OccupancyMap>());
  empty.setRoi(behind);
  EXPECT_GT(empty.compute(view).gain, 1000.0);

  // Free voxels in front of the wall are known (low entropy); the wall's voxels count.
  for (const Roi& roi : {before, across}) {
    gain.setRoi(roi);
    const ViewGain g = gain.compute(view);
    const ViewGain ref = referenceInformationGain(*map, roi, config, view);
    EXPECT_GT(g.gain, 0.0);
    EXPECT_EQ(g.voxels_seen, ref.voxels_seen);
    EXPECT_EQ(g.unknown_seen, 0u);
    EXPECT_NEAR(g.gain, ref.gain, 1e-9 * ref.gain);
  }
}

TEST(InformationGain, GainFallsOnceTheViewIsInserted)
{
  auto map = std::make_shared<OccupancyMap>();
  const Roi roi = wholePlantRoi(test::plantWorld().plant);
  const Viewpoint view = test::paperV0();
  InformationGain gain;
  gain.setConfig(GainConfig::paper());
  gain.setInputMap(map);
  gain.setRoi(roi);
  const ViewGain before = gain.compute(view);
  test::insertView(*map, view);
  const ViewGain after = gain.compute(view); // rebuilt: the map's revision changed
  EXPECT_TRUE(gain.getLastStats().rebuilt);
  // Free voxels seen once still hold 0.97 bits (p = 0.4); most unknown ones are gone
  // (some rays slip between the occupied voxels of a thin leaf: unknown behind it).
  EXPECT_LT(after.gain, before.gain);
  EXPECT_LT(static_cast<double>(after.unknown_seen),
            0.7 * static_cast<double>(before.unknown_seen));
  const ViewGain ref = referenceInformationGain(*map, roi, GainConfig::paper(), view);
  EXPECT_EQ(after.voxels_seen, ref.voxels_seen);
  EXPECT_NEAR(after.gain, ref.gain, 1e-9 * ref.gain);
  // Unchanged map: the snapshot is reused.
  EXPECT_EQ(gain.compute(view).gain, after.gain);
  EXPECT_FALSE(gain.getLastStats().rebuilt);
}

TEST(InformationGain, EqualsTheReferenceOnAPlantMapAtAnyThreadCount)
{
  const auto map = test::plantMap();
  const Plant& plant = test::plantWorld().plant;
  const std::vector<Viewpoint> views = sectorViewsAndV0(3);
  GainConfig config = GainConfig::paper();
  config.rays_x = 32;
  config.rays_y = 24;
  const std::pair<const char*, Roi> rois[] = {
      {"whole_plant", wholePlantRoi(plant)},
      {"main_stem", mainStemRoi(plant)},
      {"leaf_nodes", leafNodeRoi(plant)},
      {"no_roi", Roi()},
  };
  for (const auto& [name, roi] : rois) {
    const std::vector<ViewGain> ref = referenceGains(*map, roi, config, views);
    const std::vector<ViewGain> one = fastGains(map, roi, config, views, 1);
    const std::vector<ViewGain> two = fastGains(map, roi, config, views, 2);
    expectSameGains(one, ref, name);
    double total = 0.0;
    for (std::size_t i = 0; i < views.size(); ++i) {
      EXPECT_EQ(one[i].gain, two[i].gain) << name; // bit for bit
      EXPECT_EQ(one[i].voxels_seen, two[i].voxels_seen) << name;
      EXPECT_EQ(one[i].rays_cast, two[i].rays_cast) << name;
      total += one[i].gain;
    }
    EXPECT_GT(total, 0.0) << name;
  }
}

TEST(InformationGain, UpdateGivesTheSameSnapshotAndGainsAtAnyThreadCount)
{
  // update() walks the tree and fills the snapshot on setNumberOfThreads() threads: the
  // snapshot's sizes and every gain and voxel count are bit for bit those of one thread,
  // with an ROI and without, for a snapshot of the ROI and the occupied voxels and for
  // one of every known voxel (visibility weighting), on the plant map, on a map of one
  // line of voxels (fewer subtrees than threads) and on an empty map.
  const Plant& plant = test::plantWorld().plant;
  std::vector<Viewpoint> views = sectorViewsAndV0(5);
  views.push_back(lookingAlong(lineVoxel(-50), 0.0));
  const std::pair<const char*, std::shared_ptr<const OccupancyMap>> maps[] = {
      {"plant", test::plantMap()},
      {"line", lineWithAHitAt5()},
      {"empty", std::make_shared<OccupancyMap>()},
  };
  const auto configs = snapshotVariants();
  const auto rois = snapshotRois(plant);
  for (const auto& [map_name, map] : maps)
    for (const auto& [config_name, config] : configs)
      for (const auto& [roi_name, roi] : rois) {
        std::vector<ViewGain> one;
        InformationGain::Stats one_stats;
        for (int threads : {1, 2, 3}) {
          const std::string what = std::string(map_name) + ", " + config_name + ", " +
                                   roi_name + ", " + std::to_string(threads) + " threads";
          InformationGain gain;
          gain.setConfig(config);
          gain.setInputMap(map);
          gain.setRoi(roi);
          gain.setNumberOfThreads(threads);
          gain.update();
          const InformationGain::Stats stats = gain.getLastStats();
          std::vector<ViewGain> out;
          gain.compute(views, out);
          if (threads == 1) {
            one = out;
            one_stats = stats;
            continue;
          }
          EXPECT_EQ(stats.bricks, one_stats.bricks) << what;
          EXPECT_EQ(stats.values, one_stats.values) << what;
          EXPECT_EQ(stats.leaves, one_stats.leaves) << what;
          ASSERT_EQ(out.size(), one.size()) << what;
          for (std::size_t i = 0; i < out.size(); ++i) {
            EXPECT_EQ(out[i].gain, one[i].gain) << what << " candidate " << i;
            EXPECT_EQ(out[i].voxels_seen, one[i].voxels_seen)
                << what << " candidate " << i;
            EXPECT_EQ(out[i].unknown_seen, one[i].unknown_seen)
                << what << " candidate " << i;
            EXPECT_EQ(out[i].rays_cast, one[i].rays_cast) << what << " candidate " << i;
          }
        }
        if (std::string(map_name) != "empty") {
          EXPECT_GT(one_stats.leaves, 0u) << map_name << ", " << config_name;
        }
      }
}

TEST(InformationGain, AfterAnInsertReadsOnlyTheChangedBricksWithTheGainsOfANewSnapshot)
{
  // Gain objects follow one map through views of the plant: after each insert their
  // compute() reads only the bricks the insert changed (OccupancyMap::getChangedBricks)
  // and gives every candidate's gain and counts of a new object, bit for bit: the
  // paper's gain, unknown voxels only with a depth, and visibility weighting on the whole
  // plant, the paper's also on the leaf nodes and without ROI; on 1 and 2 threads. Two
  // inserts between computes, and clear(), make them read the whole map again.
  const Plant& plant = test::plantWorld().plant;
  std::vector<Viewpoint> candidates = sectorViewsAndV0(7);
  candidates.resize(8);
  const auto configs = snapshotVariants();
  const auto rois = snapshotRois(plant);
  auto map = std::make_shared<OccupancyMap>();
  struct Follower {
    std::string what;
    GainConfig config;
    Roi roi;
    int threads;
    std::unique_ptr<InformationGain> gain;
  };
  std::vector<Follower> followers;
  for (const auto& [config_name, config] : configs)
    for (const auto& [roi_name, roi] : rois)
      for (int threads : {1, 2}) {
        if (std::string(config_name) != "paper" && std::string(roi_name) != "whole_plant")
          continue; // every kind of snapshot once is enough (and keeps ASan's run short)
        Follower f{std::string(config_name) + ", " + roi_name + ", " +
                       std::to_string(threads) + " threads",
                   config, roi, threads, std::make_unique<InformationGain>()};
        f.gain->setConfig(config);
        f.gain->setInputMap(map);
        f.gain->setRoi(roi);
        f.gain->setNumberOfThreads(threads);
        followers.push_back(std::move(f));
      }
  const auto expectGainsOfANewObject = [&](const std::string& step, bool incremental) {
    for (Follower& f : followers) {
      const std::string what = f.what + ", " + step;
      std::vector<ViewGain> out;
      f.gain->compute(candidates, out);
      EXPECT_EQ(f.gain->getLastStats().incremental, incremental) << what;
      const std::vector<ViewGain> fresh =
          fastGains(map, f.roi, f.config, candidates, f.threads);
      ASSERT_EQ(out.size(), fresh.size()) << what;
      for (std::size_t i = 0; i < out.size(); ++i) {
        EXPECT_EQ(out[i].gain, fresh[i].gain) << what << " candidate " << i;
        EXPECT_EQ(out[i].voxels_seen, fresh[i].voxels_seen) << what << " candidate " << i;
        EXPECT_EQ(out[i].unknown_seen, fresh[i].unknown_seen)
            << what << " candidate " << i;
        EXPECT_EQ(out[i].rays_cast, fresh[i].rays_cast) << what << " candidate " << i;
      }
    }
  };
  expectGainsOfANewObject("empty map", false);
  CylindricalSectorSampler sampler;
  const double facing = sampler.getSector().facingAzimuth();
  const Viewpoint path[] = {test::paperV0(), sampler.viewpointAt(facing + 0.3, 1.2),
                            sampler.viewpointAt(facing - 0.4, 1.0),
                            sampler.viewpointAt(facing, 1.4),
                            sampler.viewpointAt(facing + 0.6, 0.9)};
  for (std::size_t v = 0; v < 3; ++v) {
    test::insertView(*map, path[v]);
    expectGainsOfANewObject("view " + std::to_string(v), true);
  }
  test::insertView(*map, path[3]);
  test::insertView(*map, path[4]);
  expectGainsOfANewObject("two views", false);
  map->clear();
  expectGainsOfANewObject("cleared", false);
  test::insertView(*map, path[0]);
  expectGainsOfANewObject("a view after clear()", true);
}

TEST(InformationGain, EqualsTheReferenceAtTheDefaultRayGrid)
{
  const auto map = test::plantMap();
  const Plant& plant = test::plantWorld().plant;
  CylindricalSectorSampler sampler;
  const std::vector<Viewpoint> views = {test::paperV0(), sampler.gridCellCentres()[4],
                                        sampler.gridCellCentres()[6]};
  const GainConfig config = GainConfig::paper();
  for (const Roi& roi : {wholePlantRoi(plant), leafNodeRoi(plant)})
    expectSameGains(fastGains(map, roi, config, views, 2),
                    referenceGains(*map, roi, config, views), "default grid");
}

TEST(InformationGain, VisibilityWeightedGainByHand)
{
  // One ray along +x from a voxel centre, 10 voxels long: voxels 0..9 by computeRayKeys,
  // then the end voxel 10; 0-4 free, 5 occupied, 6-10 unknown (lineWithAHitAt5).
  const auto map = lineWithAHitAt5();
  std::vector<double> p(11);
  for (int i = 0; i <= 10; ++i)
    p[static_cast<std::size_t>(i)] = map->probability(lineVoxel(i));
  ASSERT_NEAR(p[0], 0.4, 1e-6);
  ASSERT_NEAR(p[5], 0.7, 1e-6);
  ASSERT_EQ(p[6], 0.5);

  GainConfig config = oneRayConfig(10); // ends at the centre of voxel 10
  // The ROI holds voxels 3..8.
  const Roi roi = lineVoxels(3, 8);
  const Viewpoint view = lookingAlong(lineVoxel(0), 0.0);

  double by_hand = 0.0, vis = 1.0;
  for (int i = 0; i <= 10; ++i) {
    if (i >= 3 && i <= 8)
      by_hand += vis * occupancyEntropy(p[static_cast<std::size_t>(i)]);
    vis *= 1.0 - p[static_cast<std::size_t>(i)];
  }
  config.visibility_weighted = true;
  InformationGain gain;
  gain.setConfig(GainConfig::paper());
  gain.setInputMap(map);
  gain.setRoi(roi);
  gain.setConfig(config);
  const ViewGain weighted = gain.compute(view);
  EXPECT_EQ(weighted.voxels_seen, 6u); // the ray goes on past the occupied voxel
  EXPECT_EQ(weighted.unknown_seen, 3u);
  EXPECT_NEAR(weighted.gain, by_hand, 1e-15);
  EXPECT_NEAR(referenceInformationGain(*map, roi, config, view).gain, by_hand, 1e-15);

  // The paper's gain stops after the occupied voxel 5: voxels 3, 4, 5.
  config.visibility_weighted = false;
  gain.setConfig(config);
  const ViewGain plain = gain.compute(view);
  EXPECT_EQ(plain.voxels_seen, 3u);
  EXPECT_NEAR(plain.gain,
              occupancyEntropy(p[3]) + occupancyEntropy(p[4]) + occupancyEntropy(p[5]),
              1e-15);
}

TEST(InformationGain, UnknownOnlyCountsNeverObservedVoxelsByHand)
{
  // lineWithAHitAt5; the gain's ray starts in voxel 4 and looks along -x: 4..0 are
  // free, -1 on unknown; the ROI holds voxels -3..2.
  const auto map = lineWithAHitAt5();
  const double p_free = map->probability(lineVoxel(0));
  ASSERT_NEAR(p_free, 0.4, 1e-6);

  GainConfig config = oneRayConfig(10); // ends at the centre of voxel -6
  const Roi roi = lineVoxels(-3, 2);
  const Viewpoint view = lookingAlong(lineVoxel(4), M_PI);
  InformationGain gain;
  gain.setInputMap(map);
  gain.setRoi(roi);
  // The default counts unknown voxels, 3 per ray at most; the paper's counts every
  // voxel's entropy.
  EXPECT_TRUE(GainConfig().unknown_only);
  EXPECT_EQ(GainConfig().unknown_depth, 3);
  EXPECT_FALSE(GainConfig::paper().unknown_only);
  EXPECT_EQ(GainConfig::paper().unknown_depth, 0);
  EXPECT_EQ(gain.compute(view).gain, 3.0);
  auto expectGain = [&](double bits, const char* what) {
    gain.setConfig(config);
    const ViewGain g = gain.compute(view);
    EXPECT_EQ(g.voxels_seen, 6u) << what;
    EXPECT_EQ(g.unknown_seen, 3u) << what;
    EXPECT_NEAR(g.gain, bits, 1e-12) << what;
    EXPECT_NEAR(referenceInformationGain(*map, roi, config, view).gain, bits, 1e-12)
        << what;
  };
  expectGain(3.0 * occupancyEntropy(p_free) + 3.0, "the paper's");
  config.unknown_only = true;
  expectGain(3.0, "unknown only");   // the free voxels 2, 1, 0 add nothing
  config.visibility_weighted = true; // the five free voxels before -1 pass 1 - p each
  expectGain(std::pow(1.0 - p_free, 5) * (1.0 + 0.5 + 0.25), "unknown only, weighted");
}

TEST(InformationGain, WithUnknownOnlyARayEndsAtTheLastUnknownVoxelItCounts)
{
  // lineWithAHitAt5; the gain's ray starts in voxel -4 and looks along +x to the centre
  // of voxel 5: -4..-1 unknown, 0..4 free, 5 occupied; the ROI holds voxels -2..3.
  const auto map = lineWithAHitAt5();
  const double p_free = map->probability(lineVoxel(0));
  ASSERT_NEAR(p_free, 0.4, 1e-6);
  ASSERT_EQ(map->probability(lineVoxel(-1)), 0.5);

  GainConfig config = oneRayConfig(9); // ends at the centre of voxel 5
  const Roi roi = lineVoxels(-2, 3);
  const Viewpoint view = lookingAlong(lineVoxel(-4), 0.0);
  InformationGain gain;
  gain.setInputMap(map);
  gain.setRoi(roi);
  auto expectGain = [&](std::size_t seen, std::size_t unknown, double bits,
                        const std::string& what) {
    gain.setConfig(config);
    const ViewGain g = gain.compute(view);
    const ViewGain ref = referenceInformationGain(*map, roi, config, view);
    EXPECT_EQ(g.voxels_seen, seen) << what;
    EXPECT_EQ(ref.voxels_seen, seen) << what;
    EXPECT_EQ(g.unknown_seen, unknown) << what;
    EXPECT_EQ(ref.unknown_seen, unknown) << what;
    EXPECT_NEAR(g.gain, bits, 1e-12) << what;
    EXPECT_NEAR(ref.gain, bits, 1e-12) << what;
  };
  // The paper's entropy: the free voxels behind the unknown one still count.
  config.unknown_depth = 1;
  expectGain(5, 1, 1.0 + 4.0 * occupancyEntropy(p_free), "paper's entropy, depth 1");
  // Unknown only: nothing behind the last unknown voxel the ray may count adds to the
  // gain, and the ray ends there, weighted or not.
  config.unknown_only = true;
  for (bool weighted : {false, true}) {
    config.visibility_weighted = weighted;
    const std::string how = weighted ? ", weighted" : "";
    // Weighted, the unknown voxels -4 and -3 before the ROI pass half each: -2 is seen
    // with 0.25, -1 with 0.125.
    config.unknown_depth = 1;
    expectGain(1, 1, weighted ? 0.25 : 1.0, "depth 1" + how);
    config.unknown_depth = 2;
    expectGain(2, 2, weighted ? 0.25 + 0.125 : 2.0, "depth 2" + how);
    // A budget the ray does not spend: it goes on through the free voxels 0..3, to the
    // occupied voxel 5 unweighted and to its end weighted.
    config.unknown_depth = 3;
    expectGain(6, 2, weighted ? 0.25 + 0.125 : 2.0, "depth 3" + how);
  }
}

TEST(InformationGain, WeightedUnknownOnlyAndDepthEqualTheReferenceOnAPlantMap)
{
  const auto map = test::plantMap();
  const Plant& plant = test::plantWorld().plant;
  CylindricalSectorSampler sampler;
  const std::vector<Viewpoint> views = sampler.gridCellCentres();
  GainConfig config = GainConfig::paper();
  config.rays_x = 16;
  config.rays_y = 12;
  // The paper's entropy (weighted only: unweighted is above), unknown voxels only, and
  // at most 3 of them per ray; each unweighted and visibility-weighted.
  for (int variant : {0, 1, 2}) {
    config.unknown_only = variant > 0;
    config.unknown_depth = variant == 2 ? 3 : 0;
    for (bool weighted : {false, true}) {
      if (variant == 0 && !weighted)
        continue;
      config.visibility_weighted = weighted;
      for (const Roi& roi :
           {wholePlantRoi(plant), mainStemRoi(plant), leafNodeRoi(plant), Roi()}) {
        const std::string what = "variant " + std::to_string(variant) +
                                 (weighted ? ", weighted" : ", unweighted");
        const std::vector<ViewGain> ref = referenceGains(*map, roi, config, views);
        const std::vector<ViewGain> fast = fastGains(map, roi, config, views, 2);
        expectSameGains(fast, ref, what);
        for (const ViewGain& g : fast) {
          if (config.unknown_only) {
            EXPECT_LE(g.gain, static_cast<double>(g.unknown_seen)) << what;
          }
          if (config.unknown_depth > 0) { // each ray counts at most 3 unknown voxels
            EXPECT_LE(g.unknown_seen, 3u * g.rays_cast) << what;
          }
        }
      }
    }
  }
}

TEST(InformationGain, InvalidInputsThrow)
{
  InformationGain gain;
  gain.setConfig(GainConfig::paper());
  EXPECT_THROW(gain.compute(test::paperV0()), InvalidArgumentError);
  EXPECT_THROW(gain.update(), InvalidArgumentError);
  EXPECT_THROW(gain.setInputMap(nullptr), InvalidArgumentError);
  EXPECT_THROW(gain.setNumberOfThreads(-1), InvalidArgumentError);
  GainConfig c;
  c.rays_x = 0;
  try {
    gain.setConfig(c);
    ADD_FAILURE() << "no error";
  } catch (const InvalidArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("rays_x = 0"), std::string::npos);
  }
  c = GainConfig();
  c.horizontal_fov_rad = M_PI;
  EXPECT_THROW(gain.setConfig(c), InvalidArgumentError);
  c = GainConfig();
  c.raycast_range_m = -1.0;
  EXPECT_THROW(gain.setConfig(c), InvalidArgumentError);
  c = GainConfig();
  c.unknown_depth = -1;
  EXPECT_THROW(gain.setConfig(c), InvalidArgumentError);
  Box bad;
  bad.size = Eigen::Vector3d(-1.0, 1.0, 1.0);
  EXPECT_THROW(gain.setRoi(Roi({bad})), InvalidArgumentError);
}
