#pragma once
/// \file file_kind.h
/// \brief What a file holds, so that tools can accept a cloud, a mesh or an octree
/// wherever a geometry is asked for.

#include <string>

namespace plantnbv {
namespace io {

/// \brief What a file holds, as fileKind() tells it from its name (and PLY header).
enum class FileKind {
  cloud,  ///< a point cloud: .pcd, or .ply without faces
  mesh,   ///< a triangle mesh: .ply with faces, .obj .stl .dae .wrl .vrml
  octree, ///< an OctoMap: .bt .ot
};

/// \brief Classifies a file by its extension (case-insensitive) and, for .ply, its
/// header: .pcd -> cloud; .ply -> mesh if it has a non-empty `face` element, else cloud;
/// .obj .stl .dae .wrl .vrml -> mesh; .bt .ot -> octree.
/// Only .ply files are opened (their header only). Thread-safe.
/// \throws IoError if the file is missing (for .ply), FormatError for a malformed PLY
/// header or another extension (the message names it and the accepted ones).
FileKind fileKind(const std::string& path);

/// \brief The lower-case extension with its dot (".pcd"), or "" when there is none.
std::string extensionOf(const std::string& path);

} // namespace io
} // namespace plantnbv
