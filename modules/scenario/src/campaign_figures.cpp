#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include <plantnbv/common/error.h>
#include <plantnbv/common/roi_kind.h>
#include <plantnbv/experiment/result_store.h>
#include <plantnbv/scenario/campaign_figures.h>
#include <plantnbv/scenario/campaign_file.h>
#include <plantnbv/scenario/trial_setup.h>
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

struct Metric {
  const char* file;  ///< file name prefix
  const char* title; ///< in the figure's title
  const char* axis;  ///< y axis label
  double scale;      ///< to the axis unit
  std::function<const SampleSummary&(const CurveRow&)> of;
  bool unit_range; ///< fixed y range [0, 1]; else [0, 1.5 x the largest mean after v0]
};

const Metric kF1{"f1",
                 "F1 score",
                 "F1 score (rho = resolution)",
                 1.0,
                 [](const CurveRow& r) -> const SampleSummary& { return r.f1; },
                 true};
const Metric kChamfer{"chamfer",
                      "Chamfer distance",
                      "Chamfer distance (mm)",
                      1000.0,
                      [](const CurveRow& r) -> const SampleSummary& { return r.chamfer; },
                      false};

using Line = viz::ChartSeries::Line;
using Marker = viz::ChartSeries::Marker;

/// Okabe-Ito colours (viz::chartColor) in the order curves without a fixed style take
/// them: black is kept for the main study's reference curve, yellow (faint on white)
/// last.
constexpr std::size_t kColorOrder[] = {5, 6, 3, 1, 2, 7, 4};
constexpr Marker kMarkerOrder[] = {Marker::circle, Marker::square, Marker::diamond,
                                   Marker::cross, Marker::plus};

/// The style of each planner the paper names (and NBV on the fruit), whatever else a
/// figure shows: NBV planners solid lines, the baselines dashed.
struct PlannerStyle {
  const char* planner;
  std::size_t color; ///< viz::chartColor index
  Line line;
  Marker marker;
};
constexpr PlannerStyle kPlannerStyles[] = {
    {"nbv-whole-plant", 5, Line::solid, Marker::circle}, // blue
    {"nbv-main-stem", 6, Line::solid, Marker::square},   // vermillion
    {"nbv-leaf-nodes", 3, Line::solid, Marker::diamond}, // bluish green
    {"predefined", 1, Line::dashed, Marker::cross},      // orange
    {"random", 2, Line::dash_dot, Marker::plus},         // sky blue
    {"nbv-fruit", 7, Line::solid, Marker::none},         // reddish purple
};

/// Styles `series` in order: each takes the first colour of kColorOrder and the first
/// marker of kMarkerOrder that no curve of the figure has yet (`used_*`); once all are
/// taken, they are taken again from the start.
void styleInOrder(std::vector<viz::ChartSeries>& series,
                  std::vector<std::size_t> used_colors, std::vector<Marker> used_markers)
{
  auto unused = [](const auto& order, auto& used) {
    auto it = std::find_if(std::begin(order), std::end(order), [&used](const auto& x) {
      return std::find(used.begin(), used.end(), x) == used.end();
    });
    if (it == std::end(order)) {
      used.clear();
      it = std::begin(order);
    }
    used.push_back(*it);
    return *it;
  };
  for (viz::ChartSeries& s : series) {
    s.color = viz::chartColor(unused(kColorOrder, used_colors));
    s.marker = unused(kMarkerOrder, used_markers);
  }
}

/// One curve from the rows that pass `keep`, ordered by view, in the style of `style`.
viz::ChartSeries curve(const std::vector<CurveRow>& rows, const Metric& m,
                       const std::function<bool(const CurveRow&)>& keep,
                       const viz::ChartSeries& style)
{
  viz::ChartSeries s = style;
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
  p.x_label = "views (1 = v0 only)";
  p.y_label = m.axis;
  p.fixed_y = true;
  p.y_min = 0.0;
  p.y_max = 1.0;
  p.integer_x = true;
  return p;
}

/// The series of `planners` (name, colour, line and marker; no points), one each: the
/// paper's planners in their fixed style, the others in colours and markers left free.
std::vector<viz::ChartSeries> plannerCurveStyles(const std::vector<std::string>& planners)
{
  std::vector<viz::ChartSeries> styles(planners.size());
  std::vector<viz::ChartSeries> others;
  std::vector<std::size_t> used_colors{0}; // black: the main study's reference
  std::vector<Marker> used_markers;
  for (std::size_t i = 0; i < planners.size(); ++i) {
    styles[i].name = planners[i];
    for (const PlannerStyle& p : kPlannerStyles)
      if (planners[i] == p.planner) {
        styles[i].color = viz::chartColor(p.color);
        styles[i].line = p.line;
        styles[i].marker = p.marker;
        used_colors.push_back(p.color);
        used_markers.push_back(p.marker);
      }
  }
  for (const viz::ChartSeries& s : styles)
    if (std::none_of(std::begin(kPlannerStyles), std::end(kPlannerStyles),
                     [&s](const PlannerStyle& p) { return s.name == p.planner; }))
      others.push_back(s);
  styleInOrder(others, used_colors, used_markers);
  for (viz::ChartSeries& s : styles)
    for (const viz::ChartSeries& o : others)
      if (o.name == s.name)
        s = o;
  return styles;
}

