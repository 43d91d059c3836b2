#include <algorithm>
#include <cmath>
#include <memory>
#include <set>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/planning/view_planner.h>

#include "planning_test_util.h"

using namespace plantnbv;
using test::FixedSampler;
using test::lookingAlong;

namespace {

const Eigen::Vector3d kBoxCentre(1.0, 0.0, 1.1);
const Roi kBox({Box(kBoxCentre, Eigen::Vector3d(0.1, 0.1, 0.1))});

/// A camera at `position` looking horizontally at the box.
Viewpoint lookingAtBox(const Eigen::Vector3d& position)
{
  const Eigen::Vector3d d = kBoxCentre - position;
  return lookingAlong(position, std::atan2(d.y(), d.x()));
}

const Viewpoint kAway = lookingAlong(Eigen::Vector3d(0.5, 0.0, 1.1), M_PI);
const Viewpoint kBlocked = lookingAtBox(Eigen::Vector3d(0.5, 0.25, 1.1));
const Viewpoint kClear = lookingAtBox(Eigen::Vector3d(0.5, -0.25, 1.1));

/// A map with a wall (x = 0.8, y in [0.02, 0.4]) between kBlocked and the box; kClear
/// sees the box, which is unobserved.
std::shared_ptr<const OccupancyMap> wallMap()
{
  auto map = std::make_shared<OccupancyMap>();
  CloudXYZ cloud;
  for (int i = 0; i <= 380; ++i)
    for (int j = 0; j <= 380; ++j)
      cloud.push_back(pcl::PointXYZ(0.8f, static_cast<float>(0.02 + 0.001 * i),
                                    static_cast<float>(0.91 + 0.001 * j)));
  map->insert(cloud, Eigen::Vector3d(0.3, 0.21, 1.1));
  return map;
}

template <typename Planner>
std::unique_ptr<Planner> makePlanner(std::shared_ptr<const OccupancyMap> map,
                                     ViewpointSampler::ConstPtr sampler,
                                     const Roi& roi = kBox)
{
  auto p = std::make_unique<Planner>();
  p->setGainConfig(GainConfig::paper()); // these tests count the paper's bits
  p->setInputMap(std::move(map));
  p->setCandidateSampler(std::move(sampler));
  p->setRoi(roi);
  return p;
}

} // namespace

TEST(AttentionNbvPlanner, PicksTheCandidateThatSeesTheUnobservedBox)
{
  const auto map = wallMap();
  auto planner = makePlanner<AttentionNbvPlanner>(
      map,
      std::make_shared<FixedSampler>(std::vector<Viewpoint>{kAway, kBlocked, kClear}));
  EXPECT_EQ(planner->name(), "nbv");
  NextViewResult result;
  planner->compute(result);
  ASSERT_EQ(result.candidates.size(), 3u);
  EXPECT_EQ(result.chosen, 2u);
  EXPECT_EQ(result.view.position, kClear.position);
  EXPECT_EQ(result.candidates[0].gain.gain, 0.0);
  EXPECT_EQ(result.candidates[1].gain.gain, 0.0); // behind the wall
  EXPECT_GT(result.candidates[2].gain.gain, 1000.0);
  EXPECT_EQ(result.gain, result.candidates[2].gain.gain);
  EXPECT_EQ(result.utility, result.gain);
  EXPECT_FALSE(result.stop);
  EXPECT_NEAR(result.gain,
              referenceInformationGain(*map, kBox, GainConfig::paper(), kClear).gain,
              1e-9 * result.gain);
  EXPECT_GE(result.total_ms, result.gain_ms);
}

