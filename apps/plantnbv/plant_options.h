#pragma once
// The plant options of plant, capture and reconstruct: --seed/--plant, --stage,
// --simplified, --model, --labels, --rois, --keep-frame, --yaw-deg, --base.

#include <string>
#include <vector>

#include <plantnbv/scenario/placed_plant.h>

namespace CLI {
class App;
}

namespace plantnbv {
namespace app {

struct PlantOptions {
  scenario::PlantSource source;
  std::vector<std::string> models; ///< --model, once or more: source.model(_parts)
  std::string up_axis = "file";    ///< --model-up-axis: source.up_axis once checked
  std::vector<double> base{1.0, 0.0, 0.8}; ///< as parsed; source.base once checked
  std::string seed_flag = "--seed";        ///< the option's name, for messages
};

/// Adds the options to a subcommand. `seed_flag` names the plant's seed option: "--seed"
/// for `plant`, "--plant" where --seed seeds something else (capture, reconstruct).
void addPlantOptions(CLI::App& cmd, PlantOptions& options,
                     const std::string& seed_flag = "--seed");

/// The placed plant of the parsed options. \throws InvalidArgumentError naming the
/// option for a missing plant or a --base without three numbers; the errors of
/// scenario::makePlacedPlant.
scenario::PlacedPlant placePlant(const PlantOptions& options);

} // namespace app
} // namespace plantnbv
