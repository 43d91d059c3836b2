#include <string>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/viz/line_chart.h>

#include "viz_test_util.h"

using plantnbv::test::countNear;
using plantnbv::viz::ChartPanel;
using plantnbv::viz::ChartSeries;
using plantnbv::viz::distinctColor;
using plantnbv::viz::LineChartFigure;
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
