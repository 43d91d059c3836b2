#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <octomap/OcTree.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/camera/optical_frame.h>
#include <plantnbv/common/error.h>
#include <plantnbv/session/active_vision_session.h>

#include "octree_leaves.h"

namespace plantnbv {
namespace {

/// A small camera, so that the tests stay fast.
CameraIntrinsics smallCamera()
{
  return CameraIntrinsics::custom(64, 48, 45.7, 45.7, 31.5, 23.5);
}

/// The paper's v0 (body frame), looking at the stem from 0.4 m.
Viewpoint v0()
{
  return Pose::fromXyzQuat(0.646, 0.353, 1.383, 0.0, 0.0, -0.383, 0.924);
}

/// A frame of a flat board `distance_m` in front of the camera (constant depth).
DepthImage board(const CameraIntrinsics& K, float distance_m)
{
  DepthImage depth;
  depth.width = K.width;
  depth.height = K.height;
  depth.depth_m.assign(K.pixelCount(), distance_m);
  return depth;
}

TEST(ActiveVisionSession, ADepthFrameGivesTheMapOfItsBackProjectedCloud)
{
  const CameraIntrinsics K = smallCamera();
  const Pose T_W_O = opticalFrame(v0());
  const DepthImage depth = board(K, 0.4f);

  ActiveVisionSession from_depth;
  from_depth.integrate(depth, K, T_W_O);
  CloudXYZ cloud;
  depthToCloud(depth, K, T_W_O, cloud);
  ActiveVisionSession from_cloud;
  from_cloud.integrate(cloud, T_W_O.position);

  EXPECT_GT(from_depth.getMap()->countVoxels().occupied, 0u);
  EXPECT_EQ(test::octreeLeaves(*from_depth.getMap()),
            test::octreeLeaves(*from_cloud.getMap()));
  // A pixel's point is occupied, the voxel half-way there is free.
  const Eigen::Vector3d point = cloud.at(10, 20).getVector3fMap().cast<double>();
  EXPECT_EQ(from_depth.getMap()->state(point), VoxelState::occupied);
  EXPECT_EQ(from_depth.getMap()->state((point + T_W_O.position) / 2), VoxelState::free);
  // Both record where the frame was taken from, for the planner's view spacing, and a
  // new planner takes the record over.
  for (ActiveVisionSession* s : {&from_depth, &from_cloud})
    EXPECT_EQ(s->getPlanner().getVisitedPositions(),
              std::vector<Eigen::Vector3d>{T_W_O.position});
  from_depth.setPlanner(std::make_shared<AttentionNbvPlanner>());
  EXPECT_EQ(from_depth.getPlanner().getVisitedPositions().size(), 1u);
}

TEST(ActiveVisionSession, AMapThatHoldsAFrameLeavesTheSessionAsIntegratingIt)
{
  const CameraIntrinsics K = smallCamera();
  const Pose T_W_O = opticalFrame(v0());
  ActiveVisionSession integrated;
  integrated.integrate(board(K, 0.4f), K, T_W_O);
  // The same frame's map, made elsewhere (e.g. kept from another trial).
  auto copy = std::make_shared<OccupancyMap>(ActiveVisionSession::Config().map);
  CloudXYZ scratch;
  integrateDepthFrame(*copy, board(K, 0.4f), K, T_W_O, scratch);
  ActiveVisionSession adopted;
  adopted.setMapWithFrame(copy, T_W_O.position);
  EXPECT_EQ(adopted.getMap(), copy);
  EXPECT_EQ(adopted.getPlanner().getVisitedPositions(),
            integrated.getPlanner().getVisitedPositions());
  NextBestView a, b;
  integrated.nextBestView(a);
  adopted.nextBestView(b);
  EXPECT_EQ(a.result.chosen, b.result.chosen);
  EXPECT_EQ(a.result.gain, b.result.gain);
  EXPECT_THROW(adopted.setMapWithFrame(nullptr, T_W_O.position), InvalidArgumentError);
}

TEST(ActiveVisionSession, RanksTheCandidatesChosenFirstThenByGain)
{
  ActiveVisionSession session;
  session.setCamera(smallCamera());
  session.integrate(board(smallCamera(), 0.45f), smallCamera(), opticalFrame(v0()));
  NextBestView next;
  session.nextBestView(next);
  ASSERT_EQ(next.result.candidates.size(), 27u);
  ASSERT_EQ(next.ranking.size(), 27u);
  EXPECT_EQ(next.ranking[0].index, next.result.chosen);
  for (std::size_t i = 1; i < next.ranking.size(); ++i)
    EXPECT_GE(next.ranking[i - 1].gain.gain, next.ranking[i].gain.gain) << i;
  for (const RankedView& r : next.ranking) {
    const CandidateView& c = next.result.candidates[r.index];
    EXPECT_EQ(r.viewpoint.position, c.view.position);
    EXPECT_EQ(r.gain.gain, c.gain.gain);
    const Pose expected = opticalFrame(c.view);
    EXPECT_EQ(r.optical_pose.position, expected.position);
    EXPECT_EQ(r.optical_pose.orientation.coeffs(), expected.orientation.coeffs());
  }
  EXPECT_GT(next.ranking[0].gain.gain, 0.0);
}

TEST(ActiveVisionSession, RankingPutsCandidatesWithoutGainLast)
{
  NextViewResult result;
  result.candidates.resize(4);
  const double gains[] = {1.0, std::numeric_limits<double>::quiet_NaN(), 3.0, 2.0};
  for (int i = 0; i < 4; ++i)
    result.candidates[std::size_t(i)].gain.gain = gains[i];
  result.chosen = 3;
  std::vector<std::size_t> order;
  for (const RankedView& r : rankCandidates(result))
    order.push_back(r.index);
  EXPECT_EQ(order, (std::vector<std::size_t>{3, 2, 0, 1}));
}

TEST(ActiveVisionSession, TheRoiCanChangeBetweenSteps)
{
  ActiveVisionSession session;
  session.setCamera(smallCamera());
  NextBestView everything;
  session.nextBestView(everything);
  // An ROI far from the sector: no candidate sees it.
  session.setRoi(
      Roi({Box(Eigen::Vector3d(5.0, 5.0, 5.0), Eigen::Vector3d(0.1, 0.1, 0.1))}));
  NextBestView nothing;
  session.nextBestView(nothing);
  EXPECT_GT(everything.ranking[0].gain.gain, 0.0);
  for (const RankedView& r : nothing.ranking)
    EXPECT_EQ(r.gain.gain, 0.0);
  EXPECT_EQ(nothing.result.chosen, 0u); // all equal: the first candidate
}

TEST(ActiveVisionSession, SameSeedSameViews)
{
  ActiveVisionSession::Config config;
  config.seed = 7;
  ActiveVisionSession a(config), b(config);
  a.setCamera(smallCamera());
  b.setCamera(smallCamera());
  NextBestView na, nb;
  a.nextBestView(na);
  b.nextBestView(nb);
  ASSERT_EQ(na.ranking.size(), nb.ranking.size());
  for (std::size_t i = 0; i < na.ranking.size(); ++i)
    EXPECT_EQ(na.ranking[i].viewpoint.position, nb.ranking[i].viewpoint.position);
}

TEST(ActiveVisionSession, AMapWrittenAsOtReadsBackWithItsLogOdds)
{
  const std::string ot = ::testing::TempDir() + "session_map.ot";
  const std::string bt = ::testing::TempDir() + "session_map.bt";
  ActiveVisionSession session;
  session.integrate(board(smallCamera(), 0.4f), smallCamera(), opticalFrame(v0()));
  session.writeMap(ot);
  session.writeMap(bt);
  ActiveVisionSession loaded;
  EXPECT_TRUE(loaded.readMap(ot));
  EXPECT_EQ(test::octreeLeaves(*loaded.getMap()), test::octreeLeaves(*session.getMap()));
  EXPECT_FALSE(loaded.readMap(bt)); // maximum likelihood
  EXPECT_EQ(loaded.getMap()->countVoxels().occupied,
            session.getMap()->countVoxels().occupied);
  // The planner plans on the map it was given.
  NextBestView next;
  loaded.nextBestView(next);
  EXPECT_EQ(next.result.candidates.size(), 27u);
  std::remove(ot.c_str());
  std::remove(bt.c_str());
}

TEST(ActiveVisionSession, RefusesBadInput)
{
  ActiveVisionSession::Config config;
  config.grid_rows = 0;
  EXPECT_THROW(ActiveVisionSession{config}, InvalidArgumentError);
  ActiveVisionSession session;
  EXPECT_THROW(session.setPlanner(nullptr), InvalidArgumentError);
  EXPECT_THROW(session.setMap(nullptr), InvalidArgumentError);
  EXPECT_THROW(session.integrate(board(smallCamera(), 0.4f),
                                 CameraIntrinsics::l515(L515Mode::vga_640x480), Pose()),
               InvalidArgumentError);
}

} // namespace
} // namespace plantnbv
