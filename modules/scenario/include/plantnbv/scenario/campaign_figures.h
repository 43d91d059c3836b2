#pragma once
// The report's figures: the paper's curves (F1 and Chamfer distance vs views, mean with a
// shaded 95% confidence interval, one panel per evaluation level) from curves.csv's rows.

#include <filesystem>
#include <string>
#include <vector>

#include <plantnbv/experiment/campaign.h>
#include <plantnbv/experiment/campaign_report.h>

namespace plantnbv {
namespace scenario {

/// \brief Writes into `out_dir`, for the main study (named "main", or else the first
/// study; either only if it has no variants): f1_<study>.png and chamfer_<study>.png, one
/// panel per level, one curve per planner; for each other study (the sensitivity studies,
/// e.g. a campaign's only study when it has variants, as data/campaigns/row.yaml):
/// f1_<study>.png, a row of level panels per planner, one curve per variant (solid, each
/// its colour and marker) beside the main study's curve of the same planner (black,
/// dashed; none without a main study). Colours are Okabe and Ito's (viz::chartColor), and
/// the paper's planners keep theirs in every figure and campaign: nbv-whole-plant blue
/// with circles, nbv-main-stem vermillion with squares, nbv-leaf-nodes bluish green with
/// diamonds (solid lines), predefined orange dashed with crosses, random sky blue
/// dash-dotted with pluses, nbv-fruit reddish purple; other planners take, in order, the
/// colours and markers left free (solid lines). The x axis counts views from 1 (v0
/// only) with whole-number ticks; one legend stands right of the panels. About 1200 px
/// wide. With the campaign's `definition`, also roi_error_<study>.png for each study
/// whose NBV planners with a noisy ROI source (RoiSource) on one attention ROI and scale
/// have at least two sigmas: F1 after 3 views against sigma (cm), one panel per level,
/// one curve per attention ROI in its planner's style, and the study's other planners
/// (the baselines, oracle NBV planners) as flat lines in theirs. Returns the files
/// written.
/// \throws Error when rendering fails (e.g. no X display: run under xvfb-run).
std::vector<std::filesystem::path>
writeCampaignFigures(const std::vector<CurveRow>& rows,
                     const std::filesystem::path& out_dir,
                     const CampaignDefinition* definition = nullptr);

/// \brief What writeCampaignReportFiles read and wrote.
struct CampaignReportFiles {
  std::size_t trials = 0;  ///< result files read
  std::size_t failed = 0;  ///< of those, failed
  std::size_t missing = 0; ///< trials of campaign.yaml without a result (0 without it)
  std::size_t total = 0;   ///< trials of campaign.yaml (0 without it)
  std::vector<std::filesystem::path> written; ///< curves.csv, summary.md, PNGs
};

/// \brief `campaign report`: the report (writeCampaignReport) of the results in the
/// campaign directory `dir` into `out_dir`, titled by its campaign.yaml's name, and with
/// `figures` the PNGs (writeCampaignFigures: needs an X display).
/// \throws FileNotFoundError when `dir` has no trials/; InvalidArgumentError when it
/// holds no result yet; IoError when a file cannot be written.
CampaignReportFiles writeCampaignReportFiles(const std::filesystem::path& dir,
                                             const std::filesystem::path& out_dir,
                                             bool figures);

} // namespace scenario
} // namespace plantnbv
