#include <cmath>

#include <gtest/gtest.h>

#include <plantnbv/common/portable_math.h>

using plantnbv::portableCos;
using plantnbv::portableSin;

TEST(PortableMath, MatchesTheCLibraryToTheLastBits)
{
  // Every quadrant and the angles the generator uses (up to tens of radians).
  double worst = 0.0;
  for (int i = -20000; i <= 20000; ++i) {
    const double x = i * 0.0031 + 1e-4 * (i % 7);
    worst = std::max(worst, std::abs(portableSin(x) - std::sin(x)));
    worst = std::max(worst, std::abs(portableCos(x) - std::cos(x)));
  }
  EXPECT_LT(worst, 5e-16);
}

TEST(PortableMath, ExactValuesAndSymmetry)
{
  EXPECT_EQ(portableSin(0.0), 0.0);
  EXPECT_EQ(portableCos(0.0), 1.0);
  EXPECT_NEAR(portableSin(M_PI / 2), 1.0, 1e-16);
  EXPECT_NEAR(portableCos(M_PI), -1.0, 1e-16);
  EXPECT_NEAR(portableSin(-M_PI / 2), -1.0, 1e-16);
  for (double x : {0.3, 1.7, 2.9, 4.4, 7.5, 33.3})
    EXPECT_EQ(portableSin(-x), -portableSin(x)) << x;
  for (double x : {0.3, 1.7, 2.9, 4.4, 7.5, 33.3})
    EXPECT_EQ(portableCos(-x), portableCos(x)) << x;
}

TEST(PortableMath, NonFiniteGivesNaN)
{
  EXPECT_TRUE(std::isnan(portableSin(INFINITY)));
  EXPECT_TRUE(std::isnan(portableCos(-INFINITY)));
  EXPECT_TRUE(std::isnan(portableSin(NAN)));
}
