#pragma once
/// \file update_region.h
/// \brief UpdateRegion: the voxels whose state a caller of OccupancyMap will read, so
/// that `insert` can leave out free space that nobody reads.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <plantnbv/common/box.h>
#include <plantnbv/common/triangle_mesh.h>
#include <plantnbv/common/voxel_lattice.h>

namespace plantnbv {

/// \brief A set of voxels of a map's lattice, in bricks of 8^3 voxels (octree nodes at
/// depth 13), over the bricks that overlap a bounding box; every voxel outside those
/// bricks belongs to the region.
///
/// Given to OccupancyMap::setUpdateRegion, it tells `insert` which voxels must get
/// exactly the updates of a full insertion: the rays then jump over runs of bricks
/// outside the region (ray_traversal::traverseRayInRegion), and voxels there may stay
/// unknown where the full map has them free. A simulated trial reads only its ROIs'
/// voxels and the occupied ones, and a voxel can only become occupied where a ray ends
/// on the scene's surface: a region of the ROIs and the bricks around the scene's
/// triangles gives the trial the same plans and scores as the full map (docs/trials.md).
///
/// Bricks are added conservatively: a brick is in the region when it overlaps the
/// shape grown by the margin (a box test on each triangle's bounding box, large
/// triangles split first).
class UpdateRegion {
public:
  static constexpr int kBrickShift = 3; ///< bricks of 2^3 voxels per side

  /// \brief An empty region of a map with voxels of `resolution_m` (> 0), over the
  /// bricks that overlap `bounds_W` (clipped to the octree); voxels outside them are in
  /// the region. \throws InvalidArgumentError if the resolution is not finite and > 0
  /// or the bounds would need more than 2^30 bricks.
  UpdateRegion(double resolution_m, const Box& bounds_W);

  /// \brief The bricks a region over `bounds_W` at `resolution_m` (> 0) holds (its
  /// memory: one bit each).
  static std::size_t bricksOver(double resolution_m, const Box& bounds_W);

  /// \brief Adds every brick that overlaps `box_W` grown by `margin_m` (>= 0) on each
  /// side. \throws InvalidArgumentError if the margin is negative or not finite.
  void addBox(const Box& box_W, double margin_m = 0.0);
  /// \brief Adds every brick within `margin_m` (>= 0) of a triangle of `mesh_W` (at
  /// least those; triangles are tested by their bounding boxes).
  /// \throws InvalidArgumentError if the margin is negative or not finite.
  void addMesh(const TriangleMesh& mesh_W, double margin_m);

