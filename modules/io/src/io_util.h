#pragma once
// Internal helpers shared by the io sources (not installed).

#include <array>
#include <cstdint>
#include <istream>
#include <map>
#include <string>

#include <Eigen/Core>

#include <plantnbv/common/file_io.h>
#include <plantnbv/common/triangle_mesh.h>
#include <plantnbv/io/input_limits.h>

namespace plantnbv {
namespace io {
namespace detail {

/// The node ids of a mesh being read: one per distinct (node, geometry, material) name
/// triple, appended to the mesh's node_names, geometry_names and material_names.
class MeshNameIds {
public:
  /// The id of `names` in `mesh`, added on first sight.
  std::uint32_t idOf(const std::array<std::string, 3>& names, TriangleMesh& mesh)
  {
    const auto [it, added] =
        ids_.emplace(names, static_cast<std::uint32_t>(mesh.node_names.size()));
    if (added) {
      mesh.node_names.push_back(names[0]);
      mesh.geometry_names.push_back(names[1]);
      mesh.material_names.push_back(names[2]);
    }
    return it->second;
  }

private:
  std::map<std::array<std::string, 3>, std::uint32_t> ids_;
};

/// Throws FormatError naming the path and the cap if the file is larger than
/// limits.max_file_bytes (checked before the file is read).
void checkFileSize(const std::string& path, const InputLimits& limits);

/// Throws FormatError "<path>: <count> <what> exceed the limit of <cap>
/// (InputLimits::<cap_name>)" when cap > 0 and count > cap.
void checkLimit(const std::string& path, std::uint64_t count, const char* what,
                std::uint64_t cap, const char* cap_name);

/// Reads a whole file into a string, refusing one over limits.max_file_bytes.
/// \throws IoError, FormatError.
std::string readFileToString(const std::string& path, const InputLimits& limits);

/// Reads one line of a text header (without its "\n" or "\r\n"); false at the end of
/// the file. \throws FormatError for a line over 4096 characters (binary data, not a
/// header), so that a wrong file is not read whole into memory.
bool readHeaderLine(const std::string& path, std::istream& in, std::string& line);

/// Whether `file` is a relative path that stays inside its folder (not absolute, no
/// ".." part): what a file list or a detection file may name.
bool staysInside(const std::string& file);

/// True on little-endian hosts (all we build for, but files are written portably).
bool hostIsLittleEndian();

/// Which file axis points up, after options and file conventions are combined.
enum class Up { x, y, z };

/// The rotation that takes a file whose up axis is `up` into our Z-up frame. Follows
/// Collada's axis table: Y_UP (x right, y up, z toward the viewer) maps (x, y, z) to
/// (x, -z, y); X_UP (-y right, x up, z toward the viewer) maps (x, y, z) to (-y, -z, x).
Eigen::Matrix3d upToZ(Up up);

/// Our PLY mesh reader (ply_mesh.cpp). Refuses more vertices than limits.max_points from
/// the header, and stops with FormatError as soon as the file holds more than
/// limits.max_triangles triangles, before allocating for them.
TriangleMesh readPlyMesh(const std::string& path, const InputLimits& limits);

/// Our VRML97 reader (vrml_import.cpp): geometry in file units and axes (Y up).
TriangleMesh readVrml(const std::string& path, const InputLimits& limits);

/// The "path: " prefix of every message about a file.
inline std::string where(const std::string& path)
{
  return path + ": ";
}

} // namespace detail
} // namespace io
} // namespace plantnbv
