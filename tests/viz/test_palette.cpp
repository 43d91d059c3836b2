#include <cmath>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/viz/palette.h>

using plantnbv::PartLabel;
using plantnbv::viz::Rgb;

namespace {

double distance(const Rgb& a, const Rgb& b)
{
  return std::sqrt((a.r - b.r) * (a.r - b.r) + (a.g - b.g) * (a.g - b.g) +
                   (a.b - b.b) * (a.b - b.b));
}

} // namespace

TEST(Palette, PartColoursAreDistinctAndAsDocumented)
{
  std::vector<Rgb> parts;
  for (unsigned i = 0; i <= unsigned(plantnbv::kLastPartLabel); ++i)
    parts.push_back(plantnbv::viz::partLabelColor(static_cast<PartLabel>(i)));
  for (std::size_t i = 0; i < parts.size(); ++i)
    for (std::size_t j = i + 1; j < parts.size(); ++j)
      EXPECT_GT(distance(parts[i], parts[j]), 0.15) << i << " vs " << j;
  const Rgb leaflet = plantnbv::viz::partLabelColor(PartLabel::leaflet);
  EXPECT_GT(leaflet.g, leaflet.r);
  EXPECT_GT(leaflet.g, leaflet.b);
  const Rgb fruit = plantnbv::viz::partLabelColor(PartLabel::fruit);
  EXPECT_GT(fruit.r, fruit.g + 0.5f);
  EXPECT_THROW(plantnbv::viz::partLabelColor(static_cast<PartLabel>(8)),
               plantnbv::InvalidArgumentError);

  // ROI colours stand apart from every part colour and from each other, and repeat.
  for (std::size_t i = 0; i < 8; ++i) {
    for (const Rgb& part : parts)
      EXPECT_GT(distance(plantnbv::viz::distinctColor(i), part), 0.25) << i;
    for (std::size_t j = i + 1; j < 8; ++j)
      EXPECT_GT(
          distance(plantnbv::viz::distinctColor(i), plantnbv::viz::distinctColor(j)),
          0.25);
    EXPECT_EQ(
        distance(plantnbv::viz::distinctColor(i), plantnbv::viz::distinctColor(i + 8)),
        0.0);
  }
}

TEST(Palette, ChartColoursAreOkabeAndItos)
{
  // Okabe & Ito (2008): black, orange, sky blue, bluish green, yellow, blue, vermillion,
  // reddish purple, as 8-bit sRGB.
  const int expected[8][3] = {{0, 0, 0},     {230, 159, 0},  {86, 180, 233},
                              {0, 158, 115}, {240, 228, 66}, {0, 114, 178},
                              {213, 94, 0},  {204, 121, 167}};
  for (std::size_t i = 0; i < 8; ++i) {
    const Rgb c = plantnbv::viz::chartColor(i);
    EXPECT_EQ(std::lround(c.r * 255), expected[i][0]) << i;
    EXPECT_EQ(std::lround(c.g * 255), expected[i][1]) << i;
    EXPECT_EQ(std::lround(c.b * 255), expected[i][2]) << i;
    EXPECT_EQ(distance(c, plantnbv::viz::chartColor(i + 8)), 0.0) << i; // repeating
  }
}
