#pragma once
// Where the attention ROI comes from, the same options in reconstruct and plan:
// --roi-source, --roi-sigma, --roi-scale, --prior-internode, --detections-explore-views;
// in reconstruct also the simulated detector's.

#include <nlohmann/json_fwd.hpp>

#include <plantnbv/scenario/trial_setup.h>

namespace CLI {
class App;
}

namespace plantnbv {

class Roi;

namespace app {

/// What the attended ROI is made from.
enum class RoiSourceInput {
  simulation, ///< a trial: the plant's true boxes and a simulated detector's finds
  roi_file,   ///< plan: the --roi boxes (for detections, a fused ROI file) and the map
};

/// Adds the options to a subcommand; `seed` names what seeds the noisy draw. With
/// `simulation`, also the simulated detector's (--detector-recall, ...).
void addRoiSourceOptions(CLI::App& cmd, scenario::RoiSourceOverrides& options,
                         const std::string& seed, RoiSourceInput input);

/// The boxes of an ROI as JSON, [{name, center, size}], as summary.json's `attended_roi`
/// and `plan --json` give them.
nlohmann::json roiBoxesJson(const Roi& roi);

} // namespace app
} // namespace plantnbv
