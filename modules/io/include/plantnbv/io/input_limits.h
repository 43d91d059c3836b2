#pragma once
/// \file input_limits.h
/// \brief Caps on the size of the files the readers accept, so that a malformed or
/// hostile file (a PLY header announcing 10^12 vertices, a 100 GB file) is refused with
/// a FormatError naming the file and the cap, before memory is exhausted.
///
/// The defaults are generous for real plants (a scanned plant is a few million points,
/// a detailed plant mesh a few million triangles). They apply to loadCloud, loadMesh,
/// loadRoi and fileKind; change them for the whole process with setDefaultInputLimits
/// or for one call (loadCloud's `limits`, MeshLoadOptions::limits). 0 means no cap.
///
/// What is checked, and when:
/// - max_file_bytes: the file size, before the file is read;
/// - max_points: the point count of a cloud (PCD WIDTH x HEIGHT / POINTS, PLY vertex
///   count) and the vertex count of a mesh, from the header before anything is
///   allocated (PLY, PCD, binary STL), else while reading (VRML) or before the
///   vertices are copied out of Assimp's scene (OBJ, STL, Collada);
/// - max_triangles: the triangle count of a mesh after triangulation, likewise; for
///   VRML also the node instances walked (DEF/USE can nest to 2^depth instances).
///
/// Detection files have fixed caps of their own (detections_io.h):
/// kMaxDetectionsPerFrame entries, kMaxMaskBytesPerFrame of masks, 64 MiB of JSON (or
/// max_file_bytes if smaller).

#include <cstdint>

namespace plantnbv {
namespace io {

/// \brief Caps on what a reader accepts from one file (see above); 0: no cap.
struct InputLimits {
  std::uint64_t max_file_bytes = std::uint64_t{2} << 30; ///< 2 GiB
  std::uint64_t max_points = 100'000'000;   ///< cloud points or mesh vertices
  std::uint64_t max_triangles = 50'000'000; ///< mesh triangles (after triangulation)

  /// \brief No cap at all (trusted files only).
  static InputLimits unlimited() { return {0, 0, 0}; }
};

/// \brief The limits of every read that is given none; the defaults above until set.
/// Thread-safe (an atomic copy).
InputLimits defaultInputLimits();

/// \brief Replaces the process-wide default limits. Thread-safe; reads already under way
/// keep the limits they started with.
void setDefaultInputLimits(const InputLimits& limits);

} // namespace io
} // namespace plantnbv
