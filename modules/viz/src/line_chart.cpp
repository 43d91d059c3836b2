#include <algorithm>
#include <cmath>
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
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
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
  vtkPlot* line = chart->AddPlot(vtkChart::LINE);
  line->SetInputData(table, 0, 1);
  line->SetColor(r, g, b, 255);
  line->SetWidth(2.5f);
  line->SetLabel(s.name);
  if (s.dashed)
    line->GetPen()->SetLineType(vtkPen::DASH_LINE);
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
  if (p.legend == ChartPanel::LegendCorner::none || p.series.empty())
    return;
  chart->SetShowLegend(true);
  vtkChartLegend* legend = chart->GetLegend();
  legend->SetLabelSize(13);
  legend->SetHorizontalAlignment(vtkChartLegend::RIGHT);
  legend->SetVerticalAlignment(p.legend == ChartPanel::LegendCorner::top_right
                                   ? vtkChartLegend::TOP
                                   : vtkChartLegend::BOTTOM);
}

} // namespace

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
  matrix->SetBorders(70, 55, 20, title_px + 30);
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
