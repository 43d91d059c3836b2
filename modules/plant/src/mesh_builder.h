#pragma once
// Internal to module plant: appends labelled parts (tubes, spheroids, leaf blades) to a
// TriangleMesh. Vertices are computed in double and stored as float.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <plantnbv/common/triangle_mesh.h>

namespace plantnbv {
namespace plant_detail {

/// cos and sin of 2 pi k / n, k = 0..n-1, from portable trigonometry.
struct RingTable {
  explicit RingTable(int n);
  std::vector<double> cos, sin;
};

/// How a tube ends: open (hidden inside another part), flat disc, or a short cone.
enum class Cap { open, flat, pointed };

class MeshBuilder {
public:
  explicit MeshBuilder(TriangleMesh& mesh) : mesh_(mesh) {}

  /// Every triangle added from now on belongs to the part `name` with `label`.
  void beginPart(PartLabel label, const std::string& name);
  std::uint32_t vertex(const Eigen::Vector3d& p);
  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c);

  /// A generalised cylinder along `axis` (>= 2 distinct points) with `radius` per point,
  /// `segments` around; rings follow a parallel-transport frame so the tube does not
  /// twist. Outward-facing winding.
  /// `normal_hint` orients the first ring (any vector not parallel to the axis start).
  /// Returns the index of the first vertex of the last ring (for capFan).
  /// With `horizontal_rings` every ring lies in a plane z = const (for a near-vertical
  /// axis: the base ring then sits exactly on its z).
  std::uint32_t tube(const std::vector<Eigen::Vector3d>& axis,
                     const std::vector<double>& radius, int segments, Cap start, Cap end,
                     const Eigen::Vector3d& normal_hint = Eigen::Vector3d::UnitZ(),
                     bool horizontal_rings = false);

  /// Closes a ring of `segments` vertices starting at `ring_first` with a fan to `apex`;
  /// `facing_start` flips the winding for a cap at the start of a tube.
  void capFan(std::uint32_t ring_first, int segments, const Eigen::Vector3d& apex,
              bool facing_start);

  /// A spheroid with horizontal semi-axis `radius_xy` and vertical `radius_z`, `rings`
  /// bands from pole to pole and `segments` around. Outward-facing winding.
  void spheroid(const Eigen::Vector3d& center, double radius_xy, double radius_z,
                int rings, int segments);

  std::size_t triangleCount() const { return mesh_.triangles.size(); }

private:
  TriangleMesh& mesh_;
  PartLabel label_ = PartLabel::unknown;
  std::uint32_t node_id_ = 0;
};

} // namespace plant_detail
} // namespace plantnbv
