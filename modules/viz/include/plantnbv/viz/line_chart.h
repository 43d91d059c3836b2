#pragma once
/// \file line_chart.h
/// \brief Figures of curves: panels of line charts with shaded bands (e.g. a mean and its
/// 95% confidence interval per view), laid out in a grid with one title and rendered by
/// VTK's charts offscreen into a PNG. Rendering needs an X server, as for snapshots
/// (display.h).

#include <string>
#include <vector>

#include <plantnbv/viz/palette.h>
#include <plantnbv/viz/snapshot.h>

namespace plantnbv {
namespace viz {

/// \brief One curve: points (x[i], y[i]) joined by a line, and, when `band_low` and
/// `band_high` are given, the band between them shaded in the same colour. Non-finite
/// values leave a point out (a band point needs both of its bounds).
struct ChartSeries {
  std::string name; ///< the legend's entry
  std::vector<double> x, y;
  std::vector<double> band_low, band_high; ///< empty, or one value per x
  Rgb color;
  bool dashed = false; ///< e.g. to tell a baseline apart where colours repeat
};

/// \brief One panel: its axes and curves. Axis ranges follow the data unless fixed.
struct ChartPanel {
  std::string title;
  std::string x_label, y_label; ///< with units, e.g. "views" and "Chamfer distance (mm)"
  std::vector<ChartSeries> series;
  bool fixed_y = false;
  double y_min = 0.0, y_max = 1.0; ///< used when fixed_y; curves are clipped to it
  /// Where the legend goes inside the plot: the corner the curves leave empty.
  enum class LegendCorner { bottom_right, top_right, none };
  LegendCorner legend = LegendCorner::bottom_right;
};

/// \brief A figure of panels in a grid, filled row by row.
///
/// \code
/// viz::LineChartFigure figure;
/// figure.setTitle("F1 score vs views (mean, 95% CI)");
/// figure.setSize(1200, 420);
/// figure.addPanel(panel); // one per evaluation level
/// figure.render("f1_main.png");
/// \endcode
class LineChartFigure {
public:
  void setTitle(const std::string& title) { title_ = title; }
  /// \brief Picture size in pixels (default 1200 x 450).
  void setSize(int width, int height);
  /// \brief Panels per row (default 0: all in one row).
  void setColumns(int columns);
  void addPanel(const ChartPanel& panel);

  const std::vector<ChartPanel>& panels() const { return panels_; }

  /// \brief Renders the figure offscreen.
  /// \throws InvalidArgumentError without panels or with a series whose vectors differ in
  /// length; Error when there is no X display (display.h) or VTK fails.
  RgbImage renderImage() const;
  /// \brief renderImage(), written as a PNG (writePng).
  void render(const std::string& png_path) const;

private:
  std::string title_;
  int width_ = 1200;
  int height_ = 450;
  int columns_ = 0;
  std::vector<ChartPanel> panels_;
};

} // namespace viz
} // namespace plantnbv
