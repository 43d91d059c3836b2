#pragma once
/// \file plant_scene.h
/// \brief The scene of the paper's experiments: a posed plant (its mesh, or its scan as
/// surfels) on a support over a floor, as a committed sensor scene. The sensor renders
/// any meshes and surfels; this is where a plant becomes them.

#include <memory>
#include <vector>

#include <plantnbv/common/triangle_mesh.h>
#include <plantnbv/plant/plant.h>
#include <plantnbv/sensor/sensor_scene.h>

namespace plantnbv {

/// \brief The surroundings of a plant in the default scene, as the paper's Gazebo world
/// had them: a floor and the support the plant stands on, both labelled `background`.
///
/// Background surfaces matter for the map: a ray that hits the floor beyond the map's
/// maximum range gives a point beyond that range, which OctoMap's insertPointCloud
/// (maxrange) turns into free space up to the maximum range; without a floor the ray
/// would give no point and carve nothing. Set floor and support to false for a plant in
/// empty space.
struct PlantSceneConfig {
  /// A horizontal square at z = floor_height_m centred under the plant. Default true.
  bool floor = true;
  double floor_height_m = 0.0;    ///< metres; default 0 (the paper's floor)
  double floor_half_size_m = 5.0; ///< half the side of the square (metres), > 0
  /// A box under the plant from the floor up to the plant's base (its top face at the
  /// base height, centred on the base), like a table or pedestal; left out when the
  /// base is not above the floor. Default true.
  bool support = true;
  double support_half_width_m = 0.15; ///< half its side in x and y (metres), > 0
  /// How the points of a scanned plant (Plant::scan_points) become surfels.
  SurfelOptions surfels;

  /// \throws InvalidArgumentError naming the first bad field and its value.
  void validate() const;
};

/// \brief Plants beside the scored one, as in a greenhouse row (paper section 5.4): in
/// the scene, where they occlude and are mapped, each on its own support, but neither
/// ground truth nor ROI. Meshes only (posed in the world frame).
using NeighbourPlants = std::vector<std::shared_ptr<const Plant>>;

/// \brief The background makePlantScene puts around `plant`: the floor and the support
/// of `config` (either may be left out), then each neighbour's mesh and support, all
/// labelled `background`.
/// \throws InvalidArgumentError for an invalid config or a neighbour without a mesh (a
/// scan).
std::vector<TriangleMesh> plantSceneBackground(const Plant& plant,
                                               const PlantSceneConfig& config = {},
                                               const NeighbourPlants& neighbours = {});

/// \brief The scene of a plant as the paper's experiments had it: the plant (its mesh,
/// or its scan points as surfels when it has no mesh) where it is posed, plus the floor
/// and the support of `config` (centred under Plant::base_position) and the neighbours
/// (plantSceneBackground). Committed, with `threads` for the BVH build (0: all cores).
/// \throws InvalidArgumentError for an invalid config or a plant with neither mesh nor
/// scan points; FormatError for a malformed mesh.
SensorScene::Ptr makePlantScene(const Plant& plant, const PlantSceneConfig& config = {},
                                unsigned int threads = 0,
                                const NeighbourPlants& neighbours = {});

} // namespace plantnbv