/// The F1 after this many views is what roi_error_<study>.png shows (the view count
/// of the report's gain table: the paper's measure of what attention gains).
constexpr int kRoiErrorViews = 3;

/// The mean F1 (and its CI) after kRoiErrorViews of a study's planner at a level; false
/// when there is no such row.
bool f1AfterFewViews(const std::vector<CurveRow>& rows, const std::string& study,
                     const std::string& planner, const std::string& level,
                     SampleSummary& out)
{
  for (const CurveRow& r : rows)
    if (r.study == study && r.variant.empty() && r.planner == planner &&
        r.level == level && r.view == kRoiErrorViews) {
      out = r.f1;
      return true;
    }
  return false;
}

/// roi_error_<study>.png of writeCampaignFigures, or nothing when the study has no
/// noisy planners of two sigmas on one attention ROI and scale.
std::optional<fs::path> writeRoiErrorFigure(const std::vector<CurveRow>& rows,
                                            const CampaignStudy& study,
                                            const std::vector<std::string>& levels,
                                            const fs::path& out_dir)
{
  struct Curve {
    std::string attention; ///< the planner name of its oracle: "nbv-leaf-nodes"
    double scale = 1.0;
    std::vector<std::pair<double, std::string>> sigma_planner; ///< by sigma
  };
  std::vector<Curve> curves;
  std::vector<std::string> flat; // the study's other planners
  for (const CampaignPlanner& p : study.planners) {
    if (p.kind != PlannerKind::nbv || !p.roi_source ||
        p.roi_source->kind != RoiSourceKind::noisy) {
      addOnce(flat, p.name);
      continue;
    }
    const std::string attention = nbvPlannerName(Attention::parse(p.attention));
    auto it = std::find_if(curves.begin(), curves.end(), [&](const Curve& c) {
      return c.attention == attention && c.scale == p.roi_source->scale;
    });
    if (it == curves.end())
      it = curves.insert(curves.end(), Curve{attention, p.roi_source->scale, {}});
    it->sigma_planner.emplace_back(p.roi_source->sigma_m, p.name);
  }
  curves.erase(std::remove_if(curves.begin(), curves.end(),
                              [](const Curve& c) { return c.sigma_planner.size() < 2; }),
               curves.end());
  if (curves.empty())
    return std::nullopt;
  double sigma_min = std::numeric_limits<double>::infinity(), sigma_max = -sigma_min;
  std::vector<std::string> names;
  for (Curve& c : curves) {
    std::sort(c.sigma_planner.begin(), c.sigma_planner.end());
    sigma_min = std::min(sigma_min, c.sigma_planner.front().first);
    sigma_max = std::max(sigma_max, c.sigma_planner.back().first);
    names.push_back(c.attention);
  }
  names.insert(names.end(), flat.begin(), flat.end());
  std::vector<viz::ChartSeries> styles = plannerCurveStyles(names);
  for (std::size_t i = 0; i < curves.size(); ++i)
    if (curves[i].scale != 1.0) {
      std::ostringstream name;
      name << curves[i].attention << ", boxes x" << curves[i].scale;
      styles[i].name = name.str();
    }

  viz::LineChartFigure figure;
  figure.setTitle("F1 after " + std::to_string(kRoiErrorViews) +
                  " views vs the ROI's error, study '" + study.name +
                  "' (mean and 95% confidence interval; flat: planners without it)");
  figure.setSize(1200, 460);
  for (const std::string& level : levels) {
    viz::ChartPanel p = panel(kF1, roiTitle(level));
    p.x_label = "ROI error, sigma per axis (cm)";
    p.integer_x = false;
    p.fixed_y = false; // the differences are a few points of F1: the data's range
    for (std::size_t i = 0; i < names.size(); ++i) {
      viz::ChartSeries s = styles[i];
      SampleSummary f1;
      auto add = [&](double sigma_m) {
        s.x.push_back(sigma_m * 100.0);
        s.y.push_back(f1.mean);
        s.band_low.push_back(f1.ci_low);
        s.band_high.push_back(f1.ci_high);
      };
      if (i < curves.size()) {
        for (const auto& [sigma, planner] : curves[i].sigma_planner)
          if (f1AfterFewViews(rows, study.name, planner, level, f1))
            add(sigma);
      } else if (f1AfterFewViews(rows, study.name, names[i], level, f1)) {
        add(sigma_min);
        add(sigma_max);
        s.marker = Marker::none;
        s.band_low.clear(); // flat lines: their bands are in f1_<study>.png
        s.band_high.clear();
      }
      if (!s.x.empty())
        p.series.push_back(s);
    }
    figure.addPanel(p);
  }
  const fs::path png = out_dir / ("roi_error_" + study.name + ".png");
  figure.render(png.string());
  return png;
}

} // namespace