  /// \brief Whether brick (bx, by, bz) (key >> kBrickShift per axis) is in the region.
  bool containsBrick(int bx, int by, int bz) const
  {
    const unsigned x = static_cast<unsigned>(bx - lo_[0]);
    const unsigned y = static_cast<unsigned>(by - lo_[1]);
    const unsigned z = static_cast<unsigned>(bz - lo_[2]);
    if (x >= static_cast<unsigned>(n_[0]) || y >= static_cast<unsigned>(n_[1]) ||
        z >= static_cast<unsigned>(n_[2]))
      return true; // outside the bounds
    return (bits_[rowStart(static_cast<int>(y), static_cast<int>(z)) + (x >> 6)] >>
            (x & 63)) &
           1u;
  }
  /// \brief Whether the voxel of key (kx, ky, kz) is in the region.
  bool containsKey(int kx, int ky, int kz) const
  {
    return containsBrick(kx >> kBrickShift, ky >> kBrickShift, kz >> kBrickShift);
  }
  /// \brief Whether both hold the same bricks over the same bounds at the same
  /// resolution (then `insert` updates the same voxels with either).
  bool operator==(const UpdateRegion& other) const
  {
    return resolution() == other.resolution() && std::equal(lo_, lo_ + 3, other.lo_) &&
           std::equal(n_, n_ + 3, other.n_) && bits_ == other.bits_;
  }
  /// \brief Not operator==.
  bool operator!=(const UpdateRegion& other) const { return !(*this == other); }
  /// \brief The voxel edge (metres) of the lattice the region is made for.
  double resolution() const { return lattice_.resolution(); }
  /// \brief The bricks of the bounds that are in the region (at most bricksOver).
  std::size_t brickCount() const;
  /// \brief The box of the bounds' bricks (metres): every voxel outside it is in the
  /// region.
  void getBounds(double lo_m[3], double hi_m[3]) const
  {
    for (int a = 0; a < 3; ++a) {
      lo_m[a] = bounds_lo_[a];
      hi_m[a] = bounds_hi_[a];
    }
  }
  /// \brief Calls `f(lo_m, hi_m)` (two `const double[3]`, metres) with the box of every
  /// brick of the region within the bounds, in memory order.
  template <typename F>
  void forEachBrick(F&& f) const
  {
    const int first[3] = {0, 0, 0}, last[3] = {n_[0] - 1, n_[1] - 1, n_[2] - 1};
    forEachBrickIn(first, last, f);
  }
  /// \brief forEachBrick over the bricks that overlap the box [lo_m, hi_m] (metres) only
  /// (at least those: a brick that touches it may come too).
  template <typename F>
  void forEachBrick(const double lo_m[3], const double hi_m[3], F&& f) const
  {
    int first[3], last[3];
    if (bricksOverlapping(lo_m, hi_m, first, last))
      forEachBrickIn(first, last, f);
  }

private:
  /// The bricks of the bounds that overlap [lo, hi] (metres), from the bounds' first
  /// brick, per axis [b_lo, b_hi]; false: none.
  bool bricksOverlapping(const double lo[3], const double hi[3], int b_lo[3],
                         int b_hi[3]) const;
  /// forEachBrick over the bricks [first, last] (from the bounds' first brick).
  template <typename F>
  void forEachBrickIn(const int first[3], const int last[3], F& f) const
  {
    const int edge = 1 << kBrickShift;
    for (int z = first[2]; z <= last[2]; ++z)
      for (int y = first[1]; y <= last[1]; ++y) {
        const std::uint64_t* row = &bits_[rowStart(y, z)];
        for (int w = first[0] >> 6; w <= last[0] >> 6; ++w) {
          // The words' bits of [first[0], last[0]] only.
          std::uint64_t bits = row[w];
          if (w == first[0] >> 6)
            bits &= ~std::uint64_t{0} << (first[0] & 63);
          if (w == last[0] >> 6 && (last[0] & 63) != 63)
            bits &= (std::uint64_t{1} << ((last[0] & 63) + 1)) - 1;
          for (; bits != 0; bits &= bits - 1) {
            const int x = w * 64 + __builtin_ctzll(bits);
            const int key[3] = {(lo_[0] + x) * edge, (lo_[1] + y) * edge,
                                (lo_[2] + z) * edge};
            double lo_m[3], hi_m[3];
            for (int a = 0; a < 3; ++a) {
              lo_m[a] = lattice_.keyToLowerFace(key[a]);
              hi_m[a] = lattice_.keyToLowerFace(key[a] + edge);
            }
            f(static_cast<const double*>(lo_m), static_cast<const double*>(hi_m));
          }
        }
      }
  }
  /// Where the row of bricks (y, z) of the bounds (from their first brick) starts in
  /// bits_.
  std::size_t rowStart(int y, int z) const
  {
    return (static_cast<std::size_t>(z) * static_cast<std::size_t>(n_[1]) +
            static_cast<std::size_t>(y)) *
           stride_;
  }
  /// Adds the bricks that overlap [lo, hi] (metres), clipped to the bounds.
  void addBounds(const double lo[3], const double hi[3]);
  void addTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                   const Eigen::Vector3d& c, double margin_m, int depth);

  VoxelLattice lattice_;
  int lo_[3] = {0, 0, 0};  ///< brick coordinates of the first brick of the bounds
  int n_[3] = {0, 0, 0};   ///< bricks of the bounds per axis
  std::size_t stride_ = 0; ///< words per row of bricks along x
  double bounds_lo_[3] = {0.0, 0.0, 0.0}; ///< the bounds' bricks, metres
  double bounds_hi_[3] = {0.0, 0.0, 0.0};
  std::vector<std::uint64_t> bits_; ///< the region's bricks, rows along x
};

} // namespace plantnbv
