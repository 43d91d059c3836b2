#pragma once
/// \file voxel_lattice.h
/// \brief OctoMap's voxel lattice at a resolution: coordinate <-> voxel index <-> key <->
/// voxel centre, the one place where these are computed (the map, the voxel-grid filter,
/// the planner's gain and the evaluator all use it, so ground truth and belief fall on
/// the same cells).
///
/// The arithmetic is OctoMap 1.9's (OcTreeBaseImpl: resolution_factor = 1 / resolution,
/// coordToKey = floor(resolution_factor * coordinate) + tree_max_val, keyToCoord =
/// (key - tree_max_val + 0.5) * resolution, all in double), operation for operation:
/// tests/octree/test_voxel_lattice.cpp checks it against the installed OctoMap, so an
/// upgrade that changes it fails there with a message saying why. Including files that
/// must match OctoMap bit for bit are compiled with `-ffp-contract=off` and without
/// `-ffast-math` (no contraction is possible in these expressions, but the callers'
/// own arithmetic around them usually needs it).
///
/// Voxel index i (unbounded, 64-bit) spans [i * resolution, (i + 1) * resolution) along
/// an axis; a key is an index shifted into OctoMap's 16-level tree, key = i + 32768 in
/// [0, 65536). Keys are ints here (OctoMap's are uint16 and would wrap at the border).

#include <cmath>
#include <cstdint>

#ifdef __FAST_MATH__
#error "plantnbv/common/voxel_lattice.h must not be compiled with -ffast-math"
#endif

namespace plantnbv {

/// \brief OctoMap's lattice at one resolution. A small value type; all methods are
/// const, inline and thread-safe.
class VoxelLattice {
public:
  /// OctoMap's tree depth (OcTree: 16 levels).
  static constexpr int kTreeDepth = 16;
  /// OctoMap's tree_max_val: the key of voxel index 0.
  static constexpr int kKeyOffset = 1 << (kTreeDepth - 1);
  /// Keys lie in [0, kKeyLimit).
  static constexpr int kKeyLimit = 2 * kKeyOffset;

  /// \param[in] resolution_m voxel edge in metres (> 0; not checked here: the map and
  /// the filters validate their resolutions).
  explicit VoxelLattice(double resolution_m)
      : resolution_m_(resolution_m), resolution_factor_(1.0 / resolution_m)
  {
  }

  /// \brief The voxel edge in metres.
  double resolution() const { return resolution_m_; }
  /// 1 / resolution, computed as OctoMap does.
  double resolutionFactor() const { return resolution_factor_; }

  /// \brief floor(coordinate / resolution) as OctoMap computes it, as a double (so
  /// that callers can range-check before converting). NaN for a non-finite coordinate.
  double indexOf(double coordinate) const
  {
    return std::floor(resolution_factor_ * coordinate);
  }

  /// \brief OctoMap's coordToKeyChecked(double), range-checked before the int
  /// conversion (which OctoMap does unchecked, undefined for huge values).
  /// \return false (key unchanged) outside the tree or for a non-finite coordinate.
  bool coordToKey(double coordinate, int& key) const
  {
    const double f = indexOf(coordinate);
    if (!(f >= -kKeyOffset && f < kKeyOffset))
      return false;
    key = static_cast<int>(f) + kKeyOffset;
    return true;
  }

  /// \brief coordToKey for a point in single precision (OctoMap's point3d).
  bool coordToKey(const float p[3], int key[3]) const
  {
    return coordToKey(p[0], key[0]) && coordToKey(p[1], key[1]) &&
           coordToKey(p[2], key[2]);
  }

  /// \brief OctoMap's keyToCoord(key): the voxel centre in double.
  double keyToCoord(int key) const
  {
    return (static_cast<double>(key - kKeyOffset) + 0.5) * resolution_m_;
  }

  /// \brief The centre of voxel index i (the same value keyToCoord gives for its key,
  /// for indices outside the tree too).
  double indexToCoord(std::int64_t index) const
  {
    return (static_cast<double>(index) + 0.5) * resolution_m_;
  }

  /// \brief The lower face of key `key` along an axis (metres): key - kKeyOffset times
  /// the resolution.
  double keyToLowerFace(int key) const
  {
    return static_cast<double>(key - kKeyOffset) * resolution_m_;
  }

private:
  double resolution_m_;
  double resolution_factor_;
};

} // namespace plantnbv
