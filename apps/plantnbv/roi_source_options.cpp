#include "roi_source_options.h"

#include <CLI/CLI.hpp>

namespace plantnbv {
namespace app {

void addRoiSourceOptions(CLI::App& cmd, scenario::RoiSourceOverrides& o,
                         const std::string& seed)
{
  cmd.add_option("--roi-source", o.source,
                 "Where the attended ROI comes from: oracle (the boxes as given; "
                 "default) or noisy (each box moved by a Gaussian error, seeded by " +
                     seed + ")");
  cmd.add_option("--roi-sigma", o.sigma_m,
                 "noisy: standard deviation of each box centre's error per axis, metres");
  cmd.add_option("--roi-scale", o.scale,
                 "noisy: factor on every box's sides (default 1)");
}

} // namespace app
} // namespace plantnbv
