// The ROI sources: the oracle passes its boxes on, noisy moves them by seeded errors.

#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/session/roi_source.h>

namespace plantnbv {
namespace {

Roi threeNodes()
{
  return Roi({Box({1.0, 0.0, 1.0}, {0.03, 0.03, 0.05}, "leaf_node_1"),
              Box({1.01, 0.02, 1.1}, {0.03, 0.03, 0.05}, "leaf_node_2"),
              Box({0.99, -0.01, 1.2}, {0.03, 0.03, 0.05}, "leaf_node_3")});
}

void expectSameBoxes(const Roi& a, const Roi& b)
{
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.boxes()[i].center, b.boxes()[i].center) << i;
    EXPECT_EQ(a.boxes()[i].size, b.boxes()[i].size) << i;
    EXPECT_EQ(a.boxes()[i].name, b.boxes()[i].name) << i;
  }
}

std::string messageOf(const RoiSource& source, const std::string& prefix = "")
{
  try {
    source.validate(prefix);
  } catch (const InvalidArgumentError& e) {
    return e.what();
  }
  return "";
}

TEST(RoiSource, NamesRoundTripAndAnUnknownOneIsRefusedNamingTheChoices)
{
  for (RoiSourceKind kind : {RoiSourceKind::oracle, RoiSourceKind::noisy})
    EXPECT_EQ(roiSourceKindFromName(roiSourceKindName(kind)), kind);
  try {
    roiSourceKindFromName("detector");
    FAIL() << "accepted";
  } catch (const InvalidArgumentError& e) {
    EXPECT_EQ(
        std::string(e.what()),
        "unknown ROI source 'detector' (expected oracle, noisy, detections, prior or "
        "detections+prior)");
  }
}

TEST(RoiSource, TheOracleAndNoisyWithSigmaZeroGiveTheBoxesExactly)
{
  const Roi given = threeNodes();
  expectSameBoxes(RoiSource().apply(given, 5), given);
  RoiSource noisy;
  noisy.kind = RoiSourceKind::noisy;
  for (std::uint64_t seed : {0u, 1u, 99u})
    expectSameBoxes(noisy.apply(given, seed), given);
  EXPECT_TRUE(noisy.apply(Roi(), 3).empty());
}

TEST(RoiSource, NoisyMovesEachBoxBySeededErrorsOfItsSigmaAndScalesItsSides)
{
  RoiSource noisy;
  noisy.kind = RoiSourceKind::noisy;
  noisy.sigma_m = 0.02;
  noisy.scale = 1.5;
  const Roi given = threeNodes();
  const Roi a = noisy.apply(given, 11);
  expectSameBoxes(noisy.apply(given, 11), a); // seeded
  const Roi other = noisy.apply(given, 12);
  ASSERT_EQ(a.size(), 3u);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.boxes()[i].name, given.boxes()[i].name);
    EXPECT_EQ(a.boxes()[i].size, given.boxes()[i].size * 1.5);
    EXPECT_NE(a.boxes()[i].center, given.boxes()[i].center);
    EXPECT_NE(a.boxes()[i].center, other.boxes()[i].center);
  }

  // Over many boxes the errors are N(0, sigma^2) on each axis, independent.
  Roi many;
  const int n = 4000;
  for (int i = 0; i < n; ++i)
    many.addBox(Box({1.0, 0.0, 1.0}, {0.03, 0.03, 0.05}));
  noisy.scale = 1.0;
  const Roi moved = noisy.apply(many, 7);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sum_sq = Eigen::Vector3d::Zero();
  double xy = 0.0;
  for (const Box& b : moved.boxes()) {
    const Eigen::Vector3d e = b.center - Eigen::Vector3d(1.0, 0.0, 1.0);
    sum += e;
    sum_sq += e.cwiseProduct(e);
    xy += e.x() * e.y();
  }
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(sum[axis] / n, 0.0, 4 * 0.02 / std::sqrt(double(n))) << axis;
    EXPECT_NEAR(std::sqrt(sum_sq[axis] / n), 0.02, 0.02 * 0.05) << axis;
  }
  EXPECT_NEAR(xy / n / (0.02 * 0.02), 0.0, 0.1); // uncorrelated
}

TEST(RoiSource, BadParametersAreRefusedNamingTheKeyOrTheOption)
{
  RoiSource s;
  s.kind = RoiSourceKind::noisy;
  s.sigma_m = -0.01;
  EXPECT_EQ(messageOf(s), "roi_sigma -0.01: expected a finite value >= 0 (metres)");
  EXPECT_EQ(messageOf(s, "--"),
            "--roi-sigma -0.01: expected a finite value >= 0 (metres)");
  s.sigma_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(messageOf(s).find("roi_sigma nan"), std::string::npos) << messageOf(s);
  s.sigma_m = 0.01;
  s.scale = 0.0;
  EXPECT_EQ(messageOf(s, "--"), "--roi-scale 0: expected a finite value > 0");
  s.scale = std::numeric_limits<double>::infinity();
  EXPECT_NE(messageOf(s).find("roi_scale inf"), std::string::npos);
  s.scale = 2.0;
  EXPECT_EQ(messageOf(s), "");

  // The oracle would ignore them: refused.
  RoiSource oracle;
  oracle.sigma_m = 0.01;
  EXPECT_EQ(
      messageOf(oracle, "--"),
      "--roi-sigma 0.01: only the noisy ROI source uses it (--roi-source is oracle)");
  oracle.sigma_m = 0.0;
  oracle.scale = 2.0;
  EXPECT_EQ(messageOf(oracle),
            "roi_scale 2: only the noisy ROI source uses it (roi_source is oracle)");
  EXPECT_THROW(oracle.apply(threeNodes(), 0), InvalidArgumentError);
}

} // namespace
} // namespace plantnbv
