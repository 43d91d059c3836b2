#pragma once
// Where the attention ROI comes from, the same options in reconstruct and plan:
// --roi-source, --roi-sigma, --roi-scale; in reconstruct also the simulated detector's.

#include <plantnbv/scenario/trial_setup.h>

namespace CLI {
class App;
}

namespace plantnbv {
namespace app {

/// Adds the options to a subcommand; `seed` names what seeds the noisy draw. With
/// `simulated_detector`, also the simulated detector's (--detector-recall,
/// --detector-false-positives) and the detections source.
void addRoiSourceOptions(CLI::App& cmd, scenario::RoiSourceOverrides& options,
                         const std::string& seed, bool simulated_detector);

} // namespace app
} // namespace plantnbv