TEST(AttentionNbvPlanner, TiesGoToTheLowestIndexAndTheStopGainStops)
{
  const auto map = std::make_shared<const OccupancyMap>();
  auto planner = makePlanner<AttentionNbvPlanner>(
      map, std::make_shared<FixedSampler>(std::vector<Viewpoint>{kAway, kClear, kClear}));
  NextViewResult result;
  planner->compute(result);
  EXPECT_EQ(result.chosen, 1u);
  EXPECT_EQ(result.candidates[1].gain.gain, result.candidates[2].gain.gain);

  planner->setCandidateSampler(
      std::make_shared<FixedSampler>(std::vector<Viewpoint>{kAway, kAway, kAway}));
  planner->setStopGain(1.0);
  planner->compute(result);
  EXPECT_EQ(result.chosen, 0u);
  EXPECT_EQ(result.gain, 0.0);
  EXPECT_TRUE(result.stop);
}

TEST(AttentionNbvPlanner, TravelCostPrefersNearbyViews)
{
  const auto map = std::make_shared<const OccupancyMap>();
  const Viewpoint near_current =
      lookingAlong(Eigen::Vector3d(0.7, 0.3, 1.1), M_PI); // sees nothing
  auto planner = makePlanner<AttentionNbvPlanner>(
      map, std::make_shared<FixedSampler>(std::vector<Viewpoint>{kClear, near_current}));
  NextViewResult result;
  planner->compute(result);
  const std::size_t best_gain = result.chosen;
  planner->setTravelCostWeight(1e9);
  EXPECT_THROW(planner->compute(result), InvalidArgumentError); // needs the current view
  planner->setCurrentView(lookingAlong(Eigen::Vector3d(0.7, 0.31, 1.1), 0.0));
  planner->compute(result);
  EXPECT_EQ(result.chosen, 1u);
  EXPECT_EQ(best_gain, 0u);
  EXPECT_NEAR(result.utility, result.gain - 1e9 * 0.01, 1e-3);
  EXPECT_THROW(planner->setTravelCostWeight(-1.0), InvalidArgumentError);
}

TEST(AttentionNbvPlanner, ExploresOnceTheRoiHasLittleLeftToGive)
{
  // kClear sees the box; once a frame from kClear has made the box known, counting
  // unknown voxels leaves the ROI nothing, and the planner explores: a region only
  // kAway sees.
  auto map = std::make_shared<OccupancyMap>();
  const Roi region({Box(Eigen::Vector3d(0.2, 0.0, 1.1), Eigen::Vector3d(0.1, 0.1, 0.1))});
  auto planner = makePlanner<AttentionNbvPlanner>(
      map, std::make_shared<FixedSampler>(std::vector<Viewpoint>{kClear, kAway}));
  GainConfig config = GainConfig::paper();
  config.unknown_only = true; // every unknown voxel along a ray
  planner->setGainConfig(config);
  planner->setExploration(0.5, region);
  EXPECT_EQ(planner->getExplorationShare(), 0.5);
  NextViewResult first;
  planner->compute(first);
  EXPECT_FALSE(first.explored);
  EXPECT_EQ(first.chosen, 0u);
  ASSERT_GT(first.gain, 1000.0);

  CloudXYZ wall;
  for (int i = 0; i <= 600; ++i)
    for (int j = 0; j <= 600; ++j)
      wall.push_back(pcl::PointXYZ(1.2f, static_cast<float>(-0.3 + 0.001 * i),
                                   static_cast<float>(0.8 + 0.001 * j)));
  map->insert(wall, kClear.position);
  NextViewResult second;
  planner->compute(second);
  ASSERT_LT(second.candidates[0].gain.gain, 0.5 * first.gain);
  EXPECT_TRUE(second.explored);
  EXPECT_EQ(second.chosen, 1u);                           // the region's unknown voxels
  EXPECT_EQ(second.gain, second.candidates[1].gain.gain); // still the ROI's gain
  EXPECT_EQ(second.utility, referenceInformationGain(*map, region, config, kAway).gain);
  EXPECT_GT(second.utility, 1000.0);

  // Without exploration the ROI's gain alone decides.
  planner->setExploration(0.0);
  planner->compute(second);
  EXPECT_FALSE(second.explored);
  EXPECT_EQ(second.chosen, 0u);
  for (double bad : {-0.1, 1.5, std::nan("")})
    EXPECT_THROW(planner->setExploration(bad), InvalidArgumentError);
}

