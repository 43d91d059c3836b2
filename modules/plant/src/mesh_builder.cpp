#include "mesh_builder.h"

#include <cmath>

#include <Eigen/Geometry>

#include <plantnbv/common/portable_math.h>

namespace plantnbv {
namespace plant_detail {

RingTable::RingTable(int n) : cos(n), sin(n)
{
  for (int k = 0; k < n; ++k)
    portableSinCos(2.0 * M_PI * k / n, sin[k], cos[k]);
}

void MeshBuilder::beginPart(PartLabel label, const std::string& name)
{
  label_ = label;
  node_id_ = static_cast<std::uint32_t>(mesh_.node_names.size());
  mesh_.node_names.push_back(name);
}

std::uint32_t MeshBuilder::vertex(const Eigen::Vector3d& p)
{
  mesh_.vertices.push_back(p.cast<float>());
  return static_cast<std::uint32_t>(mesh_.vertices.size() - 1);
}

void MeshBuilder::triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c)
{
  mesh_.triangles.push_back({a, b, c});
  mesh_.labels.push_back(label_);
  mesh_.node_ids.push_back(node_id_);
}

namespace {

/// A unit vector perpendicular to unit `t`, preferring the direction of `hint`.
Eigen::Vector3d perpendicular(const Eigen::Vector3d& t, const Eigen::Vector3d& hint)
{
  Eigen::Vector3d n = hint - hint.dot(t) * t;
  if (n.squaredNorm() < 1e-12)
    n = t.unitOrthogonal();
  return n.normalized();
}

} // namespace

std::uint32_t MeshBuilder::tube(const std::vector<Eigen::Vector3d>& axis,
                                const std::vector<double>& radius, int segments,
                                Cap start, Cap end, const Eigen::Vector3d& normal_hint,
                                bool horizontal_rings)
{
  const std::size_t n = axis.size();
  const RingTable ring(segments);
  const std::uint32_t first = static_cast<std::uint32_t>(mesh_.vertices.size());
  const auto seg = static_cast<std::uint32_t>(segments);
  Eigen::Vector3d t_first = Eigen::Vector3d::UnitZ(), t_last = t_first, normal = t_first;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d t =
        (axis[i + 1 < n ? i + 1 : i] - axis[i > 0 ? i - 1 : 0]).normalized();
    const Eigen::Vector3d plane = horizontal_rings ? Eigen::Vector3d::UnitZ() : t;
    // Parallel transport: the previous normal projected onto this ring's plane.
    normal = perpendicular(plane, i == 0 ? normal_hint : normal);
    const Eigen::Vector3d binormal = plane.cross(normal);
    for (int k = 0; k < segments; ++k)
      vertex(axis[i] + radius[i] * (ring.cos[k] * normal + ring.sin[k] * binormal));
    if (i == 0)
      t_first = t;
    t_last = t;
  }
  for (std::uint32_t i = 0; i + 1 < n; ++i)
    for (std::uint32_t k = 0; k < seg; ++k) {
      const std::uint32_t k1 = (k + 1) % seg;
      const std::uint32_t a = first + i * seg + k, b = first + i * seg + k1;
      const std::uint32_t c = a + seg, d = b + seg;
      triangle(a, b, c);
      triangle(b, d, c);
    }
  const std::uint32_t last_ring = first + static_cast<std::uint32_t>(n - 1) * seg;
  if (horizontal_rings)
    t_first = Eigen::Vector3d::UnitZ(); // a flat base cap stays in its plane
  // A flat cap has its apex in the ring's plane; a pointed one 1.2 radii out.
  if (start != Cap::open)
    capFan(first, segments,
           axis.front() - (start == Cap::pointed ? 1.2 * radius.front() : 0.0) * t_first,
           true);
  if (end != Cap::open)
    capFan(last_ring, segments,
           axis.back() + (end == Cap::pointed ? 1.2 * radius.back() : 0.0) * t_last,
           false);
  return last_ring;
}

void MeshBuilder::capFan(std::uint32_t ring_first, int segments,
                         const Eigen::Vector3d& apex, bool facing_start)
{
  const auto seg = static_cast<std::uint32_t>(segments);
  const std::uint32_t tip = vertex(apex);
  for (std::uint32_t k = 0; k < seg; ++k) {
    const std::uint32_t a = ring_first + k, b = ring_first + (k + 1) % seg;
    if (facing_start)
      triangle(tip, b, a);
    else
      triangle(tip, a, b);
  }
}

void MeshBuilder::spheroid(const Eigen::Vector3d& c, double radius_xy, double radius_z,
                           int rings, int segments)
{
  const RingTable around(segments);
  const auto seg = static_cast<std::uint32_t>(segments);
  const std::uint32_t bottom = vertex(c - radius_z * Eigen::Vector3d::UnitZ());
  const std::uint32_t first = static_cast<std::uint32_t>(mesh_.vertices.size());
  for (int i = 1; i < rings; ++i) {
    double s, co; // polar angle from the bottom pole
    portableSinCos(M_PI * i / rings, s, co);
    for (int k = 0; k < segments; ++k)
      vertex(c + Eigen::Vector3d(radius_xy * s * around.cos[k],
                                 radius_xy * s * around.sin[k], -radius_z * co));
  }
  const std::uint32_t top = vertex(c + radius_z * Eigen::Vector3d::UnitZ());
  for (std::uint32_t k = 0; k < seg; ++k)
    triangle(bottom, first + (k + 1) % seg, first + k);
  for (std::uint32_t i = 0; i + 2 < static_cast<std::uint32_t>(rings); ++i)
    for (std::uint32_t k = 0; k < seg; ++k) {
      const std::uint32_t k1 = (k + 1) % seg;
      const std::uint32_t a = first + i * seg + k, b = first + i * seg + k1;
      triangle(a, b, a + seg);
      triangle(b, b + seg, a + seg);
    }
  const std::uint32_t last = first + static_cast<std::uint32_t>(rings - 2) * seg;
  for (std::uint32_t k = 0; k < seg; ++k)
    triangle(top, last + k, last + (k + 1) % seg);
}

} // namespace plant_detail
} // namespace plantnbv
