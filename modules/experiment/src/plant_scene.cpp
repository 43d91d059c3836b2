#include <cmath>
#include <sstream>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/plant_scene.h>

namespace plantnbv {

namespace {

void requirePositive(double value, const char* name)
{
  if (!(std::isfinite(value) && value > 0.0)) {
    std::ostringstream s;
    s << "PlantSceneConfig::" << name << " = " << value << " must be finite and > 0";
    throw InvalidArgumentError(s.str());
  }
}

} // namespace

void PlantSceneConfig::validate() const
{
  if (!std::isfinite(floor_height_m))
    throw InvalidArgumentError("PlantSceneConfig::floor_height_m must be finite");
  requirePositive(floor_half_size_m, "floor_half_size_m");
  requirePositive(support_half_width_m, "support_half_width_m");
  surfels.validate();
}

std::vector<TriangleMesh> plantSceneBackground(const Plant& plant,
                                               const PlantSceneConfig& config,
                                               const NeighbourPlants& neighbours)
{
  config.validate();
  std::vector<TriangleMesh> parts;
  const Eigen::Vector3d& base = plant.base_position;
  if (config.floor)
    parts.push_back(
        floorMesh(config.floor_height_m, config.floor_half_size_m, base.head<2>()));
  auto addSupport = [&](const Eigen::Vector3d& b) {
    if (config.support && b.z() > config.floor_height_m)
      parts.push_back(supportMesh(b, config.support_half_width_m, config.floor_height_m));
  };
  addSupport(base);
  for (const auto& neighbour : neighbours) {
    if (!neighbour || neighbour->mesh.empty())
      throw InvalidArgumentError(
          "plant scene: a neighbour plant needs a mesh (" +
          std::string(neighbour ? "'" + neighbour->name + "' is a scan" : "null") + ")");
    TriangleMesh mesh = neighbour->mesh;
    mesh.labels.assign(mesh.size(), PartLabel::background);
    parts.push_back(std::move(mesh));
    addSupport(neighbour->base_position);
  }
  return parts;
}

SensorScene::Ptr makePlantScene(const Plant& plant, const PlantSceneConfig& config,
                                unsigned int threads, const NeighbourPlants& neighbours)
{
  config.validate();
  auto scene = std::make_shared<SensorScene>();
  if (!plant.mesh.empty())
    scene->addMesh(plant.mesh, PartLabel::unknown);
  else if (!plant.scan_points.empty())
    scene->addSurfels(plant.scan_points, plant.scan_labels, config.surfels);
  else
    throw InvalidArgumentError("makePlantScene: plant '" + plant.name +
                               "' has neither mesh nor scan points");
  for (const TriangleMesh& part : plantSceneBackground(plant, config, neighbours))
    scene->addMesh(part, PartLabel::background);
  scene->setNumberOfThreads(threads);
  scene->commit();
  return scene;
}

} // namespace plantnbv