TEST(AttentionNbvPlanner, ExploresWhileFewViewsHaveBeenTaken)
{
  // The ROI is kBox, which kClear sees; the region only kAway sees (as above). Up to
  // `views` visited positions the region's gain ranks the candidates, then the ROI's.
  const auto map = std::make_shared<const OccupancyMap>();
  const Roi region({Box(Eigen::Vector3d(0.2, 0.0, 1.1), Eigen::Vector3d(0.1, 0.1, 0.1))});
  auto planner = makePlanner<AttentionNbvPlanner>(
      map, std::make_shared<FixedSampler>(std::vector<Viewpoint>{kClear, kAway}));
  planner->setViewSpacing(0.0);
  planner->setExploration(0.0, region); // the share's rule off
  planner->setExplorationViews(1);
  EXPECT_EQ(planner->getExplorationViews(), 1);
  NextViewResult result;
  planner->addVisitedPosition(Eigen::Vector3d(0.0, 0.0, 1.0));
  planner->compute(result);
  EXPECT_TRUE(planner->exploresTheFirstViews());
  EXPECT_TRUE(result.explored);
  EXPECT_EQ(result.chosen, 1u);
  EXPECT_EQ(result.utility,
            referenceInformationGain(*map, region, planner->getGainConfig(), kAway).gain);

  planner->addVisitedPosition(Eigen::Vector3d(0.0, 0.0, 1.0));
  planner->compute(result);
  EXPECT_FALSE(planner->exploresTheFirstViews());
  EXPECT_FALSE(result.explored); // two views taken
  EXPECT_EQ(result.chosen, 0u);
  planner->setExplorationViews(2);
  planner->compute(result);
  EXPECT_TRUE(result.explored);
  planner->setExplorationViews(0); // the default: never
  planner->clearVisitedPositions();
  planner->compute(result);
  EXPECT_FALSE(result.explored);
  EXPECT_EQ(result.chosen, 0u);
  EXPECT_THROW(planner->setExplorationViews(-1), InvalidArgumentError);
}

TEST(AttentionNbvPlanner, ViewSpacingPassesOverCandidatesNearVisitedPositions)
{
  const auto map = std::make_shared<const OccupancyMap>();
  const Viewpoint farther = lookingAtBox(Eigen::Vector3d(0.3, -0.25, 1.1)); // sees less
  auto planner = makePlanner<AttentionNbvPlanner>(
      map, std::make_shared<FixedSampler>(std::vector<Viewpoint>{kClear, farther}));
  NextViewResult result;
  planner->compute(result);
  ASSERT_EQ(result.chosen, 0u);
  ASSERT_GT(result.candidates[0].gain.gain, result.candidates[1].gain.gain);

  planner->addVisitedPosition(kClear.position + Eigen::Vector3d(0.0, 0.0, 0.05));
  planner->setViewSpacing(0.0);
  planner->compute(result);
  EXPECT_EQ(result.chosen, 0u); // no spacing: the gain decides
  planner->setViewSpacing(0.1);
  EXPECT_EQ(planner->getViewSpacing(), 0.1);
  planner->compute(result);
  EXPECT_EQ(result.chosen, 1u); // kClear is 5 cm from a visited position
  EXPECT_EQ(result.gain, result.candidates[1].gain.gain);
  // When every candidate is near a visited position, the gain decides again.
  planner->addVisitedPosition(farther.position);
  planner->compute(result);
  EXPECT_EQ(result.chosen, 0u);
  ASSERT_EQ(planner->getVisitedPositions().size(), 2u);
  planner->clearVisitedPositions();
  EXPECT_TRUE(planner->getVisitedPositions().empty());
  planner->setVisitedPositions({kClear.position});
  planner->compute(result);
  EXPECT_EQ(result.chosen, 1u); // as with the one recorded near kClear
  for (double bad : {-0.1, std::nan(""), HUGE_VAL})
    EXPECT_THROW(planner->setViewSpacing(bad), InvalidArgumentError);
}

