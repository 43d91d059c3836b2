#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/viz/line_chart.h>

#include "viz_test_util.h"

using plantnbv::test::countNear;
using plantnbv::viz::ChartPanel;
using plantnbv::viz::ChartSeries;
using plantnbv::viz::distinctColor;
using plantnbv::viz::integerTicks;
using plantnbv::viz::LineChartFigure;
using plantnbv::viz::Rgb;
using plantnbv::viz::RgbImage;

namespace {

ChartSeries rising(std::size_t color, double offset)
{
  ChartSeries s;
  s.name = "series " + std::to_string(color);
  s.color = distinctColor(color);
  for (int v = 1; v <= 10; ++v) {
    s.x.push_back(v);
    s.y.push_back(offset + 0.05 * v);
    s.band_low.push_back(offset + 0.05 * v - 0.04);
    s.band_high.push_back(offset + 0.05 * v + 0.04);
  }
  return s;
}

ChartPanel panel(const std::string& title)
{
  ChartPanel p;
  p.title = title;
  p.x_label = "views";
  p.y_label = "F1 score";
  p.fixed_y = true;
  p.series = {rising(0, 0.1), rising(1, 0.4)};
  return p;
}

} // namespace

TEST(LineChartFigure, PanelsGiveAnImageOfTheSizeWithEachSeriesInItsColour)
{
  LineChartFigure figure;
  figure.setTitle("Two panels");
  figure.setSize(900, 400);
  figure.addPanel(panel("left"));
  figure.addPanel(panel("right"));
  const RgbImage image = figure.renderImage();
  ASSERT_EQ(image.width, 900);
  ASSERT_EQ(image.height, 400);
  // Both lines are drawn in both panels (2.5 px wide, over most of the panel's width).
  for (std::size_t c : {0u, 1u}) {
    const std::size_t n = countNear(image, distinctColor(c), 12);
    EXPECT_GT(n, 2u * 300u) << "series " << c;
  }
  // White background: most of the picture.
  EXPECT_GT(countNear(image, {1.0f, 1.0f, 1.0f}, 0), image.rgb.size() / 3 / 2);
}

TEST(LineChartFigure, WritesAPng)
{
  const std::string path = std::string(PLANTNBV_BINARY_DIR) + "/tests/viz_line_chart.png";
  LineChartFigure figure;
  figure.setColumns(1);
  figure.setSize(600, 700);
  figure.addPanel(panel("top"));
  figure.addPanel(panel("bottom"));
  figure.render(path);
  const RgbImage image = plantnbv::test::readPng(path);
  EXPECT_EQ(image.width, 600);
  EXPECT_EQ(image.height, 700);
}

TEST(LineChartFigure, BadInputIsRefused)
{
  LineChartFigure figure;
  EXPECT_THROW(figure.renderImage(), plantnbv::InvalidArgumentError); // no panel
  EXPECT_THROW(figure.setSize(50, 400), plantnbv::InvalidArgumentError);
  EXPECT_THROW(figure.setColumns(-1), plantnbv::InvalidArgumentError);
  ChartPanel p = panel("short band");
  p.series[0].band_high.pop_back();
  EXPECT_THROW(figure.addPanel(p), plantnbv::InvalidArgumentError);
  p = panel("short y");
  p.series[1].y.pop_back();
  EXPECT_THROW(figure.addPanel(p), plantnbv::InvalidArgumentError);
  EXPECT_TRUE(figure.panels().empty());
}

TEST(LineChartFigure, IntegerTicksStartAtTheFirstWholeNumberWithARoundStep)
{
  using V = std::vector<double>;
  EXPECT_EQ(integerTicks(1, 10), (V{1, 2, 3, 4, 5, 6, 7, 8, 9, 10}));
  // 20 whole numbers: a step of 2, and 1 first.
  EXPECT_EQ(integerTicks(1, 20), (V{1, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20}));
  EXPECT_EQ(integerTicks(1, 30), (V{1, 5, 10, 15, 20, 25, 30}));
  // 3 is within half a step (of 5) of 1: left out, so that labels do not crowd.
  EXPECT_EQ(integerTicks(1, 12, 3), (V{1, 5, 10}));
  EXPECT_EQ(integerTicks(0, 1000),
            (V{0, 100, 200, 300, 400, 500, 600, 700, 800, 900, 1000}));
  EXPECT_EQ(integerTicks(0.5, 3.7), (V{1, 2, 3}));      // rounded inwards
  EXPECT_EQ(integerTicks(-2, 2), (V{-2, -1, 0, 1, 2})); // below zero too
  EXPECT_EQ(integerTicks(4, 4), (V{4}));
  EXPECT_TRUE(integerTicks(1.2, 1.8).empty()); // no whole number in between
  EXPECT_THROW(integerTicks(2, 1), plantnbv::InvalidArgumentError);
  EXPECT_THROW(integerTicks(1, std::numeric_limits<double>::infinity()),
               plantnbv::InvalidArgumentError);
  EXPECT_THROW(integerTicks(std::nan(""), 1), plantnbv::InvalidArgumentError);
  EXPECT_THROW(integerTicks(1, 10, 1), plantnbv::InvalidArgumentError);
}

