#pragma once
// Shared by the planning tests: a plant map built with the simulated sensor (once per
// test process), fixed-candidate samplers and small helpers.

#include <cmath>
#include <memory>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/experiment/plant_scene.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/planning/cylindrical_sector_sampler.h>
#include <plantnbv/planning/viewpoint_sampler.h>
#include <plantnbv/plant/plant_rois.h>
#include <plantnbv/plant/tomato_plant_generator.h>
#include <plantnbv/sensor/simulated_depth_sensor.h>

namespace plantnbv {
namespace test {

/// The paper's v0 (Table 1).
inline Viewpoint paperV0()
{
  return Pose::fromXyzQuat(0.646, 0.353, 1.383, 0.0, 0.0, -0.383, 0.924);
}

/// A camera at `position` looking horizontally along azimuth `yaw_rad`.
inline Viewpoint lookingAlong(const Eigen::Vector3d& position, double yaw_rad)
{
  return Viewpoint(position, Eigen::Quaterniond(Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ())));
}

/// A plant (default plant 5) posed at the paper's (1, 0, 0.8), and its scene.
struct PlantWorld {
  Plant plant;
  SensorScene::Ptr scene;
};

inline const PlantWorld& plantWorld()
{
  static const PlantWorld world = [] {
    PlantWorld w;
    w.plant = TomatoPlantGenerator(defaultPlantConfig(5)).generate();
    posePlant(w.plant, Eigen::Vector3d(1.0, 0.0, 0.8), 0.0);
    w.scene = makePlantScene(w.plant);
    return w;
  }();
  return world;
}

/// Inserts the view of the plant scene from `view` (L515 at 320 x 240).
inline void insertView(OccupancyMap& map, const Viewpoint& view)
{
  SimulatedDepthSensor sensor(CameraIntrinsics::l515(L515Mode::qvga_320x240));
  sensor.setScene(plantWorld().scene);
  CloudXYZL cloud;
  sensor.capture(view, cloud);
  map.insert(cloud, view.position);
}

/// The map after v0 and one view from the sector (built once).
inline std::shared_ptr<const OccupancyMap> plantMap()
{
  static const std::shared_ptr<const OccupancyMap> map = [] {
    auto m = std::make_shared<OccupancyMap>();
    insertView(*m, paperV0());
    CylindricalSectorSampler sampler;
    insertView(*m, sampler.viewpointAt(sampler.getSector().facingAzimuth() + 0.3, 1.2));
    return m;
  }();
  return map;
}

/// A sampler that always returns the same candidates.
class FixedSampler : public ViewpointSampler {
public:
  explicit FixedSampler(std::vector<Viewpoint> views) : views_(std::move(views)) {}
  void sample(Rng& /*rng*/, std::vector<Viewpoint>& out) const override { out = views_; }

private:
  std::vector<Viewpoint> views_;
};

} // namespace test
} // namespace plantnbv
