#pragma once
// Internal helpers shared by the io sources (not installed).

#include <cstdint>
#include <istream>
#include <string>

#include <Eigen/Core>

#include <plantnbv/common/triangle_mesh.h>

namespace plantnbv {
namespace io {
namespace detail {

/// Throws IoError naming the path unless it names a readable regular file.
void requireReadableFile(const std::string& path);

/// Reads a whole file into a string. \throws IoError.
std::string readFileToString(const std::string& path);

/// Reads one line of a text header (without its "\n" or "\r\n"); false at the end of
/// the file. \throws FormatError for a line over 4096 characters (binary data, not a
/// header), so that a wrong file is not read whole into memory.
bool readHeaderLine(const std::string& path, std::istream& in, std::string& line);

/// True on little-endian hosts (all we build for, but files are written portably).
bool hostIsLittleEndian();

/// Which file axis points up, after options and file conventions are combined.
enum class Up { x, y, z };

/// The rotation that takes a file whose up axis is `up` into our Z-up frame. Follows
/// Collada's axis table: Y_UP (x right, y up, z toward the viewer) maps (x, y, z) to
/// (x, -z, y); X_UP (-y right, x up, z toward the viewer) maps (x, y, z) to (-y, -z, x).
Eigen::Matrix3d upToZ(Up up);

/// Our PLY mesh reader (ply_mesh.cpp). Stops with FormatError as soon as the file holds
/// more than max_triangles triangles (0 = no limit), before allocating for them.
TriangleMesh readPlyMesh(const std::string& path, std::uint64_t max_triangles);

/// Our VRML97 reader (vrml_import.cpp): geometry in file units and axes (Y up).
TriangleMesh readVrml(const std::string& path, std::uint64_t max_triangles);

/// The "path: " prefix of every message about a file.
inline std::string where(const std::string& path)
{
  return path + ": ";
}

} // namespace detail
} // namespace io
} // namespace plantnbv
