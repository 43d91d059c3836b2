#pragma once
// Triangulation of the polygon faces of mesh files (PLY and VRML n-gons).

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace plantnbv {
namespace io {
namespace detail {

/// The ear-clipping steps (one corner tested against one ear) one file may take: ear
/// clipping costs up to O(corners^2) per polygon, so a small file of large non-convex
/// faces could otherwise run for hours. 2^30 steps take about 2 s; a convex face of any
/// size is a fan and costs none.
constexpr std::uint64_t kEarClippingStepsPerFile = std::uint64_t{1} << 30;

/// What triangulatePolygon did with a polygon.
enum class PolygonCut {
  cut,            ///< triangles added
  crosses_itself, ///< not simple: no ear to cut
  over_budget     ///< ear clipping would exceed the file's steps
};

/// \brief Cuts the polygon `corners` (indices into `vertices`, in the file's winding)
/// into corners.size() - 2 triangles that cover exactly its area, in the file's winding.
/// A convex polygon becomes a fan around its first corner. Any other polygon is cut by
/// ear clipping in the plane of its Newell normal: a corner on the line of its neighbours
/// (a straight corner, a spike going out and back, a repeated vertex) is cut off as a
/// triangle of area 0, so a degenerate polygon gets its true area (0 if it has none),
/// never the fan's overlap.
/// \param[in,out] steps_left the file's ear-clipping budget (kEarClippingStepsPerFile at
/// its first polygon), reduced by what this polygon took.
/// \returns PolygonCut::cut, or why not (then `triangles` is as it was). Indices must be
/// < vertices.size().
PolygonCut triangulatePolygon(const std::vector<Eigen::Vector3f>& vertices,
                              const std::vector<std::uint32_t>& corners,
                              std::vector<std::array<std::uint32_t, 3>>& triangles,
                              std::uint64_t& steps_left);

/// The reason for a refused face of `corners` corners, for the message that names the
/// file and the face: "a face of N corners crosses itself; its area is undefined".
std::string untriangulableFace(PolygonCut why, std::size_t corners);

} // namespace detail
} // namespace io
} // namespace plantnbv
