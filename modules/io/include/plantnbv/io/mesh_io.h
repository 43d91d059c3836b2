#pragma once
/// \file mesh_io.h
/// \brief Reading triangle meshes into `TriangleMesh` (metres, Z up) and writing them as
/// binary PLY with a per-face `label`.
///
/// Formats: PLY (our own reader: it keeps a face `label` property, which Assimp drops),
/// OBJ, STL and Collada .dae (Assimp 5.2), VRML97 .wrl/.vrml (our own reader: VTK 9.1's
/// vtkVRMLImporter ignores Transform rotations, and Debian's Assimp 5.2 cannot read
/// VRML). Polygons are triangulated as fans; points and lines are ignored.
///
/// Units: Collada's `<unit meter="...">` is honoured (applied once: Assimp's own unit
/// scale on the root node is replaced by ours); other formats carry no unit and are read
/// as metres. `MeshLoadOptions::scale`, when set, replaces the file's unit.
///
/// Up axis: Collada's `<up_axis>` is honoured (X_UP, Y_UP, Z_UP; Y_UP when absent, as the
/// Collada spec says); VRML is Y up by the VRML97 convention; the other formats are taken
/// as Z up. `MeshLoadOptions::up_axis`, when set, replaces the file's up axis. A Y-up
/// file is rotated by +90 degrees about X: file (x, y, z) becomes (x, -z, y).
///
/// Node names: each triangle keeps a name (`TriangleMesh::node_ids` / `node_names`,
/// equal names share one id), for labelling parts by name afterwards:
/// - Collada: the node's `name` attribute, else its `id`; OBJ: the object or group name;
///   STL: the `solid` name (Assimp's node name, else the mesh name);
/// - VRML: the nearest DEF name on the way up from the geometry (the geometry node, its
///   Shape, then the enclosing Transforms and Groups), else "shape_<k>" (k counts the
///   Shapes from 0 in the order they are met; a USEd Shape counts again);
/// - PLY: none (`node_ids` stays empty).
///
/// Geometry and material names (`TriangleMesh::geometry_names`, `material_names`; a
/// distinct (node, geometry, material) triple gets its own node id), for files whose
/// parts are named only there (3ds Max exports name parts by material):
/// - Collada: the `<geometry>`'s name (else its id) and the `<material>`'s name (else
///   its id); OBJ: the `usemtl` name; STL: none;
/// - VRML: the geometry node's DEF name and the DEF name of the Shape's Material, else
///   of its Appearance.
///
/// VRML support covers what plant models use: Transform (full VRML97 matrix), Group,
/// Collision, Anchor, Billboard (as a Group), Switch, LOD (first level), Shape with
/// IndexedFaceSet, Box, Cylinder, Cone, Sphere, DEF/USE. PROTO instances and Inline are
/// skipped (the "no triangles" error names them).
///
/// Thread safety: the functions keep no state; concurrent calls are safe.

#include <string>

#include <Eigen/Core>

#include <plantnbv/common/triangle_mesh.h>
#include <plantnbv/io/input_limits.h>

namespace plantnbv {
namespace io {

/// \brief How loadMesh() reads a file's axes and units into metres, z up.
struct MeshLoadOptions {
  /// \brief The file axis that points up (it becomes our z).
  enum class UpAxis {
    from_file, ///< as the file says (see up_axis)
    y,         ///< the file's y axis
    z,         ///< the file's z axis
  };
  /// Which file axis points up; from_file = Collada's `<up_axis>`, Y for VRML, Z for the
  /// other formats.
  UpAxis up_axis = UpAxis::from_file;
  /// Metres per file unit; 0 = from the file (Collada `<unit>`, 1 for the other formats).
  /// A non-zero value replaces the file's unit (it does not multiply it).
  double scale = 0.0;
  /// Caps on the file size, vertices and triangles (input_limits.h); by default the
  /// process-wide defaultInputLimits() when the options are made.
  InputLimits limits = defaultInputLimits();
};

/// \brief The up axis named as tools and files name it: "file" (from_file), "y" or "z".
/// \throws InvalidArgumentError naming the accepted names otherwise.
MeshLoadOptions::UpAxis upAxisFromName(const std::string& name);

/// \brief The name upAxisFromName reads back.
const char* upAxisName(MeshLoadOptions::UpAxis axis);

/// \brief The rotation loadMesh applies for an up axis given in MeshLoadOptions, into
/// z up: y turns (x, y, z) into (x, -z, y); z and from_file (whose rule depends on the
/// format, and is z for a cloud) are the identity. For points read otherwise, e.g. a
/// scanned cloud, to turn them as a mesh would be.
Eigen::Matrix3d upAxisRotation(MeshLoadOptions::UpAxis axis);

/// \brief What loadMesh made of a file's unit, so a caller can say it.
struct MeshFileUnits {
  bool can_declare_unit = false; ///< the format has a unit element (Collada)
  bool unit_declared = false;    ///< the file declares one (`<unit meter="...">`)
  double metres_per_unit = 1.0;  ///< the scale applied (MeshLoadOptions::scale if set)
};

/// \brief Reads a mesh (the format from the extension, case-insensitive). Degenerate
/// faces are kept (they carry zero area). A PLY face `label` (any integer type) fills
/// `TriangleMesh::labels`.
/// \throws IoError if the file is missing or unreadable; FormatError naming the file if
/// it cannot be parsed, holds no triangles, has a non-finite (NaN or infinite) vertex
/// coordinate (the message names the vertex) or a PLY label outside PartLabel, exceeds
/// a cap of the limits (the message names it), or the extension is unknown (the message
/// names it and the accepted ones); InvalidArgumentError for a negative or non-finite
/// scale. `units`, when given, receives what was made of the file's unit.
TriangleMesh loadMesh(const std::string& path, const MeshLoadOptions& options = {},
                      MeshFileUnits* units = nullptr);

/// \brief The checks loadMesh makes on a Collada file's text before Assimp reads it:
/// node graphs (cycles through `<instance_node>`, nesting, expansion), arrays, accessors
/// and index lists that Assimp 5.2.5 would loop on, crash on or read outside of
/// (docs/reliability.md). \throws FormatError naming `path` and the line.
void checkColladaText(const std::string& path, const std::string& text);

/// \brief Writes a binary little-endian PLY: vertex x y z (float), face vertex_indices
/// (uchar count, uint indices) and, when the mesh has labels, face `label` (uint). Node
/// names are not written. loadMesh reads the file back exactly.
/// \throws IoError if the file cannot be written; FormatError if the mesh is invalid
/// (TriangleMesh::validate).
void saveMeshPly(const std::string& path, const TriangleMesh& mesh);

} // namespace io
} // namespace plantnbv
