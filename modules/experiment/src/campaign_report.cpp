#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>

#include <plantnbv/common/error.h>
#include <plantnbv/common/file_io.h>
#include <plantnbv/common/number_text.h>
#include <plantnbv/experiment/campaign_report.h>
#include <plantnbv/metrics/reconstruction_metrics.h>

namespace plantnbv {

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr int kMetrics = 4; // f1, precision, recall, chamfer
const char* const kMetricNames[kMetrics] = {"f1", "precision", "recall", "chamfer"};

double metric(const LevelScore& s, int m)
{
  switch (m) {
  case 0:
    return s.f1;
  case 1:
    return s.precision;
  case 2:
    return s.recall;
  default:
    return s.chamfer;
  }
}

std::string csvNumber(double x)
{
  return std::isfinite(x) ? shortestText(x) : std::string();
}

/// A group of trials compared with each other: a study variant's planner.
struct GroupKey {
  std::string study, variant, planner;
  bool operator<(const GroupKey& o) const
  {
    // "main" first, then by name.
    return std::make_tuple(study != "main", study, variant, planner) <
           std::make_tuple(o.study != "main", o.study, o.variant, o.planner);
  }
};

/// A unit: one sample of a group (plant, yaw, repetition); its curves are the means
/// over its trials (the patterns of a pre-defined planner), [level][metric][view].
struct Unit {
  std::vector<const StoredTrial*> trials;
};

struct Group {
  std::map<std::tuple<std::string, double, int>, Unit> units;
  int views = 0;
};

/// The per-view values of one unit, one level and one metric (trials that stopped early
/// keep their last value), averaged over the unit's trials where finite.
std::vector<double> unitCurve(const Unit& unit, const std::string& level, int m,
                              int views)
{
  std::vector<double> curve(static_cast<std::size_t>(views), kNan);
  for (int v = 0; v < views; ++v) {
    double sum = 0.0;
    int n = 0;
    for (const StoredTrial* t : unit.trials) {
      const auto it = std::find(t->level_names.begin(), t->level_names.end(), level);
      if (it == t->level_names.end() || t->views.empty())
        continue;
      const std::size_t l = static_cast<std::size_t>(it - t->level_names.begin());
      const std::size_t i =
          std::min<std::size_t>(static_cast<std::size_t>(v), t->views.size() - 1);
      const double x = metric(t->views[i][l], m);
      if (std::isfinite(x)) {
        sum += x;
        ++n;
      }
    }
    curve[static_cast<std::size_t>(v)] = n ? sum / n : kNan;
  }
  return curve;
}

struct Analysis {
  std::map<GroupKey, Group> groups;
  std::vector<std::string> levels; // in first-seen order
  std::size_t done = 0, failed = 0;
};

Analysis analyse(const std::vector<StoredTrial>& trials)
{
  Analysis a;
  for (const StoredTrial& t : trials) {
    if (t.failed) {
      ++a.failed;
      continue;
    }
    ++a.done;
    for (const std::string& l : t.level_names)
      if (std::find(a.levels.begin(), a.levels.end(), l) == a.levels.end())
        a.levels.push_back(l);
    Group& g = a.groups[{t.study, t.variant, t.planner}];
    g.units[{t.plant, t.yaw_deg, t.repetition}].trials.push_back(&t);
    g.views = std::max(g.views, static_cast<int>(t.views.size()));
  }
  return a;
}

bool hasLevel(const Group& g, const std::string& level)
{
  for (const auto& [key, unit] : g.units)
    for (const StoredTrial* t : unit.trials)
      if (std::find(t->level_names.begin(), t->level_names.end(), level) !=
          t->level_names.end())
        return true;
  return false;
}

/// The mean F1 curve of a group at a level, and the units' F1 curves.
std::vector<double> meanCurve(const Group& g, const std::string& level,
                              std::vector<std::vector<double>>* unit_curves = nullptr)
{
  std::vector<std::vector<double>> curves;
  for (const auto& [key, unit] : g.units)
    curves.push_back(unitCurve(unit, level, 0, g.views));
  std::vector<double> mean(static_cast<std::size_t>(g.views), kNan);
  for (int v = 0; v < g.views; ++v) {
    std::vector<double> values;
    for (const auto& c : curves)
      values.push_back(c[static_cast<std::size_t>(v)]);
    mean[static_cast<std::size_t>(v)] = summarize(values).mean;
  }
  if (unit_curves)
    *unit_curves = std::move(curves);
  return mean;
}

std::string viewsText(int views)
{
  return views < 0 ? "-" : std::to_string(views);
}

std::string medianText(double m, int max_views)
{
  if (std::isnan(m))
    return "-";
  if (std::isinf(m))
    return ">" + std::to_string(max_views);
  std::ostringstream s;
  s << m;
  return s.str();
}

/// "3 / 6 (median 3 / 5.5)": views to reach F1 0.8 / 0.9 from the mean curve, median
/// over the units ("-" never within the budget on the mean curve, ">N" for the median).
std::string reachText(const Group& g, const std::string& level)
{
  std::vector<std::vector<double>> curves;
  const std::vector<double> mean = meanCurve(g, level, &curves);
  std::string text;
  std::string medians;
  for (double tau : {0.8, 0.9}) {
    std::vector<double> reach;
    for (const auto& c : curves) {
      const int v = viewsToReach(c, tau);
      reach.push_back(v < 0 ? std::numeric_limits<double>::infinity() : double(v));
    }
    text += (text.empty() ? "" : " / ") + viewsText(viewsToReach(mean, tau));
    medians += (medians.empty() ? "" : " / ") + medianText(median(reach), g.views);
  }
  return text + " (median " + medians + ")";
}

std::string fixed(double x, int digits)
{
  if (!std::isfinite(x))
    return "-";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", digits, x);
  return buffer;
}

std::string signedPercent(double x)
{
  if (!std::isfinite(x))
    return "-";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%+.1f%%", x);
  return buffer;
}

/// F1 after `views` views: mean and CI text.
std::string f1At(const Group& g, const std::string& level, int views)
{
  if (views > g.views)
    return "-";
  std::vector<double> values;
  for (const auto& [key, unit] : g.units)
    values.push_back(
        unitCurve(unit, level, 0, g.views)[static_cast<std::size_t>(views - 1)]);
  const SampleSummary s = summarize(values);
  return fixed(s.mean, 3) + " [" + fixed(s.ci_low, 3) + ", " + fixed(s.ci_high, 3) + "]";
}

/// Relative gain in percent of a's mean F1 over b's after `views` views, and the
/// difference in percentage points.
std::pair<double, double> gainAt(const Group& a, const Group& b, const std::string& level,
                                 int views)
{
  if (views > a.views || views > b.views)
    return {kNan, kNan};
  const double fa = meanCurve(a, level)[static_cast<std::size_t>(views - 1)];
  const double fb = meanCurve(b, level)[static_cast<std::size_t>(views - 1)];
  return {100.0 * (fa - fb) / fb, 100.0 * (fa - fb)};
}

/// The mean over a group's units of the whole plant's recall of organ `o` (index into
/// evaluatedOrgans()) after `views` views (a unit's value: the mean over its trials
/// where finite; a trial that stopped early keeps its last view); NaN where no unit has
/// it (files without organ recall, a plant without the organ).
double organRecallAt(const Group& g, std::size_t o, int views)
{
  std::vector<double> values;
  for (const auto& [key, unit] : g.units) {
    double sum = 0.0;
    int n = 0;
    for (const StoredTrial* t : unit.trials) {
      if (t->organ_recall.empty())
        continue;
      const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(views - 1),
                                                  t->organ_recall.size() - 1);
      const double x = t->organ_recall[i][o];
      if (std::isfinite(x)) {
        sum += x;
        ++n;
      }
    }
    if (n)
      values.push_back(sum / n);
  }
  return values.empty() ? kNan : summarize(values).mean;
}

