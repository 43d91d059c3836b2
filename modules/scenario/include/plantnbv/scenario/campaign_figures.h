#pragma once
// The report's figures: the paper's curves (F1 and Chamfer distance vs views, mean with a
// shaded 95% confidence interval, one panel per evaluation level) from curves.csv's rows.

#include <filesystem>
#include <string>
#include <vector>

#include <plantnbv/experiment/campaign_report.h>

namespace plantnbv {
namespace scenario {

/// Writes into `out_dir`, for the main study (the one with baselines, named "main", or
/// else the first): f1_<study>.png and chamfer_<study>.png, one panel per level, one
/// curve per planner; for each other study (the sensitivity studies): f1_<study>.png, a
/// row of level panels per planner, one curve per variant beside the main study's curve
/// of the same planner (dashed). About 1200 px wide. Returns the files written.
/// \throws Error when rendering fails (e.g. no X display: run under xvfb-run).
std::vector<std::filesystem::path>
writeCampaignFigures(const std::vector<CurveRow>& rows,
                     const std::filesystem::path& out_dir);

} // namespace scenario
} // namespace plantnbv