TEST(LineChartFigure, TheLegendStandsRightOfThePanelsOutsideTheData)
{
  // A band over the whole y range and every x: a legend inside the plot would leave a
  // white box in it.
  const Rgb blue = plantnbv::viz::chartColor(5);
  ChartSeries s;
  s.name = "a planner with a long name";
  s.color = blue;
  for (int v = 1; v <= 10; ++v) {
    s.x.push_back(v);
    s.y.push_back(0.5);
    s.band_low.push_back(0.0);
    s.band_high.push_back(1.0);
  }
  ChartPanel p = panel("full band");
  p.series = {s};
  p.integer_x = true;
  LineChartFigure figure;
  figure.setSize(800, 400);
  figure.addPanel(p);
  const RgbImage image = figure.renderImage();
  // The band's tint (alpha 50 of 255 over white), and the box around it.
  const float a = 50.0f / 255.0f;
  const Rgb tint{1 - a + a * blue.r, 1 - a + a * blue.g, 1 - a + a * blue.b};
  const auto near = [&image](int x, int y, const Rgb& c, int tolerance) {
    const int want[3] = {int(c.r * 255 + 0.5f), int(c.g * 255 + 0.5f),
                         int(c.b * 255 + 0.5f)};
    for (int k = 0; k < 3; ++k)
      if (std::abs(int(image.at(x, y)[k]) - want[k]) > tolerance)
        return false;
    return true;
  };
  int x0 = image.width, x1 = -1, y0 = image.height, y1 = -1;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      if (near(x, y, tint, 3)) {
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
      }
  ASSERT_GT(x1 - x0, 300) << "no band drawn";
  ASSERT_GT(y1 - y0, 200) << "no band drawn";
  std::size_t white_inside = 0;
  for (int y = y0 + 3; y <= y1 - 3; ++y)
    for (int x = x0 + 3; x <= x1 - 3; ++x)
      white_inside += near(x, y, {1.0f, 1.0f, 1.0f}, 0);
  EXPECT_EQ(white_inside, 0u) << "something white covers the band";
  // The legend's line right of the band, within the picture.
  std::size_t legend_line = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = x1 + 10; x < image.width; ++x)
      legend_line += near(x, y, blue, 12);
  EXPECT_GT(legend_line, 40u);
  // Without a legend the panel takes the width: the band reaches further right.
  figure.setShowLegend(false);
  const RgbImage wide = figure.renderImage();
  int wide_x1 = -1;
  for (int y = 0; y < wide.height; ++y)
    for (int x = 0; x < wide.width; ++x)
      if (std::abs(int(wide.at(x, y)[0]) - int(tint.r * 255 + 0.5f)) <= 3 &&
          std::abs(int(wide.at(x, y)[1]) - int(tint.g * 255 + 0.5f)) <= 3 &&
          std::abs(int(wide.at(x, y)[2]) - int(tint.b * 255 + 0.5f)) <= 3)
        wide_x1 = std::max(wide_x1, x);
  EXPECT_GT(wide_x1, x1 + 100);
}

TEST(LineChartFigure, LinePatternsAndMarkersAreDrawn)
{
  // One line without a band or legend, counted in its colour: dashes leave gaps, markers
  // add area.
  const Rgb green = plantnbv::viz::chartColor(3);
  const auto pixels = [&green](ChartSeries::Line line, ChartSeries::Marker marker) {
    ChartSeries s = rising(0, 0.2);
    s.color = green;
    s.band_low.clear();
    s.band_high.clear();
    s.line = line;
    s.marker = marker;
    ChartPanel p = panel("one line");
    p.series = {s};
    LineChartFigure figure;
    figure.setSize(600, 400);
    figure.setShowLegend(false);
    figure.addPanel(p);
    return countNear(figure.renderImage(), green, 12);
  };
  const std::size_t solid = pixels(ChartSeries::Line::solid, ChartSeries::Marker::none);
  const std::size_t dashed = pixels(ChartSeries::Line::dashed, ChartSeries::Marker::none);
  const std::size_t marked =
      pixels(ChartSeries::Line::solid, ChartSeries::Marker::square);
  EXPECT_GT(solid, 300u);
  EXPECT_LT(dashed, solid * 9 / 10);
  EXPECT_GT(dashed, solid / 4);
  EXPECT_GT(marked, solid + 10 * 20); // 10 squares of several pixels each
}
