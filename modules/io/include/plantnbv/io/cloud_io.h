#pragma once
/// \file cloud_io.h
/// \brief Reading and writing point clouds (PCD and PLY, chosen by the file extension).

#include <string>

#include <plantnbv/common/pcl_fwd.h>
#include <plantnbv/io/input_limits.h>

namespace plantnbv {
namespace io {

/// \brief Reads a .pcd or .ply point cloud (PCL's readers; the extension decides,
/// case-insensitive). Points are read as they are, non-finite (NaN or infinite)
/// coordinates included, as PCL marks invalid pixels of organized clouds: filters and
/// metrics drop them, and `is_dense` is set from the points (false if any coordinate
/// is non-finite), whatever the file says. x, y, z and label of any numeric type are
/// converted (PCL's own conversion leaves zeros for, e.g., double coordinates).
/// Organized PCD files keep their width and height. For XYZL a file without a `label`
/// field gives label 0 everywhere. `limits` (default: defaultInputLimits()) caps the
/// file size and the point count, checked before the points are read. Thread-safe.
/// \throws IoError if the file is missing or unreadable, FormatError if it is malformed
/// (headers are checked before PCL reads the file: PCL 1.13 crashes on some malformed
/// ones), exceeds a limit (the message names it), has no x/y/z fields, a label that is
/// not a non-negative whole number, or the extension is neither .pcd nor .ply (the
/// message names it and the accepted ones).
void loadCloud(const std::string& path, CloudXYZ& cloud);
void loadCloud(const std::string& path, CloudXYZL& cloud);
void loadCloud(const std::string& path, CloudXYZ& cloud, const InputLimits& limits);
void loadCloud(const std::string& path, CloudXYZL& cloud, const InputLimits& limits);

/// \brief Writes a .pcd or .ply point cloud, binary by default; loadCloud reads it back
/// exactly, ASCII included. PCD through PCL (ASCII with 9 significant digits); PLY with
/// our own writer: vertex x y z (float) and, for XYZL, label (uint), no other elements
/// (PLY clouds are unorganized). Thread-safe.
/// \throws IoError if the file cannot be written, FormatError for another extension.
void saveCloud(const std::string& path, const CloudXYZ& cloud, bool binary = true);
void saveCloud(const std::string& path, const CloudXYZL& cloud, bool binary = true);

} // namespace io
} // namespace plantnbv