bool isNbv(const std::string& planner)
{
  return planner.rfind("nbv", 0) == 0;
}

/// The paper's numbers (Burusa et al., section 4).
struct PaperNumber {
  const char* level;
  const char* planner;
  const char* quantity; // "views to F1 0.8", "views to F1 0.9", "F1 gain at 3 views vs X"
  const char* other;    // the baseline of a gain, else nullptr
  const char* value;
};
constexpr PaperNumber kPaper[] = {
    {"whole_plant", "nbv-whole-plant", "views to F1 0.8", nullptr, "3"},
    {"whole_plant", "nbv-main-stem", "views to F1 0.8", nullptr, "3"},
    {"whole_plant", "predefined", "views to F1 0.8", nullptr, "4"},
    {"whole_plant", "random", "views to F1 0.8", nullptr, "4"},
    {"whole_plant", "nbv-whole-plant", "F1 gain at 3 views", "predefined", "+9.7%"},
    {"whole_plant", "nbv-whole-plant", "F1 gain at 3 views", "random", "+5.3%"},
    {"whole_plant", "nbv-main-stem", "F1 gain at 3 views", "predefined", "+9.7%"},
    {"whole_plant", "nbv-main-stem", "F1 gain at 3 views", "random", "+5.3%"},
    {"main_stem", "nbv-whole-plant", "views to F1 0.8", nullptr, "4"},
    {"main_stem", "nbv-main-stem", "views to F1 0.8", nullptr, "4"},
    {"main_stem", "predefined", "views to F1 0.8", nullptr, "5"},
    {"main_stem", "random", "views to F1 0.8", nullptr, "5"},
    {"main_stem", "nbv-whole-plant", "F1 gain at 3 views", "predefined", "+14.2%"},
    {"main_stem", "nbv-whole-plant", "F1 gain at 3 views", "random", "+7.9%"},
    {"main_stem", "nbv-main-stem", "F1 gain at 3 views", "predefined", "+14.2%"},
    {"main_stem", "nbv-main-stem", "F1 gain at 3 views", "random", "+7.9%"},
    {"leaf_nodes", "nbv-leaf-nodes", "views to F1 0.8", nullptr, "3"},
    {"leaf_nodes", "nbv-whole-plant", "views to F1 0.8", nullptr, "5"},
    {"leaf_nodes", "nbv-main-stem", "views to F1 0.8", nullptr, "5"},
    {"leaf_nodes", "predefined", "views to F1 0.8", nullptr, "6"},
    {"leaf_nodes", "random", "views to F1 0.8", nullptr, "6"},
    {"leaf_nodes", "nbv-leaf-nodes", "views to F1 0.9", nullptr, "6"},
    {"leaf_nodes", "nbv-whole-plant", "views to F1 0.9", nullptr, ">= 9"},
    {"leaf_nodes", "nbv-main-stem", "views to F1 0.9", nullptr, ">= 9"},
    {"leaf_nodes", "predefined", "views to F1 0.9", nullptr, ">= 9"},
    {"leaf_nodes", "random", "views to F1 0.9", nullptr, ">= 9"},
    {"leaf_nodes", "nbv-leaf-nodes", "F1 gain at 3 views", "predefined", "+25.9%"},
    {"leaf_nodes", "nbv-leaf-nodes", "F1 gain at 3 views", "random", "+17.3%"},
    {"leaf_nodes", "nbv-leaf-nodes", "F1 gain at 3 views", "nbv-whole-plant",
     "+6.8% (vs other NBV)"},
    {"leaf_nodes", "nbv-leaf-nodes", "F1 gain at 3 views", "nbv-main-stem",
     "+6.8% (vs other NBV)"},
};

