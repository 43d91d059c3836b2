// Statistics over trials: Student's t quantiles, mean / sd / CI, median.

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/statistics.h>

using namespace plantnbv;

TEST(Statistics, StudentTQuantilesMatchTheTables)
{
  // Two-sided 95% (p = 0.975), from the standard tables.
  EXPECT_NEAR(studentTQuantile(0.975, 1), 12.706204736, 1e-8);
  EXPECT_NEAR(studentTQuantile(0.975, 2), 4.302652730, 1e-8);
  EXPECT_NEAR(studentTQuantile(0.975, 9), 2.262157163, 1e-8);
  EXPECT_NEAR(studentTQuantile(0.975, 29), 2.045229642, 1e-8);
  EXPECT_NEAR(studentTQuantile(0.975, 119), 1.980099876, 1e-8);
  EXPECT_NEAR(studentTQuantile(0.975, 1e7), 1.959963985, 1e-6); // the normal limit
  EXPECT_NEAR(studentTQuantile(0.95, 4), 2.131846786, 1e-8);
  EXPECT_NEAR(studentTQuantile(0.995, 5), 4.032142984, 1e-8);
  // 1 dof is Cauchy: tan(pi (p - 1/2)).
  EXPECT_NEAR(studentTQuantile(0.9, 1), std::tan(M_PI * 0.4), 1e-9);
  EXPECT_DOUBLE_EQ(studentTQuantile(0.5, 3), 0.0);
  EXPECT_NEAR(studentTQuantile(0.025, 9), -studentTQuantile(0.975, 9), 1e-12);
  EXPECT_THROW(studentTQuantile(1.0, 3), InvalidArgumentError);
  EXPECT_THROW(studentTQuantile(0.975, 0), InvalidArgumentError);
}

TEST(Statistics, SummaryOfHandComputedValues)
{
  // 2, 4, 6: mean 4, sd 2, CI 4 -+ t(0.975, 2) * 2 / sqrt(3).
  const SampleSummary s = summarize({2.0, 4.0, 6.0});
  EXPECT_EQ(s.n, 3u);
  EXPECT_DOUBLE_EQ(s.mean, 4.0);
  EXPECT_DOUBLE_EQ(s.sd, 2.0);
  const double half = 4.302652729749464 * 2.0 / std::sqrt(3.0);
  EXPECT_NEAR(s.ci_low, 4.0 - half, 1e-9);
  EXPECT_NEAR(s.ci_high, 4.0 + half, 1e-9);

  // NaN values are left out; one value has no spread.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const SampleSummary one = summarize({nan, 0.5});
  EXPECT_EQ(one.n, 1u);
  EXPECT_DOUBLE_EQ(one.mean, 0.5);
  EXPECT_TRUE(std::isnan(one.sd));
  EXPECT_TRUE(std::isnan(one.ci_low));
  const SampleSummary none = summarize({});
  EXPECT_EQ(none.n, 0u);
  EXPECT_TRUE(std::isnan(none.mean));
}

TEST(Statistics, MedianHandlesEvenCountsAndNever)
{
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_DOUBLE_EQ(median({3, 1, 2}), 2.0);
  EXPECT_DOUBLE_EQ(median({4, 1, 3, 2}), 2.5);
  EXPECT_DOUBLE_EQ(median({3, inf, 5}), 5.0);
  EXPECT_TRUE(std::isinf(median({3, inf})));
  EXPECT_TRUE(std::isnan(median({})));
}
