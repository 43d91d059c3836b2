#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartMatrix.h>
#include <vtkChartXY.h>
#include <vtkContextActor.h>
#include <vtkContextScene.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkPlotArea.h>
#include <vtkPlotPoints.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkTextRenderer.h>
#include <vtkVector.h>

#include <plantnbv/common/error.h>
#include <plantnbv/viz/line_chart.h>

#include "window_image.h"
#include "x_display.h"

namespace plantnbv {
namespace viz {

namespace {

unsigned char byte(float c)
{
  return static_cast<unsigned char>(std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f));
}

vtkSmartPointer<vtkDoubleArray> column(const char* name)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  return a;
}

void checkSeries(const ChartSeries& s)
{
  const std::size_t n = s.x.size();
  const bool band = !s.band_low.empty() || !s.band_high.empty();
  if (s.y.size() != n || (band && (s.band_low.size() != n || s.band_high.size() != n)))
    throw InvalidArgumentError("chart series '" + s.name +
                               "': x, y and the band bounds differ in length");
}

int penType(ChartSeries::Line line)
{
  switch (line) {
  case ChartSeries::Line::dashed:
    return vtkPen::DASH_LINE;
  case ChartSeries::Line::dotted:
    return vtkPen::DOT_LINE;
  case ChartSeries::Line::dash_dot:
    return vtkPen::DASH_DOT_LINE;
  case ChartSeries::Line::dash_dot_dot:
    return vtkPen::DASH_DOT_DOT_LINE;
  case ChartSeries::Line::solid:
    break;
  }
  return vtkPen::SOLID_LINE;
}

int markerStyle(ChartSeries::Marker marker)
{
  switch (marker) {
  case ChartSeries::Marker::circle:
    return vtkPlotPoints::CIRCLE;
  case ChartSeries::Marker::square:
    return vtkPlotPoints::SQUARE;
  case ChartSeries::Marker::diamond:
    return vtkPlotPoints::DIAMOND;
  case ChartSeries::Marker::plus:
    return vtkPlotPoints::PLUS;
  case ChartSeries::Marker::cross:
    return vtkPlotPoints::CROSS;
  case ChartSeries::Marker::none:
    break;
  }
  return vtkPlotPoints::NONE;
}

/// A line plot of `chart` in the colour, pattern and marker of `s`, labelled by its name.
vtkPlot* addStyledLine(vtkChartXY* chart, const ChartSeries& s)
{
  vtkPlot* line = chart->AddPlot(vtkChart::LINE);
  line->SetColor(byte(s.color.r), byte(s.color.g), byte(s.color.b), 255);
  line->SetWidth(2.5f);
  line->SetLabel(s.name);
  line->GetPen()->SetLineType(penType(s.line));
  if (auto* points = vtkPlotPoints::SafeDownCast(line)) {
    points->SetMarkerStyle(markerStyle(s.marker));
    points->SetMarkerSize(9.0f);
  }
  return line;
}

/// The line of `s`, and its band (legend-less, translucent) drawn first beneath it.
void addSeries(vtkChartXY* chart, const ChartSeries& s)
{
  const unsigned char r = byte(s.color.r), g = byte(s.color.g), b = byte(s.color.b);
  if (!s.band_low.empty()) {
    vtkNew<vtkTable> table;
    auto x = column("x"), low = column("low"), high = column("high");
    for (std::size_t i = 0; i < s.x.size(); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.band_low[i]) &&
          std::isfinite(s.band_high[i])) {
        x->InsertNextValue(s.x[i]);
        low->InsertNextValue(s.band_low[i]);
        high->InsertNextValue(s.band_high[i]);
      }
    table->AddColumn(x);
    table->AddColumn(low);
    table->AddColumn(high);
    if (table->GetNumberOfRows() > 1) {
      auto* area = vtkPlotArea::SafeDownCast(chart->AddPlot(vtkChart::AREA));
      area->SetInputData(table);
      area->SetInputArray(0, "x");
      area->SetInputArray(1, "low");
      area->SetInputArray(2, "high");
      area->SetColor(r, g, b, 50);
      area->SetLegendVisibility(false);
    }
  }
  vtkNew<vtkTable> table;
  auto x = column("x"), y = column("y");
  for (std::size_t i = 0; i < s.x.size(); ++i)
    if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) {
      x->InsertNextValue(s.x[i]);
      y->InsertNextValue(s.y[i]);
    }
  table->AddColumn(x);
  table->AddColumn(y);
  addStyledLine(chart, s)->SetInputData(table, 0, 1);
}