std::vector<fs::path> writeCampaignFigures(const std::vector<CurveRow>& rows,
                                           const fs::path& out_dir,
                                           const CampaignDefinition* definition)
{
  std::vector<std::string> studies;
  for (const CurveRow& r : rows)
    addOnce(studies, r.study);
  if (studies.empty())
    return {};
  // The main study's curves join its trials view by view: a study of several variants
  // (a row study alone in its campaign) would join them into one line, so it is drawn as
  // a sensitivity study, with no main study when no study is without variants.
  auto oneVariant = [&rows](const std::string& study) {
    return std::none_of(rows.begin(), rows.end(), [&](const CurveRow& r) {
      return r.study == study && !r.variant.empty();
    });
  };
  std::string main;
  if (std::find(studies.begin(), studies.end(), "main") != studies.end() &&
      oneVariant("main"))
    main = "main";
  else if (const auto first = std::find_if(studies.begin(), studies.end(), oneVariant);
           first != studies.end())
    main = *first;
  std::vector<std::string> planners, levels; // of the main study, or of all
  for (const CurveRow& r : rows)
    if (r.study == main || main.empty()) {
      addOnce(planners, r.planner);
      addOnce(levels, r.level);
    }

  std::vector<fs::path> written;
  for (const Metric* m : {&kF1, &kChamfer}) {
    if (main.empty())
      break;
    viz::LineChartFigure figure;
    figure.setTitle(std::string(m->title) + " vs views, study '" + main +
                    "' (mean and 95% confidence interval" +
                    (m->unit_range ? ")" : "; the scale fits the views after v0)"));
    figure.setSize(1200, 460);
    const std::vector<viz::ChartSeries> styles = plannerCurveStyles(planners);
    for (const std::string& level : levels) {
      viz::ChartPanel p = panel(*m, roiTitle(level));
      for (std::size_t i = 0; i < planners.size(); ++i)
        p.series.push_back(curve(
            rows, *m,
            [&](const CurveRow& r) {
              return r.study == main && r.planner == planners[i] && r.level == level;
            },
            styles[i]));
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
    // The main study's curve black and dashed, the variants' solid, each its colour and
    // marker.
    viz::ChartSeries reference_style;
    reference_style.name = main;
    reference_style.color = viz::chartColor(0);
    reference_style.line = Line::dashed;
    std::vector<viz::ChartSeries> variant_styles(variants.size());
    for (std::size_t v = 0; v < variants.size(); ++v)
      variant_styles[v].name = variants[v];
    styleInOrder(variant_styles, {0}, {});
    viz::LineChartFigure figure;
    figure.setTitle("F1 score vs views, study '" + study +
                    "' (mean and 95% confidence interval" +
                    (main.empty() ? ")" : "; dashed: study '" + main + "')"));
    figure.setColumns(static_cast<int>(levels.size()));
    figure.setSize(1200, 80 + 330 * static_cast<int>(study_planners.size()));
    for (const std::string& planner : study_planners)
      for (const std::string& level : levels) {
        viz::ChartPanel p = panel(kF1, planner + ", " + roiTitle(level));
        viz::ChartSeries reference = curve(
            rows, kF1,
            [&](const CurveRow& r) {
              return r.study == main && r.planner == planner && r.level == level;
            },
            reference_style);
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
              variant_styles[v]));
        figure.addPanel(p);
      }
    written.push_back(out_dir / ("f1_" + study + ".png"));
    figure.render(written.back().string());
  }

  if (definition)
    for (const CampaignStudy& study : definition->studies) {
      std::vector<std::string> study_levels;
      for (const CurveRow& r : rows)
        if (r.study == study.name)
          addOnce(study_levels, r.level);
      if (const auto png = writeRoiErrorFigure(rows, study, study_levels, out_dir))
        written.push_back(*png);
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
  CampaignFile f;
  const bool has_definition = fs::exists(store.definitionPath());
  if (has_definition) {
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
    for (const fs::path& png : writeCampaignFigures(
             campaignCurves(trials), out_dir, has_definition ? &f.definition : nullptr))
      r.written.push_back(png);
  return r;
}

} // namespace scenario
} // namespace plantnbv
