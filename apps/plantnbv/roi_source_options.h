#pragma once
// Where the attention ROI comes from, the same options in reconstruct and plan:
// --roi-source, --roi-sigma, --roi-scale.

#include <plantnbv/scenario/trial_setup.h>

namespace CLI {
class App;
}

namespace plantnbv {
namespace app {

/// Adds the options to a subcommand; `seed` names what seeds the noisy draw.
void addRoiSourceOptions(CLI::App& cmd, scenario::RoiSourceOverrides& options,
                         const std::string& seed);

} // namespace app
} // namespace plantnbv