/// Whole-number ticks over the panel's x range, which the axis spans with a margin.
void setIntegerTicks(vtkAxis* axis, const ChartPanel& p)
{
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const ChartSeries& s : p.series)
    for (double x : s.x)
      if (std::isfinite(x)) {
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
  if (!(lo <= hi))
    return;
  const std::vector<double> ticks = integerTicks(lo, hi);
  if (ticks.empty())
    return;
  vtkNew<vtkDoubleArray> positions;
  vtkNew<vtkStringArray> labels;
  for (double t : ticks) {
    positions->InsertNextValue(t);
    labels->InsertNextValue(std::to_string(std::llround(t)));
  }
  const double margin = 0.03 * std::max(hi - lo, 1.0);
  axis->SetBehavior(vtkAxis::FIXED);
  axis->SetRange(lo - margin, hi + margin);
  axis->SetCustomTickPositions(positions, labels);
}

void styleAxis(vtkAxis* axis, const std::string& title)
{
  axis->SetTitle(title);
  axis->GetTitleProperties()->SetFontSize(15);
  axis->GetTitleProperties()->BoldOff();
  axis->GetLabelProperties()->SetFontSize(13);
}

void fillPanel(vtkChartXY* chart, const ChartPanel& p)
{
  chart->SetTitle(p.title);
  chart->GetTitleProperties()->SetFontSize(17);
  chart->GetTitleProperties()->BoldOn();
  for (const ChartSeries& s : p.series)
    addSeries(chart, s);
  styleAxis(chart->GetAxis(vtkAxis::BOTTOM), p.x_label);
  styleAxis(chart->GetAxis(vtkAxis::LEFT), p.y_label);
  if (p.fixed_y) {
    chart->GetAxis(vtkAxis::LEFT)->SetBehavior(vtkAxis::FIXED);
    chart->GetAxis(vtkAxis::LEFT)->SetRange(p.y_min, p.y_max);
  }
  if (p.integer_x)
    setIntegerTicks(chart->GetAxis(vtkAxis::BOTTOM), p);
  chart->SetShowLegend(false); // the figure's legend stands outside the panels
}

/// Each named series once, as first seen panel by panel.
std::vector<const ChartSeries*> legendEntries(const std::vector<ChartPanel>& panels)
{
  std::vector<const ChartSeries*> entries;
  for (const ChartPanel& p : panels)
    for (const ChartSeries& s : p.series)
      if (!s.name.empty() &&
          std::none_of(entries.begin(), entries.end(),
                       [&s](const ChartSeries* e) { return e->name == s.name; }))
        entries.push_back(&s);
  return entries;
}

constexpr int kLegendFontSize = 13;
constexpr int kLegendPadding = 5;      // vtkChartLegend's default padding
constexpr int kLegendSymbolWidth = 48; // long enough to show a line's pattern
constexpr int kLegendMargin = 15;      // between the panels, the legend and the edge

/// The width and height in pixels of `text` as the chart draws it (72 dpi, VTK's
/// default for a render window).
vtkVector2i textSize(const std::string& text)
{
  vtkNew<vtkTextProperty> property;
  property->SetFontSize(kLegendFontSize);
  int bbox[4] = {0, 0, 0, 0};
  vtkTextRenderer* renderer = vtkTextRenderer::GetInstance();
  if (renderer == nullptr || !renderer->GetBoundingBox(property, text, bbox, 72))
    return vtkVector2i(static_cast<int>(8 * text.size()), 2 * kLegendFontSize);
  return vtkVector2i(bbox[1] - bbox[0] + 1, bbox[3] - bbox[2] + 1);
}

} // namespace

std::vector<double> integerTicks(double min, double max, int max_ticks)
{
  if (!std::isfinite(min) || !std::isfinite(max) || min > max || max_ticks < 2)
    throw InvalidArgumentError("integer ticks need finite min <= max and at least 2 "
                               "ticks, not [" +
                               std::to_string(min) + ", " + std::to_string(max) +
                               "] with " + std::to_string(max_ticks));
  const double first = std::ceil(min), last = std::floor(max);
  std::vector<double> ticks;
  if (first > last)
    return ticks;
  // The first multiple of `step` after `first` that a tick takes, and the tick count.
  const auto second = [first](double step) {
    return std::ceil((first + 0.5 * step) / step) * step;
  };
  const auto count = [&](double step) {
    return 1.0 + std::max(0.0, std::floor((last - second(step)) / step) + 1.0);
  };
  double step = 1.0;
  for (int i = 0; count(step) > max_ticks; ++i)
    step = std::pow(10.0, i / 3) * (i % 3 == 0 ? 2.0 : i % 3 == 1 ? 5.0 : 10.0);
  ticks.push_back(first);
  for (double t = second(step); t <= last; t += step)
    ticks.push_back(t);
  return ticks;
}

void LineChartFigure::setSize(int width, int height)
{
  if (width < 100 || height < 100 || width > 8192 || height > 8192)
    throw InvalidArgumentError(
        "a chart figure is 100 to 8192 pixels wide and high, not " +
        std::to_string(width) + " x " + std::to_string(height));
  width_ = width;
  height_ = height;
}

