#include "synthetic_plant.h"

#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include <plantnbv/common/random.h>

namespace plantnbv {
namespace test {

namespace {

/// Appends a tube of `segments` around the polyline `axis` (radius per vertex).
void addTube(TriangleMesh& m, const std::vector<Eigen::Vector3d>& axis,
             const std::vector<double>& radius, int segments, PartLabel label,
             const std::string& name)
{
  TriangleMesh part;
  for (std::size_t i = 0; i < axis.size(); ++i) {
    const Eigen::Vector3d dir =
        (axis[std::min(i + 1, axis.size() - 1)] - axis[i > 0 ? i - 1 : 0]).normalized();
    const Eigen::Vector3d u = dir.unitOrthogonal(), v = dir.cross(u);
    for (int s = 0; s < segments; ++s) {
      const double a = 2.0 * M_PI * s / segments;
      part.vertices.push_back(
          (axis[i] + radius[i] * (std::cos(a) * u + std::sin(a) * v)).cast<float>());
    }
  }
  for (std::uint32_t i = 0; i + 1 < axis.size(); ++i)
    for (std::uint32_t s = 0; s < static_cast<std::uint32_t>(segments); ++s) {
      const std::uint32_t n = segments, s1 = (s + 1) % n;
      part.triangles.push_back({i * n + s, i * n + s1, (i + 1) * n + s});
      part.triangles.push_back({i * n + s1, (i + 1) * n + s1, (i + 1) * n + s});
    }
  part.labels.assign(part.triangles.size(), label);
  part.node_names = {name};
  part.node_ids.assign(part.triangles.size(), 0);
  m.append(part);
}

/// Appends a curved elliptic leaflet (a single surface) centred at `base` along `dir`.
void addLeaflet(TriangleMesh& m, const Eigen::Vector3d& base, const Eigen::Vector3d& dir,
                double length, double width, double droop, int detail,
                const std::string& name)
{
  TriangleMesh part;
  const Eigen::Vector3d side = dir.cross(Eigen::Vector3d::UnitZ()).normalized();
  const int nu = detail, nv = std::max(4, detail / 3);
  for (int i = 0; i <= nu; ++i) {
    const double t = static_cast<double>(i) / nu;
    const double half_width = 0.5 * width * std::sin(M_PI * t);
    for (int j = 0; j <= nv; ++j) {
      const double w = (2.0 * j / nv - 1.0) * half_width;
      const Eigen::Vector3d p = base + t * length * dir + w * side -
                                droop * t * t * Eigen::Vector3d::UnitZ() +
                                0.2 * std::abs(w) * Eigen::Vector3d::UnitZ();
      part.vertices.push_back(p.cast<float>());
    }
  }
  const std::uint32_t row = nv + 1;
  for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(nu); ++i)
    for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(nv); ++j) {
      part.triangles.push_back({i * row + j, (i + 1) * row + j, i * row + j + 1});
      part.triangles.push_back(
          {i * row + j + 1, (i + 1) * row + j, (i + 1) * row + j + 1});
    }
  part.labels.assign(part.triangles.size(), PartLabel::leaflet);
  part.node_names = {name};
  part.node_ids.assign(part.triangles.size(), 0);
  m.append(part);
}

void addSphere(TriangleMesh& m, const Eigen::Vector3d& c, double r, int detail,
               const std::string& name)
{
  std::vector<Eigen::Vector3d> axis;
  std::vector<double> radius;
  const int rings = std::max(6, detail / 2);
  for (int i = 0; i <= rings; ++i) {
    const double phi = M_PI * (0.02 + 0.96 * i / rings); // leave tiny caps open
    axis.push_back(c - r * std::cos(phi) * Eigen::Vector3d::UnitZ());
    radius.push_back(r * std::sin(phi));
  }
  addTube(m, axis, radius, detail, PartLabel::fruit, name);
}

} // namespace

TriangleMesh makeSyntheticPlant(const SyntheticPlantConfig& config)
{
  Rng rng(config.seed);
  TriangleMesh mesh;
  const int d = std::max(6, config.detail);

  std::vector<Eigen::Vector3d> stem;
  std::vector<double> stem_radius;
  const int stem_rings = 4 * d;
  for (int i = 0; i <= stem_rings; ++i) {
    const double z = config.stem_height_m * i / stem_rings;
    stem.emplace_back(0.01 * std::sin(3.0 * z), 0.0, z); // slightly curved
    stem_radius.push_back(config.stem_radius_m * (1.0 - 0.3 * z / config.stem_height_m));
  }
  addTube(mesh, stem, stem_radius, d, PartLabel::stem, "stem");

  for (int l = 0; l < config.leaves; ++l) {
    const double z = config.stem_height_m * (0.15 + 0.8 * l / std::max(1, config.leaves));
    const double yaw = l * 137.5 * M_PI / 180.0;
    const Eigen::Vector3d dir(std::cos(yaw), std::sin(yaw), 0.0);
    const Eigen::Vector3d node(0.01 * std::sin(3.0 * z), 0.0, z);
    const double length = rng.uniform(0.15, 0.25);
    std::vector<Eigen::Vector3d> petiole;
    std::vector<double> petiole_radius;
    for (int i = 0; i <= d; ++i) {
      const double t = static_cast<double>(i) / d;
      petiole.push_back(node + t * length * dir +
                        0.05 * t * (1.0 - t) * Eigen::Vector3d::UnitZ());
      petiole_radius.push_back(0.0025);
    }
    addTube(mesh, petiole, petiole_radius, std::max(6, d / 3), PartLabel::petiole,
            "petiole_" + std::to_string(l));
    for (int k = 0; k < config.leaflets_per_leaf; ++k) {
      const double t = (k + 1.0) / config.leaflets_per_leaf;
      const double side =
          (k % 2 ? 1.0 : -1.0) * (k + 1 == config.leaflets_per_leaf ? 0.0 : 1.0);
      const Eigen::Vector3d across = dir.cross(Eigen::Vector3d::UnitZ());
      const Eigen::Vector3d leaflet_dir = (dir + 1.2 * side * across).normalized();
      addLeaflet(
          mesh, node + t * length * dir + 0.05 * t * (1.0 - t) * Eigen::Vector3d::UnitZ(),
          leaflet_dir, rng.uniform(0.04, 0.08), rng.uniform(0.02, 0.035),
          rng.uniform(0.0, 0.02), d,
          "leaflet_" + std::to_string(l) + "_" + std::to_string(k));
    }
  }

  for (int f = 0; f < config.fruits; ++f) {
    const double yaw = (f * 137.5 + 60.0) * M_PI / 180.0;
    const double z = config.stem_height_m * (0.3 + 0.15 * f);
    addSphere(mesh, Eigen::Vector3d(0.06 * std::cos(yaw), 0.06 * std::sin(yaw), z),
              rng.uniform(0.015, 0.025), d, "fruit_" + std::to_string(f));
  }
  return mesh;
}

} // namespace test
} // namespace plantnbv
