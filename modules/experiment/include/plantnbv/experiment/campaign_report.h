#pragma once
/// \file campaign_report.h
/// \brief Statistics of a campaign's results: the mean curves with 95% confidence
/// intervals (curves.csv) and the paper's summary numbers (summary.md), section 4.

#include <filesystem>
#include <string>
#include <vector>

#include <plantnbv/experiment/result_store.h>
#include <plantnbv/experiment/statistics.h>

namespace plantnbv {

/// \brief One row of curves.csv: a study variant's planner at one level after `view`
/// views (1 = v0 only). The samples are the trials' units: one per plant, yaw and
/// repetition; the patterns of a pre-defined planner are averaged into one unit first.
/// A trial that stopped early keeps its last scores for the remaining views.
struct CurveRow {
  /// The study, its variant (empty for one variant), the planner and the level.
  ///@{
  std::string study, variant, planner, level;
  ///@}
  int view = 0; ///< views taken, 1 = v0 only
  /// F1, precision, recall and Chamfer distance (metres) over the units.
  ///@{
  SampleSummary f1, precision, recall, chamfer;
  ///@}
};

/// \brief The rows for all done trials (failed ones are left out), ordered by study
/// ("main" first), variant, planner, level (in the trials' order), view.
std::vector<CurveRow> campaignCurves(const std::vector<StoredTrial>& trials);

/// \brief Where a study variant's planner spends its time: the mean times of its done
/// trials whose files give every time (TrialTimes::complete), and its share of all
/// those trials' time.
struct TimingRow {
  /// The study, its variant (empty for one variant) and the planner.
  ///@{
  std::string study, variant, planner;
  ///@}
  std::size_t trials = 0; ///< the trials timed
  TrialTimes mean;        ///< the means of their times (ms a trial)
  double share = 0.0;     ///< their summed total_ms over that of every timed trial
};

/// \brief One row per study variant's planner with a timed trial, in campaignCurves'
/// order (failed trials and those without every time are left out).
std::vector<TimingRow> campaignTiming(const std::vector<StoredTrial>& trials);

/// \brief Writes curves.csv: study,variant,planner,level,view, then for each of f1,
/// precision, recall, chamfer: `<m>_mean,<m>_sd,<m>_n,<m>_ci_low,<m>_ci_high` (95%,
/// Student's t; empty where undefined). \throws IoError if it cannot.
void writeCurvesCsv(const std::filesystem::path& path, const std::vector<CurveRow>& rows);

/// \brief Writes OUT/curves.csv and OUT/summary.md: views to reach F1 0.8 and 0.9 per
/// planner and level (from the mean curve, and the median over units), the relative F1
/// gain of each NBV planner (kind nbv, named "nbv-...") over the "predefined" and
/// "random" planners after 3 views, the sensitivity studies beside the main study, and
/// the paper's own numbers beside ours: only the paper's rows whose planner (and
/// baseline) the main study ran at that level, with one line that counts those left
/// out. A section with no row (no NBV planner beside a baseline, no sensitivity study,
/// none of the paper's rows) is left out, heading and all. \throws IoError if it cannot
/// write.
void writeCampaignReport(const std::vector<StoredTrial>& trials,
                         const std::filesystem::path& out_dir, const std::string& title);

} // namespace plantnbv
