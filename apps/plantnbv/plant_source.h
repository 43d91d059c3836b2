#pragma once
// The plant a tool works on: a generated tomato plant (--seed) or a mesh file (--model),
// placed in the world as the paper's scene does. Shared by plant, capture, reconstruct.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <plantnbv/common/box.h>
#include <plantnbv/plant/plant.h>

namespace CLI {
class App;
}

namespace plantnbv {
namespace app {

struct PlantSourceOptions {
  std::optional<std::uint64_t> seed;
  std::string seed_flag = "--seed"; ///< the option's name, for messages
  std::optional<double> stage;
  bool simplified = false;
  std::string model;
  std::string labels;
  std::string rois;
  bool keep_frame = false;
  double yaw_deg = 0.0;
  std::vector<double> base{1.0, 0.0, 0.8}; // Table 1 of the paper
};

/// Adds --seed/--stage/--simplified, --model/--labels/--rois/--keep-frame, --yaw-deg and
/// --base to a subcommand. `seed_flag` names the plant's seed option: "--seed" for
/// `plant`, "--plant" where --seed seeds something else (capture, reconstruct).
void addPlantSourceOptions(CLI::App& cmd, PlantSourceOptions& options,
                           const std::string& seed_flag = "--seed");

/// A plant with the ROIs it comes with, placed in the world frame.
struct PlacedPlant {
  Plant plant;
  /// Named ROIs in the world frame: whole_plant, main_stem, leaf_nodes, fruits for a
  /// generated plant; whole_plant (the bounding box) and those of --rois for a model.
  std::vector<std::pair<std::string, Roi>> rois;
  std::string description; ///< e.g. "seed 3, growth stage 0.333"
};

/// Generates or loads the plant and places it: base at --base, turned by --yaw-deg about
/// its stem (a model: the centre of its bounding box's bottom face is the base, unless
/// --keep-frame). \throws plantnbv::Error on bad options or files.
PlacedPlant makePlacedPlant(const PlantSourceOptions& options);

} // namespace app
} // namespace plantnbv