TEST(AttentionNbvPlanner, SameSeedSameViews)
{
  const auto map = test::plantMap();
  const Roi roi = leafNodeRoi(test::plantWorld().plant);
  auto sampler = std::make_shared<CylindricalSectorSampler>();
  auto a = makePlanner<AttentionNbvPlanner>(map, sampler, roi);
  auto b = makePlanner<AttentionNbvPlanner>(map, sampler, roi);
  a->setSeed(9);
  b->setSeed(9);
  b->setNumberOfThreads(1);
  for (int step = 0; step < 2; ++step) {
    NextViewResult ra, rb;
    a->compute(ra);
    b->compute(rb);
    ASSERT_EQ(ra.candidates.size(), 27u);
    EXPECT_EQ(ra.chosen, rb.chosen);
    EXPECT_EQ(ra.gain, rb.gain);
    EXPECT_EQ(ra.view.position, rb.view.position);
    for (const CandidateView& c : ra.candidates)
      EXPECT_LE(c.gain.gain, ra.gain);
  }
}

TEST(PredefinedPlanner, PatternOrders)
{
  using V = std::vector<int>;
  EXPECT_EQ(PredefinedPlanner::patternOrder(1), (V{0, 1, 2, 5, 4, 3, 6, 7, 8}));
  EXPECT_EQ(PredefinedPlanner::patternOrder(2), (V{0, 3, 6, 7, 4, 1, 2, 5, 8}));
  EXPECT_EQ(PredefinedPlanner::patternOrder(3), (V{4, 5, 8, 7, 6, 3, 0, 1, 2}));
  EXPECT_EQ(PredefinedPlanner::patternOrder(4), (V{0, 1, 3, 2, 4, 6, 5, 7, 8}));
  // Every pattern visits every cell once on other grids too.
  for (int pattern = 1; pattern <= 4; ++pattern)
    for (const auto& [rows, cols] : {std::pair{1, 1}, {1, 5}, {2, 4}, {4, 3}, {5, 5}}) {
      V order = PredefinedPlanner::patternOrder(pattern, rows, cols);
      ASSERT_EQ(order.size(), static_cast<std::size_t>(rows * cols));
      std::sort(order.begin(), order.end());
      for (int i = 0; i < rows * cols; ++i)
        EXPECT_EQ(order[static_cast<std::size_t>(i)], i)
            << pattern << " " << rows << "x" << cols;
    }
  EXPECT_THROW(PredefinedPlanner::patternOrder(0), InvalidArgumentError);
  EXPECT_THROW(PredefinedPlanner::patternOrder(5), InvalidArgumentError);
  EXPECT_THROW(PredefinedPlanner::patternOrder(1, 0, 3), InvalidArgumentError);
}

TEST(PredefinedPlanner, VisitsTheNineCentresInPatternOrderAndLoops)
{
  const auto map = std::make_shared<const OccupancyMap>();
  auto sampler = std::make_shared<CylindricalSectorSampler>();
  const std::vector<Viewpoint> centres = sampler->gridCellCentres();
  auto planner = makePlanner<PredefinedPlanner>(map, sampler);
  EXPECT_EQ(planner->name(), "predefined");
  InformationGain gain;
  gain.setConfig(GainConfig::paper()); // as makePlanner's
  gain.setInputMap(map);
  gain.setRoi(kBox);
  for (int pattern = 1; pattern <= 4; ++pattern) {
    planner->setPattern(pattern);
    planner->reset();
    const std::vector<int> order = PredefinedPlanner::patternOrder(pattern);
    for (int k = 0; k < 20; ++k) {
      NextViewResult result;
      planner->compute(result);
      const auto cell = static_cast<std::size_t>(order[static_cast<std::size_t>(k % 9)]);
      ASSERT_EQ(result.chosen, cell) << "pattern " << pattern << " step " << k;
      EXPECT_EQ(result.view.position, centres[cell].position);
      ASSERT_EQ(result.candidates.size(), 9u);
      EXPECT_EQ(result.gain, gain.compute(centres[cell]).gain);
      for (std::size_t i = 0; i < 9; ++i) {
        if (i != cell) {
          EXPECT_TRUE(std::isnan(result.candidates[i].gain.gain));
        }
      }
    }
  }
  EXPECT_THROW(planner->setPattern(5), InvalidArgumentError);
}

