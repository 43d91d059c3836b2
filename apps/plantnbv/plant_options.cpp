#include "plant_options.h"

#include <iostream>

#include <CLI/CLI.hpp>

#include <plantnbv/common/error.h>
#include <plantnbv/io/mesh_io.h>

#include "cli_checks.h"

namespace plantnbv {
namespace app {

void addPlantOptions(CLI::App& cmd, PlantOptions& o, const std::string& seed_flag)
{
  o.seed_flag = seed_flag;
  scenario::PlantSource& s = o.source;
  auto* seed =
      cmd.add_option(seed_flag, s.seed,
                     "Generate a tomato plant from this seed (0-9: the default set)")
          ->check(unsignedInteger());
  auto* model = cmd.add_option("--model", o.models,
                               "Load a plant instead: a mesh (.dae .obj .ply .stl .wrl) "
                               "or a scanned cloud (.pcd .ply); repeat it for a plant "
                               "split into several mesh files")
                    ->expected(1)
                    ->take_all();
  seed->excludes(model);
  model->excludes(seed);
  cmd.add_option("--stage", s.stage,
                 "Growth stage in [0, 1] (default: seed/9 for seeds 0-9, else 0.5)")
      ->needs(seed);
  cmd.add_flag("--simplified", s.simplified, "Remove half of the leaflets of every leaf")
      ->needs(seed);
  cmd.add_option("--labels", s.labels,
                 "Part labels from node, geometry or material names, e.g. "
                 "stem=Branch.*,leaflet=Leaf.*,flower=Blossom.*")
      ->needs(model);
  cmd.add_option("--model-scale", s.scale,
                 "Metres per model file unit, e.g. 0.01 for centimetres (default: the "
                 "file's: Collada's <unit>, else metres)")
      ->check(CLI::PositiveNumber)
      ->needs(model);
  cmd.add_option("--model-up-axis", o.up_axis,
                 "The model file's axis that points up: file (Collada's <up_axis>, VRML "
                 "y, other formats z), y (an OBJ exported y up, as Blender's default) or "
                 "z")
      ->capture_default_str()
      ->needs(model);
  cmd.add_option("--rois", s.rois,
                 "Your own ROI file (YAML boxes, world frame), scored as the level "
                 "model_rois");
  auto* keep = cmd.add_flag("--keep-frame", s.keep_frame,
                            "Keep the model file's coordinates (no --base, --yaw-deg)")
                   ->needs(model);
  cmd.add_option("--yaw-deg", s.yaw_deg, "Turn the plant about its stem, degrees")
      ->check(magnitudeAtMost(scenario::kMaxPlantYawDeg, "degrees"))
      ->capture_default_str()
      ->excludes(keep);
  cmd.add_option("--base", o.base, "Plant base position x,y,z in metres (world frame)")
      ->delimiter(',')
      ->capture_default_str()
      ->excludes(keep);
}

scenario::PlacedPlant placePlant(const PlantOptions& o)
{
  if (!o.source.seed && o.models.empty())
    throw InvalidArgumentError("give a plant: " + o.seed_flag +
                               " S (generated) or --model FILE");
  if (o.base.size() != 3)
    throw InvalidArgumentError("--base must be three numbers x,y,z in metres");
  scenario::PlantSource source = o.source;
  try {
    source.up_axis = io::upAxisFromName(o.up_axis);
  } catch (const InvalidArgumentError&) {
    throw InvalidArgumentError("--model-up-axis: expected file, y or z, got '" +
                               o.up_axis + "'");
  }
  if (!o.models.empty()) {
    source.model = o.models.front();
    source.model_parts.assign(o.models.begin() + 1, o.models.end());
  }
  source.base = Eigen::Vector3d(o.base[0], o.base[1], o.base[2]);
  scenario::PlacedPlant placed = scenario::makePlacedPlant(source);
  for (const std::string& w : placed.warnings)
    std::cerr << "plantnbv: warning: " << w << "\n";
  return placed;
}

} // namespace app
} // namespace plantnbv