void writeSummary(std::ostream& out, const Analysis& a, const std::string& title)
{
  out << "# " << title << "\n\n"
      << a.done << " trials done, " << a.failed << " failed (left out). Samples: one per "
      << "plant, yaw and repetition; the patterns of a pre-defined planner are averaged "
         "into one sample. Views count v0.\n\n";

  // Each section only where it has rows: a heading with nothing under it says nothing.
  // Views to reach F1 0.8 / 0.9, study by study.
  if (!a.groups.empty())
    out << "## Views to reach F1 0.8 / 0.9\n\n"
        << "From the mean F1 curve, and in brackets the median over samples (`-`: the "
           "mean curve never reaches it; `>N`: more than half of the samples never do "
           "within N views).\n";
  std::string current;
  for (const auto& [key, g] : a.groups) {
    const std::string heading =
        key.study + (key.variant.empty() ? "" : ", " + key.variant);
    if (heading != current) {
      current = heading;
      out << "\n### " << heading << "\n\n| planner | n |";
      for (const std::string& l : a.levels)
        out << " " << l << " |";
      out << "\n|---|---|";
      for (std::size_t i = 0; i < a.levels.size(); ++i)
        out << "---|";
      out << "\n";
    }
    out << "| " << key.planner << " | " << g.units.size() << " |";
    for (const std::string& l : a.levels)
      out << " " << (hasLevel(g, l) ? reachText(g, l) : "n/a") << " |";
    out << "\n";
  }

  // Relative F1 gain at 3 views in the main study.
  auto find = [&a](const std::string& study, const std::string& variant,
                   const std::string& planner) -> const Group* {
    const auto it = a.groups.find({study, variant, planner});
    return it == a.groups.end() ? nullptr : &it->second;
  };
  std::ostringstream gains;
  for (const auto& [key, g] : a.groups) {
    if (key.study != "main" || !isNbv(key.planner))
      continue;
    for (const char* base : {"predefined", "random"}) {
      const Group* b = find(key.study, key.variant, base);
      if (!b)
        continue;
      gains << "| " << key.planner << " | " << base << " |";
      for (const std::string& l : a.levels) {
        const auto [rel, points] = gainAt(g, *b, l, 3);
        gains << " " << signedPercent(rel) << " (" << fixed(points, 1) << ") |";
      }
      gains << "\n";
    }
  }
  if (!gains.str().empty()) {
    out << "\n## F1 gain of the NBV planners after 3 views (study main)\n\n"
        << "Relative gain of the mean F1, (NBV - baseline) / baseline, and in brackets "
           "the difference in percentage points.\n\n| planner | baseline |";
    for (const std::string& l : a.levels)
      out << " " << l << " |";
    out << "\n|---|---|";
    for (std::size_t i = 0; i < a.levels.size(); ++i)
      out << "---|";
    out << "\n" << gains.str();
  }

  // Recall per organ in the main study: which organs the reconstructions miss.
  const std::vector<PartLabel>& organs = evaluatedOrgans();
  std::ostringstream organ_rows;
  std::vector<bool> organ_seen(organs.size(), false);
  for (const auto& [key, g] : a.groups)
    for (std::size_t o = 0; o < organs.size(); ++o)
      if (key.study == "main" && std::isfinite(organRecallAt(g, o, g.views)))
        organ_seen[o] = true;
  for (const auto& [key, g] : a.groups) {
    if (key.study != "main")
      continue;
    organ_rows << "| " << key.planner << (key.variant.empty() ? "" : ", " + key.variant)
               << " |";
    for (std::size_t o = 0; o < organs.size(); ++o)
      if (organ_seen[o])
        organ_rows << " " << fixed(organRecallAt(g, o, std::min(3, g.views)), 3) << " / "
                   << fixed(organRecallAt(g, o, g.views), 3) << " |";
    organ_rows << "\n";
  }
  if (std::find(organ_seen.begin(), organ_seen.end(), true) != organ_seen.end()) {
    out << "\n## Recall per organ (study main)\n\n"
        << "The whole plant's recall of each organ after 3 views / after the last view "
           "(mean over samples; a voxel where two organs meet counts for both).\n\n"
           "| planner |";
    for (std::size_t o = 0; o < organs.size(); ++o)
      if (organ_seen[o])
        out << " " << partLabelName(organs[o]) << " |";
    out << "\n|---|";
    for (std::size_t o = 0; o < organs.size(); ++o)
      if (organ_seen[o])
        out << "---|";
    out << "\n" << organ_rows.str();
  }

  // Sensitivity studies: each variant beside the main study's same planner.
  // Rows level by level, so that variants of one planner stand together.
  std::ostringstream studies;
  std::string done_study;
  for (const auto& entry : a.groups) {
    const GroupKey& key0 = entry.first;
    if (key0.study == "main" || key0.study == done_study)
      continue;
    done_study = key0.study;
    std::ostringstream rows;
    std::vector<std::string> planners;
    for (const auto& [key, g] : a.groups)
      if (key.study == key0.study &&
          std::find(planners.begin(), planners.end(), key.planner) == planners.end())
        planners.push_back(key.planner);
    for (const std::string& l : a.levels)
      for (const std::string& planner : planners) {
        auto row = [&](const Group& grp, const std::string& variant) {
          rows << "| " << l << " | " << planner << " | " << variant << " | "
               << grp.units.size() << " | " << f1At(grp, l, 3) << " | "
               << f1At(grp, l, grp.views) << " | " << reachText(grp, l) << " |\n";
        };
        if (const Group* m = find("main", "", planner))
          if (hasLevel(*m, l))
            row(*m, "main");
        for (const auto& [key, g] : a.groups)
          if (key.study == key0.study && key.planner == planner && hasLevel(g, l))
            row(g, key.variant.empty() ? "-" : key.variant);
      }
    if (rows.str().empty())
      continue;
    studies << "\n### " << key0.study
            << "\n\n| level | planner | variant | n | F1 at "
               "3 views | F1 at the last view | views to 0.8 / 0.9 |\n"
               "|---|---|---|---|---|---|---|\n"
            << rows.str();
  }
  if (!studies.str().empty())
    out << "\n## Sensitivity studies\n\nF1 after 3 views and after the last view (mean "
           "[95% CI]), views to reach F1 0.8 / 0.9 (mean curve; median over samples). "
           "`main` is the main study's result for the same planner.\n"
        << studies.str();

  // The paper beside ours: the rows whose planner (and baseline) ran at the level.
  std::ostringstream paper;
  std::size_t paper_rows = 0, not_run = 0;
  for (const PaperNumber& p : kPaper) {
    ++paper_rows;
    const Group* g = find("main", "", p.planner);
    const Group* b = p.other ? find("main", "", p.other) : nullptr;
    if (!g || !hasLevel(*g, p.level) || (p.other && (!b || !hasLevel(*b, p.level)))) {
      ++not_run;
      continue;
    }
    std::string ours;
    if (b) {
      const auto [rel, points] = gainAt(*g, *b, p.level, 3);
      ours = signedPercent(rel) + " (" + fixed(points, 1) + " points)";
    } else {
      const int v =
          viewsToReach(meanCurve(*g, p.level),
                       std::string(p.quantity) == "views to F1 0.8" ? 0.8 : 0.9);
      ours = v < 0 ? ">" + std::to_string(g->views) : std::to_string(v);
    }
    paper << "| " << p.level << " | " << p.planner << " | " << p.quantity
          << (p.other ? std::string(" vs ") + p.other : std::string()) << " | " << p.value
          << " | " << ours << " |\n";
  }
  if (paper.str().empty())
    return;
  out << "\n## The paper's numbers beside ours\n\n"
      << "Paper: Burusa et al., section 4 (10 plants x 12 yaws). Ours: study main, mean "
         "curve. The paper does not say whether its F1 gains are relative or percentage "
         "points: both of ours are given.";
  if (not_run)
    out << "\n\n"
        << not_run << " of the paper's " << paper_rows << " rows "
        << (not_run == 1 ? "has" : "have")
        << " no trial in this campaign (the planner, its baseline or the level is not in "
           "study main) and "
        << (not_run == 1 ? "is" : "are") << " left out.";
  out << "\n\n| level | planner | quantity | paper | ours |\n|---|---|---|---|---|\n"
      << paper.str();
}

} // namespace