TEST(RandomPlanner, DeterministicBySeedAndPicksADrawnCandidate)
{
  const auto map = std::make_shared<const OccupancyMap>();
  auto sampler = std::make_shared<CylindricalSectorSampler>();
  auto a = makePlanner<RandomPlanner>(map, sampler);
  auto b = makePlanner<RandomPlanner>(map, sampler);
  EXPECT_EQ(a->name(), "random");
  a->setSeed(5);
  b->setSeed(5);
  // The planner's Rng: draw the candidates, then the index.
  Rng rng(5);
  std::set<std::size_t> chosen;
  for (int step = 0; step < 12; ++step) {
    NextViewResult ra, rb;
    a->compute(ra);
    b->compute(rb);
    std::vector<Viewpoint> drawn;
    sampler->sample(rng, drawn);
    const std::size_t index = static_cast<std::size_t>(rng.index(drawn.size()));
    ASSERT_EQ(ra.candidates.size(), 27u);
    EXPECT_EQ(ra.chosen, index);
    EXPECT_EQ(rb.chosen, ra.chosen);
    EXPECT_EQ(ra.view.position, drawn[index].position);
    EXPECT_EQ(ra.candidates[index].view.position, drawn[index].position);
    EXPECT_FALSE(std::isnan(ra.gain));
    EXPECT_EQ(ra.gain, ra.candidates[index].gain.gain);
    chosen.insert(ra.chosen);
  }
  EXPECT_GT(chosen.size(), 3u);
  NextViewResult rc;
  b->setSeed(6);
  b->compute(rc);
  a->setSeed(5);
  NextViewResult ra;
  a->compute(ra);
  EXPECT_NE(ra.view.position, rc.view.position);
}

TEST(ViewPlanner, MissingInputsThrow)
{
  const auto map = std::make_shared<const OccupancyMap>();
  const auto sampler = std::make_shared<CylindricalSectorSampler>();
  std::vector<std::unique_ptr<ViewPlanner>> planners;
  planners.push_back(std::make_unique<AttentionNbvPlanner>());
  planners.push_back(std::make_unique<PredefinedPlanner>());
  planners.push_back(std::make_unique<RandomPlanner>());
  for (auto& p : planners) {
    NextViewResult r;
    EXPECT_THROW(p->compute(r), InvalidArgumentError) << p->name();
    p->setInputMap(map);
    EXPECT_THROW(p->compute(r), InvalidArgumentError) << p->name();
    p->setCandidateSampler(sampler);
    EXPECT_NO_THROW(p->compute(r)) << p->name();
    EXPECT_THROW(p->setInputMap(nullptr), InvalidArgumentError);
    EXPECT_THROW(p->setCandidateSampler(nullptr), InvalidArgumentError);
    EXPECT_THROW(p->setNumberOfThreads(-2), InvalidArgumentError);
  }
  PredefinedPlanner predefined;
  predefined.setInputMap(map);
  predefined.setCandidateSampler(
      std::make_shared<FixedSampler>(std::vector<Viewpoint>{kAway}));
  NextViewResult r;
  EXPECT_THROW(predefined.compute(r), InvalidArgumentError);
  AttentionNbvPlanner nbv;
  nbv.setInputMap(map);
  nbv.setCandidateSampler(std::make_shared<FixedSampler>(std::vector<Viewpoint>{}));
  EXPECT_THROW(nbv.compute(r), InvalidArgumentError);
}
