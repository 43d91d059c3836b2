#pragma once
/// \file triangle_mesh.h
/// \brief The one triangle mesh type of plantnbv: vertices in metres in the world frame
/// (Z up), triangles, and per-triangle part labels and source node names.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace plantnbv {

/// \brief What a surface is part of. Stored as `label` in pcl::PointXYZL and in PLY
/// files. The values are kept across versions (a new label takes the next value).
enum class PartLabel : std::uint32_t {
  unknown = 0,
  stem = 1,       ///< main stem and side shoots
  petiole = 2,    ///< leaf stalks and the rachis between leaflets
  leaflet = 3,    ///< leaf blades
  peduncle = 4,   ///< truss stalks and fruit pedicels
  fruit = 5,      ///< fruits, with the calyx (sepals) that stays on a fruit
  background = 6, ///< floor, support, walls: not the plant
  flower = 7,     ///< blossoms and buds: petals, their sepals (calyx) and anthers
};

/// \brief The largest PartLabel value: labels above it are not ours.
constexpr PartLabel kLastPartLabel = PartLabel::flower;

/// \brief True for the labels of plant organs (stem to fruit, flower): not unknown, not
/// background, not a value beyond kLastPartLabel.
bool isPlantPart(std::uint32_t label);

/// \brief The label's name ("stem", ...). \throws InvalidArgumentError for other values.
const char* partLabelName(PartLabel label);
/// \brief The label named `name`. \throws InvalidArgumentError for unknown names.
PartLabel partLabelFromName(const std::string& name);

/// \brief An indexed triangle mesh.
///
/// `labels` and `node_ids` are either empty or hold one entry per triangle. `node_ids`
/// index `node_names`: the names of the scene-graph nodes or meshes a file gave, kept so
/// that parts can be labelled afterwards by name. `geometry_names` and `material_names`
/// are either empty or parallel to `node_names`: entry i names the geometry (mesh) and
/// the material of the triangles with node id i ("" where the file gives none), as
/// modelling tools that export parts only as materials need.
struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;               ///< world frame, metres
  std::vector<std::array<std::uint32_t, 3>> triangles; ///< three indices into `vertices`
  std::vector<PartLabel> labels;       ///< one per triangle, or empty (unlabelled)
  std::vector<std::uint32_t> node_ids; ///< one per triangle (into `node_names`), or empty
  std::vector<std::string> node_names; ///< the file's node or mesh names
  std::vector<std::string> geometry_names; ///< per node id: its geometry's name, or empty
  std::vector<std::string> material_names; ///< per node id: its material's name, or empty

  /// \brief The number of triangles.
  std::size_t size() const { return triangles.size(); }
  /// \brief True if the mesh has no triangle.
  bool empty() const { return triangles.empty(); }
  /// \brief True if the triangles carry part labels.
  bool hasLabels() const { return !labels.empty(); }

  /// \brief The triangle's area in square metres.
  double triangleArea(std::size_t t) const;
  /// \brief Axis-aligned bounds of the vertices. \throws InvalidArgumentError when empty.
  void bounds(Eigen::Vector3f& min, Eigen::Vector3f& max) const;
  /// \brief The names a triangle with node id `id` carries: node, geometry and material
  /// name ("" where there is none).
  std::array<std::string, 3> namesOf(std::uint32_t id) const;
  /// \brief Appends another mesh (its node, geometry and material names are appended
  /// too).
  void append(const TriangleMesh& other);
  /// \brief Checks sizes, indices and finiteness. \throws FormatError naming the defect.
  void validate() const;
};

} // namespace plantnbv
