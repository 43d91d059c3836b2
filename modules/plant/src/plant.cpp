#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Geometry>

#include <plantnbv/common/error.h>
#include <plantnbv/plant/plant.h>
#include <plantnbv/common/portable_math.h>

namespace plantnbv {

Eigen::Vector3d Plant::stemPointAtHeight(double height_m) const
{
  const auto& axis = anatomy.stem_axis;
  if (axis.empty())
    throw InvalidArgumentError("plant '" + name + "' has no stem axis");
  const double z = base_position.z() + height_m;
  if (z <= axis.front().z())
    return axis.front();
  for (std::size_t i = 1; i < axis.size(); ++i)
    if (z <= axis[i].z()) {
      const double dz = axis[i].z() - axis[i - 1].z();
      const double f = dz > 0.0 ? (z - axis[i - 1].z()) / dz : 1.0;
      return (1.0 - f) * axis[i - 1] + f * axis[i];
    }
  return axis.back();
}

void Plant::bounds(Eigen::Vector3f& min, Eigen::Vector3f& max) const
{
  if (mesh.vertices.empty() && scan_points.empty())
    throw InvalidArgumentError("plant '" + name + "' has neither mesh nor scan points");
  min = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  max = -min;
  for (const auto* points : {&mesh.vertices, &scan_points})
    for (const auto& v : *points) {
      min = min.cwiseMin(v);
      max = max.cwiseMax(v);
    }
}

void posePlant(Plant& plant, const Eigen::Vector3d& base_position, double yaw_rad)
{
  if (!base_position.allFinite() || !std::isfinite(yaw_rad)) {
    std::ostringstream s;
    s << "posePlant: base position (" << base_position.transpose() << ") and yaw "
      << yaw_rad << " must be finite";
    throw InvalidArgumentError(s.str());
  }
  // Relative to the current pose: undo it and apply the new one in a single rotation.
  double s, c;
  portableSinCos(yaw_rad - plant.yaw_rad, s, c);
  Eigen::Matrix3d R;
  R << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
  const Eigen::Vector3d old_base = plant.base_position;
  auto point = [&](Eigen::Vector3d& p) { p = base_position + R * (p - old_base); };
  auto direction = [&](Eigen::Vector3d& v) { v = R * v; };

  for (auto* points : {&plant.mesh.vertices, &plant.scan_points})
    for (auto& v : *points) {
      Eigen::Vector3d p = v.cast<double>();
      point(p);
      v = p.cast<float>();
    }
  PlantAnatomy& a = plant.anatomy;
  for (auto& p : a.stem_axis)
    point(p);
  for (auto& leaf : a.leaves) {
    point(leaf.node.position);
    point(leaf.node.stem_point);
    direction(leaf.node.petiole_direction);
    for (auto& p : leaf.axis)
      point(p);
    for (auto& l : leaf.leaflets) {
      point(l.base);
      point(l.tip);
    }
  }
  for (auto& truss : a.trusses) {
    point(truss.attachment);
    for (auto& p : truss.peduncle)
      point(p);
    for (auto& f : truss.fruits)
      point(f.center);
  }
  plant.base_position = base_position;
  plant.yaw_rad = yaw_rad;
}

} // namespace plantnbv
