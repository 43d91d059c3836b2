#pragma once
/// \file cloud_io.h
/// \brief Reading and writing point clouds (PCD and PLY, chosen by the file extension).

#include <string>

#include <plantnbv/common/pcl_fwd.h>
#include <plantnbv/io/input_limits.h>

namespace plantnbv {
namespace io {

/// \brief Reads a .pcd or .ply point cloud with our own readers (not PCL's io library,
/// which crashed on malformed files and loads VTK); the extension decides,
/// case-insensitive. PCD: DATA ascii, binary and binary_compressed, fields of any type
/// and count (the first value of x, y, z and label is kept, other fields are skipped),
/// POINTS must be WIDTH x HEIGHT. PLY: ascii and binary of either byte order; the points
/// are the vertex element's, whose x, y, z and label must be single values of any type
/// (other properties, lists included, and other elements are skipped). Points are read
/// as they are, non-finite (NaN or infinite) coordinates included, as PCL marks invalid
/// pixels of organized clouds: filters and metrics drop them, and `is_dense` is set from
/// the points (false if any coordinate is non-finite), whatever the file says.
/// Organized PCD files keep their width and height. For XYZL a file without a `label`
/// field gives label 0 everywhere. `limits` (default: defaultInputLimits()) caps the
/// file size and the point count, checked from the header before anything is allocated
/// for the points. `cloud` is left as it was if the file is refused. Thread-safe.
/// \throws IoError if the file is missing or unreadable, FormatError if it is malformed
/// (the message names the line or what is wrong), exceeds a limit (the message names
/// it), has no x/y/z fields, a label that is not a non-negative whole number, or the
/// extension is neither .pcd nor .ply (the message names it and the accepted ones).
void loadCloud(const std::string& path, CloudXYZ& cloud);
/// \brief loadCloud() with labels (0 everywhere if the file has no `label` field).
void loadCloud(const std::string& path, CloudXYZL& cloud);
/// \brief loadCloud() with `limits` instead of defaultInputLimits().
void loadCloud(const std::string& path, CloudXYZ& cloud, const InputLimits& limits);
/// \brief loadCloud() with labels and `limits` instead of defaultInputLimits().
void loadCloud(const std::string& path, CloudXYZL& cloud, const InputLimits& limits);

/// \brief Writes a .pcd or .ply point cloud, binary by default, that loadCloud (and
/// PCL) reads back exactly, ASCII included (the shortest text of each float that reads
/// back as it). x y z (float) and, for XYZL, label (uint). PCD keeps an organized cloud's
/// width and height; PLY clouds are unorganized (one vertex element, nothing else).
/// Thread-safe.
/// \throws IoError if the file cannot be written, FormatError for another extension.
void saveCloud(const std::string& path, const CloudXYZ& cloud, bool binary = true);
void saveCloud(const std::string& path, const CloudXYZL& cloud, bool binary = true);

} // namespace io
} // namespace plantnbv