std::vector<CurveRow> campaignCurves(const std::vector<StoredTrial>& trials)
{
  const Analysis a = analyse(trials);
  std::vector<CurveRow> rows;
  for (const auto& [key, g] : a.groups)
    for (const std::string& level : a.levels) {
      if (!hasLevel(g, level))
        continue;
      std::vector<std::vector<double>> curves[kMetrics];
      for (int m = 0; m < kMetrics; ++m)
        for (const auto& [ukey, unit] : g.units)
          curves[m].push_back(unitCurve(unit, level, m, g.views));
      for (int v = 0; v < g.views; ++v) {
        CurveRow row;
        row.study = key.study;
        row.variant = key.variant;
        row.planner = key.planner;
        row.level = level;
        row.view = v + 1;
        SampleSummary* out[kMetrics] = {&row.f1, &row.precision, &row.recall,
                                        &row.chamfer};
        for (int m = 0; m < kMetrics; ++m) {
          std::vector<double> values;
          for (const auto& c : curves[m])
            values.push_back(c[static_cast<std::size_t>(v)]);
          *out[m] = summarize(values);
        }
        rows.push_back(std::move(row));
      }
    }
  return rows;
}

std::vector<TimingRow> campaignTiming(const std::vector<StoredTrial>& trials)
{
  std::map<GroupKey, TimingRow> groups;
  double all_ms = 0.0;
  for (const StoredTrial& t : trials) {
    if (t.failed || !t.times.complete())
      continue;
    TimingRow& row = groups[{t.study, t.variant, t.planner}];
    if (row.trials++ == 0) {
      row.study = t.study;
      row.variant = t.variant;
      row.planner = t.planner;
      for (double TrialTimes::*ms : kTrialTimes)
        row.mean.*ms = 0.0; // sums until the end
    }
    for (double TrialTimes::*ms : kTrialTimes)
      row.mean.*ms += t.times.*ms;
    all_ms += t.times.total_ms;
  }
  std::vector<TimingRow> rows;
  for (auto& [key, row] : groups) {
    row.share = all_ms > 0.0 ? row.mean.total_ms / all_ms : 0.0;
    for (double TrialTimes::*ms : kTrialTimes)
      row.mean.*ms /= double(row.trials);
    rows.push_back(row);
  }
  return rows;
}

