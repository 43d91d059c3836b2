#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

#include <plantnbv/common/error.h>
#include <plantnbv/io/file_kind.h>

#include "io_util.h"
#include "ply_format.h"

namespace plantnbv {
namespace io {

namespace {

/// True if the PLY header declares a face element with at least one face. Only the
/// header is read (it is text in every PLY format).
bool plyHasFaces(const std::string& path)
{
  requireRegularFile(path);
  std::ifstream in(path, std::ios::binary);
  const detail::PlyHeader header = detail::readPlyHeader(path, in);
  const detail::PlyElement* face = detail::findElement(header, "face");
  return face && face->count > 0;
}

} // namespace

std::string extensionOf(const std::string& path)
{
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

FileKind fileKind(const std::string& path)
{
  const std::string ext = extensionOf(path);
  if (ext == ".pcd")
    return FileKind::cloud;
  if (ext == ".ply")
    return plyHasFaces(path) ? FileKind::mesh : FileKind::cloud;
  if (ext == ".obj" || ext == ".stl" || ext == ".dae" || ext == ".wrl" || ext == ".vrml")
    return FileKind::mesh;
  if (ext == ".bt" || ext == ".ot")
    return FileKind::octree;
  throw FormatError(detail::where(path) + "unknown extension '" + ext +
                    "' (expected .pcd, .ply, .obj, .stl, .dae, .wrl, .vrml, .bt or .ot)");
}

} // namespace io
} // namespace plantnbv
