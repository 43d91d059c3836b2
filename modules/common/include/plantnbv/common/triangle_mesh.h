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
/// files.
enum class PartLabel : std::uint32_t {
  unknown = 0,
  stem = 1,
  petiole = 2,
  leaflet = 3,
  peduncle = 4,
  fruit = 5,
  background = 6,
};

/// \brief The label's name ("stem", ...). \throws InvalidArgumentError for other values.
const char* partLabelName(PartLabel label);
/// \brief The label named `name`. \throws InvalidArgumentError for unknown names.
PartLabel partLabelFromName(const std::string& name);

/// \brief An indexed triangle mesh.
///
/// `labels` and `node_ids` are either empty or hold one entry per triangle. `node_ids`
/// index `node_names`: the names of the scene-graph nodes or meshes a file gave, kept so
/// that parts can be labelled afterwards by name.
struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;               ///< world frame, metres
  std::vector<std::array<std::uint32_t, 3>> triangles; ///< three indices into `vertices`
  std::vector<PartLabel> labels;       ///< one per triangle, or empty (unlabelled)
  std::vector<std::uint32_t> node_ids; ///< one per triangle (into `node_names`), or empty
  std::vector<std::string> node_names; ///< the file's node or mesh names

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
  /// \brief Appends another mesh (its node names are appended too).
  void append(const TriangleMesh& other);
  /// \brief Checks sizes, indices and finiteness. \throws FormatError naming the defect.
  void validate() const;
};

} // namespace plantnbv
