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
  /// The points' coordinates, in data units; of equal length.
  ///@{
  std::vector<double> x, y;
  ///@}
  /// The band's lower and upper bounds: empty, or one value per x.
  ///@{
  std::vector<double> band_low, band_high;
  ///@}
  Rgb color; ///< of the line and its band (the band drawn translucent); see chartColor
  /// \brief A line's pattern (VTK's pen types), to tell curves apart without colour.
  enum class Line {
    solid,       ///< unbroken
    dashed,      ///< - - -
    dotted,      ///< . . .
    dash_dot,    ///< - . - .
    dash_dot_dot ///< - . . - . .
  };
  Line line = Line::solid; ///< the line's pattern, in the plot and the legend
  /// \brief A mark at each point (VTK's marker styles), also drawn in the legend.
  enum class Marker {
    none,    ///< the line alone
    circle,  ///< a filled circle
    square,  ///< a filled square
    diamond, ///< a filled diamond
    plus,    ///< +
    cross    ///< x
  };
  Marker marker = Marker::none; ///< the mark at each point
};

/// \brief One panel: its axes and curves. Axis ranges follow the data unless fixed.
struct ChartPanel {
  std::string title; ///< above the panel
  /// The axes' titles, with units, e.g. "views" and "Chamfer distance (mm)".
  ///@{
  std::string x_label, y_label;
  ///@}
  std::vector<ChartSeries> series; ///< the curves, drawn in order
  bool fixed_y = false; ///< true: the y axis spans [y_min, y_max]; false: the data's
  /// The y axis range when fixed_y; curves are clipped to it.
  ///@{
  double y_min = 0.0, y_max = 1.0;
  ///@}
  /// \brief true: the x axis has ticks at whole numbers only (integerTicks over the
  /// data's x range, e.g. view counts), and spans that range with a margin of 3% on
  /// either side, so that the first tick is the smallest x.
  bool integer_x = false;
};

/// \brief Tick positions at whole numbers from `min` to `max` (rounded inwards): `min`
/// itself, then the multiples of a step of 1, 2 or 5 times a power of ten, the smallest
/// that gives at most `max_ticks` ticks, that lie at least half a step above `min`.
/// E.g. (1, 10) gives 1, 2, ..., 10; (1, 30) gives 1, 5, 10, ..., 30; empty when no
/// whole number lies in [min, max].
/// \throws InvalidArgumentError when min or max is not finite, min > max, or max_ticks <
/// 2. Thread-safe.
std::vector<double> integerTicks(double min, double max, int max_ticks = 12);

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
  /// \brief The figure's title, above the panels.
  void setTitle(const std::string& title) { title_ = title; }
  /// \brief Picture size in pixels (default 1200 x 450).
  void setSize(int width, int height);
  /// \brief Panels per row (default 0: all in one row).
  void setColumns(int columns);
  /// \brief Appends a panel (the next cell of the grid).
  void addPanel(const ChartPanel& panel);
  /// \brief Whether the figure has a legend (default true): one box right of the
  /// panels, outside every plot, that names each named series once (those of the first
  /// panel first, then names new in later panels) with the colour, line and marker it
  /// first has. The panels are narrowed to make room for it.
  void setShowLegend(bool show) { show_legend_ = show; }

  /// \brief The panels, in the order added.
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
  bool show_legend_ = true;
  std::vector<ChartPanel> panels_;
};

} // namespace viz
} // namespace plantnbv
