#include <algorithm>
#include <cmath>
#include <sstream>

#include <plantnbv/common/error.h>
#include <plantnbv/octree/update_region.h>

namespace plantnbv {

namespace {

constexpr std::size_t kMaxBricks = std::size_t{1} << 30;
/// A triangle whose bounding box spans more bricks than this along an axis is split in
/// four (up to kMaxSplits times), so that a large slanted one (a floor, a wall) adds the
/// bricks along its plane rather than its whole bounding box.
constexpr int kSplitAbove = 4;
constexpr int kMaxSplits = 24;

void requireMargin(double margin_m, const char* who)
{
  if (!(std::isfinite(margin_m) && margin_m >= 0.0)) {
    std::ostringstream s;
    s << "UpdateRegion::" << who << ": margin " << margin_m
      << " must be finite and >= 0 (metres)";
    throw InvalidArgumentError(s.str());
  }
}

/// The brick holding `coordinate` along an axis, clamped to the octree.
int brickOf(const VoxelLattice& lattice, double coordinate)
{
  const double f = std::floor(lattice.resolutionFactor() * coordinate) +
                   static_cast<double>(VoxelLattice::kKeyOffset);
  const double key = f > 0.0
                         ? std::min(f, static_cast<double>(VoxelLattice::kKeyLimit - 1))
                         : 0.0; // also NaN
  return static_cast<int>(key) >> UpdateRegion::kBrickShift;
}

} // namespace

std::size_t UpdateRegion::bricksOver(double resolution_m, const Box& bounds_W)
{
  const VoxelLattice lattice(resolution_m);
  std::size_t bricks = 1;
  for (int a = 0; a < 3; ++a)
    bricks *= static_cast<std::size_t>(brickOf(lattice, bounds_W.max()[a]) -
                                       brickOf(lattice, bounds_W.min()[a]) + 1);
  return bricks;
}

UpdateRegion::UpdateRegion(double resolution_m, const Box& bounds_W)
    : lattice_(resolution_m)
{
  if (!(std::isfinite(resolution_m) && resolution_m > 0.0)) {
    std::ostringstream s;
    s << "UpdateRegion: resolution " << resolution_m
      << " must be finite and > 0 (metres)";
    throw InvalidArgumentError(s.str());
  }
  const std::size_t bricks = bricksOver(resolution_m, bounds_W);
  if (bricks > kMaxBricks) {
    std::ostringstream s;
    s << "UpdateRegion: bounds of " << bounds_W.size.transpose() << " m hold " << bricks
      << " bricks of " << (1 << kBrickShift) << "^3 voxels at " << resolution_m
      << " m (at most " << kMaxBricks << ")";
    throw InvalidArgumentError(s.str());
  }
  for (int a = 0; a < 3; ++a) {
    lo_[a] = brickOf(lattice_, bounds_W.min()[a]);
    n_[a] = brickOf(lattice_, bounds_W.max()[a]) - lo_[a] + 1;
    bounds_lo_[a] = lattice_.keyToLowerFace(lo_[a] << kBrickShift);
    bounds_hi_[a] = lattice_.keyToLowerFace((lo_[a] + n_[a]) << kBrickShift);
  }
  stride_ = (static_cast<std::size_t>(n_[0]) + 63) / 64;
  bits_.assign(
      stride_ * static_cast<std::size_t>(n_[1]) * static_cast<std::size_t>(n_[2]), 0);
}

bool UpdateRegion::bricksOverlapping(const double lo[3], const double hi[3], int b_lo[3],
                                     int b_hi[3]) const
{
  for (int a = 0; a < 3; ++a) {
    if (hi[a] < bounds_lo_[a] || lo[a] > bounds_hi_[a])
      return false;
    b_lo[a] = std::max(brickOf(lattice_, lo[a]), lo_[a]) - lo_[a];
    b_hi[a] = std::min(brickOf(lattice_, hi[a]), lo_[a] + n_[a] - 1) - lo_[a];
  }
  return true;
}

void UpdateRegion::addBounds(const double lo[3], const double hi[3])
{
  int b_lo[3], b_hi[3];
  if (!bricksOverlapping(lo, hi, b_lo, b_hi))
    return;
  for (int z = b_lo[2]; z <= b_hi[2]; ++z)
    for (int y = b_lo[1]; y <= b_hi[1]; ++y) {
      std::uint64_t* row = &bits_[rowStart(y, z)];
      for (int x = b_lo[0]; x <= b_hi[0]; ++x)
        row[x >> 6] |= std::uint64_t{1} << (x & 63);
    }
}

void UpdateRegion::addBox(const Box& box_W, double margin_m)
{
  requireMargin(margin_m, "addBox");
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = box_W.min()[a] - margin_m;
    hi[a] = box_W.max()[a] + margin_m;
  }
  addBounds(lo, hi);
}

void UpdateRegion::addTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                               const Eigen::Vector3d& c, double margin_m, int depth)
{
  const Eigen::Vector3d lo = a.cwiseMin(b).cwiseMin(c).array() - margin_m;
  const Eigen::Vector3d hi = a.cwiseMax(b).cwiseMax(c).array() + margin_m;
  for (int i = 0; i < 3; ++i)
    if (hi[i] < bounds_lo_[i] || lo[i] > bounds_hi_[i])
      return; // outside the bounds: in the region anyway
  const double brick_m = lattice_.resolution() * (1 << kBrickShift);
  if (depth < kMaxSplits && (hi - lo).maxCoeff() > kSplitAbove * brick_m) {
    const Eigen::Vector3d ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
    addTriangle(a, ab, ca, margin_m, depth + 1);
    addTriangle(ab, b, bc, margin_m, depth + 1);
    addTriangle(ca, bc, c, margin_m, depth + 1);
    addTriangle(ab, bc, ca, margin_m, depth + 1);
    return;
  }
  addBounds(lo.data(), hi.data());
}

void UpdateRegion::addMesh(const TriangleMesh& mesh_W, double margin_m)
{
  requireMargin(margin_m, "addMesh");
  for (const auto& t : mesh_W.triangles) {
    const Eigen::Vector3d a = mesh_W.vertices[t[0]].cast<double>();
    const Eigen::Vector3d b = mesh_W.vertices[t[1]].cast<double>();
    const Eigen::Vector3d c = mesh_W.vertices[t[2]].cast<double>();
    if (a.allFinite() && b.allFinite() && c.allFinite()) // no ray hits another
      addTriangle(a, b, c, margin_m, 0);
  }
}

std::size_t UpdateRegion::brickCount() const
{
  std::size_t count = 0;
  for (std::uint64_t w : bits_) // the padding of the rows stays 0
    count += static_cast<std::size_t>(__builtin_popcountll(w));
  return count;
}

} // namespace plantnbv