void LineChartFigure::setColumns(int columns)
{
  if (columns < 0)
    throw InvalidArgumentError("chart columns must be >= 0 (0: one row)");
  columns_ = columns;
}

void LineChartFigure::addPanel(const ChartPanel& panel)
{
  for (const ChartSeries& s : panel.series)
    checkSeries(s);
  panels_.push_back(panel);
}

RgbImage LineChartFigure::renderImage() const
{
  if (panels_.empty())
    throw InvalidArgumentError("a chart figure needs at least one panel");
  const int n = static_cast<int>(panels_.size());
  const int cols = columns_ > 0 ? std::min(columns_, n) : n;
  const int rows = (n + cols - 1) / cols;

  // The connection outlives the window, which uses it and does not close it.
  detail::XDisplayConnection display;
  // A plain window and renderer with a context actor: a vtkContextView would also make
  // an interactor, and warn on stderr that none of its styles is linked.
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1.0, 1.0, 1.0);
  vtkNew<vtkContextActor> context;
  renderer->AddActor(context);
  vtkNew<vtkRenderWindow> window;
  window->SetDisplayId(display.handle());
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(8);
  window->SetSize(width_, height_);
  window->AddRenderer(renderer);

  vtkNew<vtkChartMatrix> matrix;
  context->GetScene()->AddItem(matrix);
  matrix->SetSize(vtkVector2i(cols, rows));
  // Room for the figure's title above the panels (pixels).
  const int title_px = title_.empty() ? 0 : 40;
  const int top_px = title_px + 30;

  // The legend: a box right of the panels, drawn by VTK's legend item from the plots of a
  // chart that is never drawn itself; the panels' right border makes room for it.
  const std::vector<const ChartSeries*> entries =
      show_legend_ ? legendEntries(panels_) : std::vector<const ChartSeries*>();
  vtkNew<vtkChartXY> legend_chart;
  vtkNew<vtkChartLegend> legend;
  int legend_px = 0;
  if (!entries.empty()) {
    int label_px = 0;
    for (const ChartSeries* s : entries) {
      label_px = std::max(label_px, textSize(s->name).GetX());
      vtkNew<vtkTable> table; // one point: a plot wants data, though it is not drawn
      auto x = column("x"), y = column("y");
      x->InsertNextValue(0.0);
      y->InsertNextValue(0.0);
      table->AddColumn(x);
      table->AddColumn(y);
      addStyledLine(legend_chart, *s)->SetInputData(table, 0, 1);
    }
    const int box_w = label_px + 2 * kLegendPadding + kLegendSymbolWidth;
    const int line_h = textSize("Tgyf").GetY();
    const int box_h =
        static_cast<int>(entries.size()) * (line_h + kLegendPadding) + kLegendPadding;
    legend_px = box_w + kLegendMargin;
    legend->SetChart(legend_chart);
    legend->SetLabelSize(kLegendFontSize);
    legend->SetPadding(kLegendPadding);
    legend->SetSymbolWidth(kLegendSymbolWidth);
    legend->SetHorizontalAlignment(vtkChartLegend::CUSTOM);
    legend->SetVerticalAlignment(vtkChartLegend::CUSTOM);
    legend->SetDragEnabled(false);
    // The box's top beside the top of the first row's plots (scene y runs upwards).
    legend->SetPoint(vtkVector2f(static_cast<float>(width_ - kLegendMargin - box_w),
                                 static_cast<float>(height_ - top_px - box_h)));
    legend->Update();
    context->GetScene()->AddItem(legend);
  }
  matrix->SetBorders(70, 55, 20 + legend_px, top_px);
  matrix->SetGutter(vtkVector2f(80.0f, 85.0f));
  for (int i = 0; i < n; ++i) {
    // The matrix counts rows from the bottom.
    auto* chart = vtkChartXY::SafeDownCast(
        matrix->GetChart(vtkVector2i(i % cols, rows - 1 - i / cols)));
    if (chart == nullptr)
      throw Error("VTK's chart matrix gave no XY chart");
    fillPanel(chart, panels_[i]);
  }
  if (!title_.empty()) {
    vtkNew<vtkTextActor> title;
    title->SetInput(title_.c_str());
    vtkTextProperty* text = title->GetTextProperty();
    text->SetFontSize(22);
    text->BoldOn();
    text->SetFontFamilyToArial();
    text->SetColor(0.1, 0.1, 0.1);
    text->SetJustificationToCentered();
    text->SetVerticalJustificationToTop();
    title->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    title->SetPosition(0.5, 1.0 - 8.0 / height_);
    renderer->AddActor2D(title);
  }
  window->Render();
  RgbImage image = detail::readWindowImage(window, width_, height_);
  window->Finalize();
  return image;
}

void LineChartFigure::render(const std::string& png_path) const
{
  writePng(renderImage(), png_path);
}

} // namespace viz
} // namespace plantnbv
