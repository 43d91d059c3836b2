#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <optional>

#include <plantnbv/common/error.h>
#include <plantnbv/common/roi_kind.h>
#include <plantnbv/experiment/result_store.h>
#include <plantnbv/scenario/campaign_figures.h>
#include <plantnbv/scenario/campaign_file.h>
#include <plantnbv/viz/line_chart.h>

namespace plantnbv {
namespace scenario {

namespace {

namespace fs = std::filesystem;

/// Keeps first-seen order (curves.csv's order: planners and levels as the trials list
/// them).
void addOnce(std::vector<std::string>& list, const std::string& name)
{
  if (std::find(list.begin(), list.end(), name) == list.end())
    list.push_back(name);
}

std::string levelTitle(const std::string& level)
{
  const std::optional<RoiKind> kind = roiKindFromName(level);
  return kind ? roiKindTitle(*kind) : level;
}

struct Metric {
  const char* file;  ///< file name prefix
  const char* title; ///< in the figure's title
  const char* axis;  ///< y axis label
  double scale;      ///< to the axis unit
  std::function<const SampleSummary&(const CurveRow&)> of;
  bool unit_range; ///< fixed y range [0, 1]; else [0, 1.5 x the largest mean after v0]
  viz::ChartPanel::LegendCorner legend;
};

const Metric kF1{"f1",
                 "F1 score",
                 "F1 score (rho = resolution)",
                 1.0,
                 [](const CurveRow& r) -> const SampleSummary& { return r.f1; },
                 true,
                 viz::ChartPanel::LegendCorner::bottom_right};
const Metric kChamfer{"chamfer",
                      "Chamfer distance",
                      "Chamfer distance (mm)",
                      1000.0,
                      [](const CurveRow& r) -> const SampleSummary& { return r.chamfer; },
                      false,
                      viz::ChartPanel::LegendCorner::top_right};

/// One curve from the rows that pass `keep`, ordered by view.
viz::ChartSeries curve(const std::vector<CurveRow>& rows, const Metric& m,
                       const std::function<bool(const CurveRow&)>& keep,
                       const std::string& name, std::size_t color)
{
  viz::ChartSeries s;
  s.name = name;
  s.color = viz::distinctColor(color);
  for (const CurveRow& r : rows)
    if (keep(r)) {
      const SampleSummary& v = m.of(r);
      s.x.push_back(r.view);
      s.y.push_back(v.mean * m.scale);
      s.band_low.push_back(v.ci_low * m.scale);
      s.band_high.push_back(v.ci_high * m.scale);
    }
  return s;
}

viz::ChartPanel panel(const Metric& m, const std::string& title)
{
  viz::ChartPanel p;
  p.title = title;
  p.x_label = "views (v0 included)";
  p.y_label = m.axis;
  p.fixed_y = true;
  p.y_min = 0.0;
  p.y_max = 1.0;
  p.legend = m.legend;
  return p;
}

} // namespace

std::vector<fs::path> writeCampaignFigures(const std::vector<CurveRow>& rows,
                                           const fs::path& out_dir)
{
  std::vector<std::string> studies;
  for (const CurveRow& r : rows)
    addOnce(studies, r.study);
  if (studies.empty())
    return {};
  const std::string main =
      std::find(studies.begin(), studies.end(), "main") != studies.end()
          ? "main"
          : studies.front();
  std::vector<std::string> planners, levels;
  for (const CurveRow& r : rows)
    if (r.study == main) {
      addOnce(planners, r.planner);
      addOnce(levels, r.level);
    }

  std::vector<fs::path> written;
  for (const Metric* m : {&kF1, &kChamfer}) {
    viz::LineChartFigure figure;
    figure.setTitle(std::string(m->title) + " vs views, study '" + main +
                    "' (mean and 95% confidence interval" +
                    (m->unit_range ? ")" : "; the scale fits the views after v0)"));
    figure.setSize(1200, 460);
    for (const std::string& level : levels) {
      viz::ChartPanel p = panel(*m, levelTitle(level));
      for (std::size_t i = 0; i < planners.size(); ++i)
        p.series.push_back(curve(
            rows, *m,
            [&](const CurveRow& r) {
              return r.study == main && r.planner == planners[i] && r.level == level;
            },
            planners[i], i));
      if (!m->unit_range) { // v0's distances, many times the others, would flatten them
        double top = 0.0;
        for (const viz::ChartSeries& s : p.series)
          for (std::size_t i = 0; i < s.x.size(); ++i)
            if (s.x[i] >= 2 && std::isfinite(s.y[i]))
              top = std::max(top, s.y[i]);
        p.y_max = top > 0.0 ? 1.5 * top : 1.0;
      }
      figure.addPanel(p);
    }
    written.push_back(out_dir / (std::string(m->file) + "_" + main + ".png"));
    figure.render(written.back().string());
  }

  // Sensitivity studies: per planner a row of level panels, a curve per variant.
  for (const std::string& study : studies) {
    if (study == main)
      continue;
    std::vector<std::string> study_planners, variants;
    for (const CurveRow& r : rows)
      if (r.study == study) {
        addOnce(study_planners, r.planner);
        addOnce(variants, r.variant);
      }
    viz::LineChartFigure figure;
    figure.setTitle("F1 score vs views, study '" + study +
                    "' (mean and 95% confidence interval; dashed: study '" + main + "')");
    figure.setColumns(static_cast<int>(levels.size()));
    figure.setSize(1200, 80 + 330 * static_cast<int>(study_planners.size()));
    for (const std::string& planner : study_planners)
      for (const std::string& level : levels) {
        viz::ChartPanel p = panel(kF1, planner + ", " + levelTitle(level));
        viz::ChartSeries reference = curve(
            rows, kF1,
            [&](const CurveRow& r) {
              return r.study == main && r.planner == planner && r.level == level;
            },
            main, 7);
        reference.dashed = true;
        reference.band_low.clear(); // the main study's band is in f1_main.png
        reference.band_high.clear();
        if (!reference.x.empty())
          p.series.push_back(reference);
        for (std::size_t v = 0; v < variants.size(); ++v)
          p.series.push_back(curve(
              rows, kF1,
              [&](const CurveRow& r) {
                return r.study == study && r.variant == variants[v] &&
                       r.planner == planner && r.level == level;
              },
              variants[v], v));
        figure.addPanel(p);
      }
    written.push_back(out_dir / ("f1_" + study + ".png"));
    figure.render(written.back().string());
  }
  return written;
}

CampaignReportFiles writeCampaignReportFiles(const fs::path& dir, const fs::path& out_dir,
                                             bool figures)
{
  const ResultStore store(dir);
  if (!fs::is_directory(dir / "trials"))
    throw FileNotFoundError("'" + dir.string() +
                            "' is not a campaign directory (no trials/)");
  // With the campaign's definition, each file is checked to be one of its trials' own.
  CampaignReportFiles r;
  std::string title = "Campaign " + dir.filename().string();
  std::vector<StoredTrial> trials;
  if (fs::exists(store.definitionPath())) {
    CampaignFile f;
    const StoreStatus s = campaignDirectoryStatus(dir, &f);
    title = "Campaign '" + f.definition.name + "'";
    r.missing = s.missing;
    r.total = s.total;
    trials = store.load(expandCampaign(f.definition));
  } else {
    trials = store.load();
  }
  if (trials.empty())
    throw InvalidArgumentError("'" + dir.string() + "' holds no trial results yet");
  r.trials = trials.size();
  r.failed = std::size_t(std::count_if(trials.begin(), trials.end(),
                                       [](const StoredTrial& t) { return t.failed; }));
  writeCampaignReport(trials, out_dir, title);
  r.written = {out_dir / "curves.csv", out_dir / "summary.md"};
  if (figures)
    for (const fs::path& png : writeCampaignFigures(campaignCurves(trials), out_dir))
      r.written.push_back(png);
  return r;
}

} // namespace scenario
} // namespace plantnbv