void writeCurvesCsv(const std::filesystem::path& path, const std::vector<CurveRow>& rows)
{
  AtomicFile file(path);
  std::ostream& out = file.stream();
  out << "study,variant,planner,level,view";
  for (const char* m : kMetricNames)
    out << "," << m << "_mean," << m << "_sd," << m << "_n," << m << "_ci_low," << m
        << "_ci_high";
  out << "\n";
  for (const CurveRow& r : rows) {
    out << r.study << "," << r.variant << "," << r.planner << "," << r.level << ","
        << r.view;
    for (const SampleSummary* s : {&r.f1, &r.precision, &r.recall, &r.chamfer})
      out << "," << csvNumber(s->mean) << "," << csvNumber(s->sd) << "," << s->n << ","
          << csvNumber(s->ci_low) << "," << csvNumber(s->ci_high);
    out << "\n";
  }
  file.commit();
}

void writeCampaignReport(const std::vector<StoredTrial>& trials,
                         const std::filesystem::path& out_dir, const std::string& title)
{
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec)
    throw IoError("cannot create '" + out_dir.string() + "': " + ec.message());
  writeCurvesCsv(out_dir / "curves.csv", campaignCurves(trials));
  const Analysis a = analyse(trials);
  writeFileAtomically(out_dir / "summary.md",
                      [&](std::ostream& out) { writeSummary(out, a, title); });
}

} // namespace plantnbv
