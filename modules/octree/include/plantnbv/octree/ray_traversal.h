#pragma once
/// \file ray_traversal.h
/// \brief OctoMap's ray traversal (OcTreeBaseImpl::computeRayKeys), copied operation for
/// operation so that code which must visit exactly OctoMap's voxels
/// (OccupancyMap::insert, the planner's information gain) shares one copy. Keys and
/// centres come from the voxel lattice (plantnbv/common/voxel_lattice.h).
///
/// Exactness needs the including source file to round like OctoMap: compile it with
/// `-ffp-contract=off` (no fused multiply-add) and without `-ffast-math`.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

#include <plantnbv/common/voxel_lattice.h>

namespace plantnbv {
namespace ray_traversal {

namespace detail {
/// Calls a visitor method; a void method means "go on".
template <typename Call>
inline bool proceed(Call&& call)
{
  if constexpr (std::is_void_v<decltype(call())>) {
    call();
    return true;
  } else {
    return static_cast<bool>(call());
  }
}
} // namespace detail

/// \brief The initial state of OctoMap's 3D DDA for one segment (computeRayKeys'
/// initialization phase, operation for operation).
struct RaySetup {
  float direction[3]; ///< unit direction in single precision (point3d normalized)
  float length;       ///< |end - origin| in single precision (point3d::norm())
  int step[3];        ///< -1, 0, 1 per axis
  double t_max[3];    ///< where the ray crosses the origin voxel's next border per axis
  double t_delta[3];  ///< distance between borders along the ray per axis
};

/// \brief computeRayKeys' initialization. \return false when origin and end share a
/// voxel (OctoMap then returns no voxel at all).
inline bool setupRay(const float origin[3], const float end[3], const int key_origin[3],
                     const int key_end[3], const VoxelLattice& lattice, RaySetup& s)
{
  const double resolution = lattice.resolution();
  if (key_origin[0] == key_end[0] && key_origin[1] == key_end[1] &&
      key_origin[2] == key_end[2])
    return false; // same voxel

  float* direction = s.direction;
  for (int i = 0; i < 3; ++i)
    direction[i] = end[i] - origin[i];
  // point3d::norm(): float squares and sums, then a double square root.
  s.length = static_cast<float>(std::sqrt(
      static_cast<double>(direction[0] * direction[0] + direction[1] * direction[1] +
                          direction[2] * direction[2])));
  for (int i = 0; i < 3; ++i)
    direction[i] /= s.length;

  for (int i = 0; i < 3; ++i) {
    if (direction[i] > 0.0)
      s.step[i] = 1;
    else if (direction[i] < 0.0)
      s.step[i] = -1;
    else
      s.step[i] = 0;
    if (s.step[i] != 0) {
      // The voxel's border in the ray's direction.
      double voxel_border = lattice.keyToCoord(key_origin[i]);
      voxel_border += static_cast<float>(s.step[i] * resolution * 0.5);
      s.t_max[i] = (voxel_border - origin[i]) / direction[i];
      s.t_delta[i] = resolution / std::fabs(direction[i]);
    } else {
      s.t_max[i] = std::numeric_limits<double>::max();
      s.t_delta[i] = std::numeric_limits<double>::max();
    }
  }
  return true;
}

/// \brief One step of OctoMap's 3D DDA: into the next voxel along the axis whose border
/// the ray crosses first (on ties z before y before x, OctoMap's comparisons). The
/// traversal below and the planner's gain (which also tracks bricks and jumps over empty
/// ones) both step with it, so the step exists once.
/// \param[in,out] tx, ty, tz where the ray crosses the current voxel's next border per
/// axis (OctoMap's tMax); the crossed one advances by its delta.
/// \param[in,out] kx, ky, kz the voxel's key; the crossed axis moves by its step.
/// \param[out] t_entry where the ray enters the new voxel (the crossed tMax before the
/// step). \return the axis stepped along: 0, 1 or 2.
inline int ddaStep(double& tx, double& ty, double& tz, double dx, double dy, double dz,
                   int sx, int sy, int sz, int& kx, int& ky, int& kz, double& t_entry)
{
  if (tx < ty) {
    if (tx < tz) {
      kx += sx;
      t_entry = tx;
      tx += dx;
      return 0;
    }
  } else if (ty < tz) {
    ky += sy;
    t_entry = ty;
    ty += dy;
    return 1;
  }
  kz += sz;
  t_entry = tz;
  tz += dz;
  return 2;
}

/// \brief Adds `delta` to `t` while t < target, with the result bit for bit that of
/// as many sequential double additions (`while (t < target) t += delta;`): how the DDA
/// below advances one axis's t_max past a distance at once.
///
/// Within a binade [2^(e-1), 2^e) doubles are the multiples of one ulp, so every
/// addition there adds the same rounded increment (delta rounded to a multiple of the
/// ulp; except when delta's remainder is exactly half an ulp, where ties-to-even
/// alternates: those additions are made one by one). Runs of additions that stay in a
/// binade are therefore one multiplication; only the additions that leave a binade, and
/// the few (up to 8) left before a binade's top, are made as such. O(binades crossed)
/// instead of O(additions). A run of few additions (under 48) is made one by one:
/// cheaper than the bulk steps' bookkeeping.
/// \pre delta > 0 and finite, and not below t's ulp (every addition changes t).
/// \return the number of additions.
inline long long advanceWhileBelow(double& t, double delta, double target)
{
  long long n = 0;
  const double inv_delta = 1.0 / delta; // only to estimate counts (corrected exactly)
  if ((target - t) * inv_delta < 48.0) {
    for (; t < target; ++n)
      t += delta;
    return n;
  }
  while (t < target) {
    std::uint64_t bits;
    std::memcpy(&bits, &t, sizeof bits);
    const int biased =
        static_cast<int>((bits >> 52) & 0x7ff); // t in [2^(b-1023), 2^(b-1022))
    const std::uint64_t top_bits = static_cast<std::uint64_t>(biased + 1) << 52;
    double top;
    std::memcpy(&top, &top_bits, sizeof top);
    const double limit = std::min(target, top);
    // Few additions left in this binade: made one by one below (cheaper).
    if (t > 0.0 && biased >= 54 && biased <= 2000 && // normal, and so is its ulp
        (limit - t) * inv_delta > 8.0) {
      const std::uint64_t ulp_bits = static_cast<std::uint64_t>(biased - 52) << 52;
      const std::uint64_t inv_ulp_bits = static_cast<std::uint64_t>(2098 - biased) << 52;
      double ulp, inv_ulp;
      std::memcpy(&ulp, &ulp_bits, sizeof ulp);
      std::memcpy(&inv_ulp, &inv_ulp_bits, sizeof inv_ulp);
      const double q = delta * inv_ulp; // delta / ulp, exact: a power-of-two scaling
      // floor(q) by truncation (q > 0); exact halves are the ties-to-even case.
      const double whole =
          q < 0x1p52 ? static_cast<double>(static_cast<long long>(q)) : q;
      if (q < 0x1p52 && q - whole != 0.5) {
        const double step = (q - whole < 0.5 ? whole : whole + 1.0) * ulp; // exact
        // The smallest m >= 1 with t + m step >= limit (sums below `top` are exact):
        // estimated, then corrected by exact tests.
        double m =
            static_cast<double>(static_cast<long long>((limit - t) * inv_delta)) + 1.0;
        while (m > 1.0 && t + (m - 1.0) * step >= limit)
          m -= 1.0;
        while (t + m * step < limit)
          m += 1.0;
        if (m > 1.0) { // the first m - 1 additions stay in the binade
          t += (m - 1.0) * step;
          n += static_cast<long long>(m - 1.0);
        }
      }
    }
    // Real additions up to the binade's top or the target: one after a bulk step (it
    // may leave the binade or reach the target), else each addition left in the binade.
    do {
      t += delta;
      ++n;
    } while (t < limit);
  }
  return n;
}

/// \brief The region of every brick: traverseRayInRegion over it is traverseRay.
struct WholeLattice {
  static constexpr int kBrickShift = 3; ///< any: no brick is ever asked
  /// \brief Every brick is in it.
  static constexpr bool containsBrick(int, int, int) { return true; }
};

template <typename Region, typename Visitor>
void traverseRayInRegion(const float origin[3], const float end[3],
                         const int key_origin[3], const int key_end[3],
                         const VoxelLattice& lattice, const Region& region,
                         Visitor& visitor, double clear_until = 0.0);

/// \brief The voxels of the segment origin -> end, end voxel excluded, in order: 3D DDA
/// after J. Amanatides and A. Woo, "A Fast Voxel Traversal Algorithm for Ray Tracing",
/// Eurographics 1987. This is OctoMap 1.9.x's OcTreeBaseImpl::computeRayKeys operation
/// for operation, with the same float and double roundings, so that the voxels are the
/// same (including its stop rule for rays that miss the end voxel by rounding, and no
/// voxel at all when origin and end share a voxel).
///
/// Each step goes along the axis whose t_max is smallest; on ties z before y before x
/// (OctoMap's comparisons), so the voxel sequence is the merge of the three axes'
/// border crossings ordered by (t, z > y > x).
///
/// The visitor gets `begin(kx, ky, kz, step)` for the first voxel (the origin's) and
/// `next(axis, kx, ky, kz, t_entry)` for every following one, which is one step along
/// `axis` from the one before; `t_entry` is where the ray enters that voxel (metres from
/// the origin along the ray, OctoMap's tMax before the step). Either may return bool:
/// false stops the traversal (void: go on).
/// \param[in] origin, end the segment in single precision (OctoMap's point3d).
/// \param[in] key_origin, key_end their keys (VoxelLattice::coordToKey).
/// \param[in] lattice the octree's lattice.
template <typename Visitor>
void traverseRay(const float origin[3], const float end[3], const int key_origin[3],
                 const int key_end[3], const VoxelLattice& lattice, Visitor& visitor)
{
  traverseRayInRegion(origin, end, key_origin, key_end, lattice, WholeLattice{}, visitor);
}

/// \brief A ray as the brick march below sees it.
struct MarchRay {
  double o[3];       ///< origin (OctoMap's float origin)
  double dir[3];     ///< OctoMap's float unit direction
  double inv_dir[3]; ///< 1 / dir (0 where it is 0)
  double dt[3];      ///< the DDA's t_delta
  int step[3];       ///< the DDA's step
};

/// \brief The march's view of a segment set up by setupRay.
inline MarchRay marchRay(const float origin[3], const RaySetup& s)
{
  MarchRay m;
  for (int a = 0; a < 3; ++a) {
    m.o[a] = origin[a];
    m.dir[a] = s.direction[a];
    m.inv_dir[a] = s.direction[a] != 0.0f ? 1.0 / s.direction[a] : 0.0;
    m.dt[a] = s.t_delta[a];
    m.step[a] = s.step[a];
  }
  return m;
}

namespace detail {
/// nextBrickEntry's rare case, out of line: the ray crosses the borders of the axes in
/// `tied` (a bit per axis, a's included) within kTie of each other at `t` from brick b;
/// whether a brick of any order of those crossings matters.
template <typename Matters>
[[gnu::noinline]] bool tiedBrickMatters(const MarchRay& ray, const int b[3], int tied,
                                        Matters& matters)
{
  for (int subset = 1; subset < 8; ++subset) {
    if ((subset & tied) != subset)
      continue;
    if (matters(b[0] + ((subset & 1) ? ray.step[0] : 0),
                b[1] + ((subset & 2) ? ray.step[1] : 0),
                b[2] + ((subset & 4) ? ray.step[2] : 0)))
      return true;
  }
  return false;
}
} // namespace detail

/// \brief Walks the bricks (cubes of 2^shift voxels, aligned with the octree) along the
/// ray from brick `b` (key >> shift per axis; updated), and returns where the ray enters
/// the first one for which `matters(bx, by, bz)` holds, or infinity if it enters none
/// before `limit` (metres along the ray). The distances are geometric (rounding about
/// 1e-13 m): callers stop well short of them (see advanceBelow). Where the ray crosses
/// two or three borders within `kTie` of each other, OctoMap's steps (accumulated sums)
/// may cross them in another order than this walk and pass through a brick it skips:
/// there every brick of those orders is asked, and the walk stops at the crossing if
/// one matters.
template <typename Matters>
double nextBrickEntry(const MarchRay& ray, const VoxelLattice& lattice, int shift,
                      int b[3], double limit, Matters&& matters)
{
  // Far above the rounding of both sums (~1e-13 m), far below a voxel.
  const double kTie = 1e-6 * lattice.resolution();
  double tc[3], tc_step[3]; // where the ray leaves brick b per axis, and per brick
  for (int a = 0; a < 3; ++a) {
    if (ray.step[a] == 0) {
      tc[a] = tc_step[a] = std::numeric_limits<double>::infinity();
      continue;
    }
    const int key = ray.step[a] > 0 ? (b[a] + 1) << shift : b[a] << shift;
    tc[a] = (lattice.keyToLowerFace(key) - ray.o[a]) * ray.inv_dir[a];
    tc_step[a] = (1 << shift) * lattice.resolution() * std::fabs(ray.inv_dir[a]);
  }
  // The loop in scalars, which the compiler keeps in registers (an array indexed by the
  // axis goes through memory on every step); the same operations in the same order.
  double tx = tc[0], ty = tc[1], tz = tc[2];
  int bx = b[0], by = b[1], bz = b[2];
  double entry = std::numeric_limits<double>::infinity();
  for (;;) {
    // The axis crossed first (ties: z before y before x, as the comparisons fall).
    const int a = tx < ty ? (tx < tz ? 0 : 2) : (ty < tz ? 1 : 2);
    const double t = a == 0 ? tx : (a == 1 ? ty : tz);
    if (t > limit)
      break;
    // The axes crossed (nearly) with it, a's included; another one is rare: out of line.
    const int tied = (tx - t <= kTie) | (ty - t <= kTie) << 1 | (tz - t <= kTie) << 2;
    if (tied & (tied - 1)) {
      const int here[3] = {bx, by, bz};
      if (detail::tiedBrickMatters(ray, here, tied, matters)) {
        entry = t;
        break;
      }
    }
    if (a == 0) {
      bx += ray.step[0];
      if (matters(bx, by, bz)) {
        entry = t;
        break;
      }
      tx += tc_step[0];
    } else if (a == 1) {
      by += ray.step[1];
      if (matters(bx, by, bz)) {
        entry = t;
        break;
      }
      ty += tc_step[1];
    } else {
      bz += ray.step[2];
      if (matters(bx, by, bz)) {
        entry = t;
        break;
      }
      tz += tc_step[2];
    }
  }
  b[0] = bx;
  b[1] = by;
  b[2] = bz;
  return entry;
}

/// \brief How far (voxels along the ray) a jump stops short of the next brick that
/// matters: far more than the rounding of nextBrickEntry's distances and of OctoMap's
/// sums (~1e-13 m), far less than a voxel. The map's region walk and the planner's gain
/// both jump with it.
constexpr double kJumpMarginVoxels = 1e-4;

/// \brief The shortest gap (voxels along the ray) traverseRayInRegion jumps over once the
/// march has found where it ends: advancing the state costs about as much as walking a
/// few voxels, so shorter gaps are walked (8 measured best of 4, 8 and 16 since the
/// advance's runs go side by side; 16 of 8, 16, 32 and 64 before: docs/performance.md,
/// "Shorter jumps" and "Jumps from 8 voxels"). The first jump, from a RegionHorizon
/// bound, advances the state anyway and takes every gap.
constexpr double kMinJumpVoxels = 8.0;

/// \brief Takes at once every DDA step that enters a voxel before `target`: OctoMap's
/// steps are the merge of the three axes' border crossings ordered by t, so those are,
/// per axis, the additions while t_max < target (advanceWhileBelow), and the state is
/// the one stepping one by one would reach. The caller keeps `target` short of any voxel
/// that must be visited (a margin far above the rounding of nextBrickEntry) and two
/// voxels short of the segment's length (no jumped step is the end voxel or trips
/// OctoMap's length rule).
///
/// How, by the runs' lengths (additions per axis; measured best on this project's
/// trials and gains, docs/performance.md "The jumps"):
/// - every run under kShortAdditions (the planner's jumps between bricks): one axis after
///   another, one addition at a time;
/// - longer runs (a frame's first jump, from the camera to the region): a run of
///   kBulkAdditions or more in advanceWhileBelow's bulk steps, the others in rounds of
///   one addition per axis for as long as every axis of the round is below the target,
///   then without the axes that reached it. The axes' chains of dependent additions then
///   overlap instead of following one another.
/// Each axis makes its own additions in order while it is below the target, so the
/// state is the same whichever way is taken.
inline void advanceBelow(const MarchRay& ray, double target, double t[3], int k[3])
{
  constexpr double kShortAdditions = 64;
  constexpr double kBulkAdditions = 256;
  if (target - t[0] < kShortAdditions * ray.dt[0] &&
      target - t[1] < kShortAdditions * ray.dt[1] &&
      target - t[2] < kShortAdditions * ray.dt[2]) {
    for (int a = 0; a < 3; ++a)
      for (; t[a] < target; k[a] += ray.step[a])
        t[a] += ray.dt[a];
    return;
  }
  long long n[3] = {0, 0, 0};
  int left[3], count = 0; // the axes below the target, in rounds
  for (int a = 0; a < 3; ++a) {
    if (target - t[a] >= kBulkAdditions * ray.dt[a])
      n[a] = advanceWhileBelow(t[a], ray.dt[a], target);
    else if (t[a] < target)
      left[count++] = a;
  }
  const auto dropReached = [&] {
    int kept = 0;
    for (int i = 0; i < count; ++i)
      if (t[left[i]] < target)
        left[kept++] = left[i];
    count = kept;
  };
  if (count == 3) {
    double x = t[0], y = t[1], z = t[2];
    long long rounds = 0;
    do {
      x += ray.dt[0];
      y += ray.dt[1];
      z += ray.dt[2];
      ++rounds;
    } while (x < target && y < target && z < target);
    t[0] = x, t[1] = y, t[2] = z;
    n[0] += rounds, n[1] += rounds, n[2] += rounds;
    dropReached();
  }
  if (count == 2) {
    const int a = left[0], b = left[1];
    double u = t[a], v = t[b];
    long long rounds = 0;
    do {
      u += ray.dt[a];
      v += ray.dt[b];
      ++rounds;
    } while (u < target && v < target);
    t[a] = u, t[b] = v;
    n[a] += rounds, n[b] += rounds;
    dropReached();
  }
  if (count == 1)
    n[left[0]] += advanceWhileBelow(t[left[0]], ray.dt[left[0]], target);
  for (int a = 0; a < 3; ++a)
    k[a] += static_cast<int>(n[a]) * ray.step[a];
}

/// \brief The most rays advanceBelowTogether advances at once.
constexpr int kRaysTogether = 4; // two SSE2 pairs per axis (advanceBelowTogether)

namespace detail {
/// Two doubles in one SSE2 register (GCC's and Clang's vector extension): the lanes make
/// the same IEEE additions as scalar code.
typedef double DoublePair __attribute__((vector_size(16)));
} // namespace detail

/// \brief advanceBelow for up to kRaysTogether rays at once, each to its own target: the
/// same additions, so the same states. The additions that every ray of the group makes
/// on an axis are made in SSE2 lanes, one chain per ray and axis, all side by side (one
/// ray's three chains alone leave the core waiting on each addition); what each ray has
/// left then goes through advanceBelow. Made for a frame's first jumps from the camera,
/// where neighbouring pixels' rays make nearly the same 50-150 additions per axis.
/// \param[in] rays, targets `count` rays (1 to kRaysTogether) and their targets.
/// \param[in,out] t, k their states, as advanceBelow's.
inline void advanceBelowTogether(const MarchRay* const rays[], const double targets[],
                                 double t[][3], int k[][3], int count)
{
  using Pair = detail::DoublePair;
  // Runs longer than this go through advanceBelow's bulk steps (O(binades), not O(n)).
  constexpr double kMaxCommon = 2048.0;
  // Additions every ray makes, per axis: a lower bound on each chain's count. After j
  // additions of d to t0, all below the target, the sum differs from t0 + j d by j
  // roundings of under 2^-53 of the target each; the keys bound a segment to under 2^17
  // voxels (target / d < 2^17) and j to kMaxCommon, so that is far below the two
  // additions (2 d) left out. The factor 1 + 1e-6 covers the division's rounding.
  long long common[3];
  for (int a = 0; a < 3; ++a) {
    double fewest = kMaxCommon;
    for (int g = 0; g < count; ++g) {
      const double n = (targets[g] - t[g][a]) / (rays[g]->dt[a] * (1.0 + 1e-6)) - 2.0;
      if (!(n >= fewest)) // NaN included
        fewest = n;
    }
    common[a] = fewest > 0.0 ? static_cast<long long>(fewest) : 0;
  }
  // Ray g's chain of axis a: pair g / 2, element g % 2; lanes beyond `count` add 0 to 0.
  const auto sumOf = [&](int g, int a) { return g < count ? t[g][a] : 0.0; };
  const auto deltaOf = [&](int g, int a) { return g < count ? rays[g]->dt[a] : 0.0; };
  // In registers: six chains side by side while every axis has additions to make, then
  // the axes one by one.
  Pair x0 = {sumOf(0, 0), sumOf(1, 0)}, x1 = {sumOf(2, 0), sumOf(3, 0)},
       y0 = {sumOf(0, 1), sumOf(1, 1)}, y1 = {sumOf(2, 1), sumOf(3, 1)},
       z0 = {sumOf(0, 2), sumOf(1, 2)}, z1 = {sumOf(2, 2), sumOf(3, 2)};
  const Pair dx0 = {deltaOf(0, 0), deltaOf(1, 0)}, dx1 = {deltaOf(2, 0), deltaOf(3, 0)},
             dy0 = {deltaOf(0, 1), deltaOf(1, 1)}, dy1 = {deltaOf(2, 1), deltaOf(3, 1)},
             dz0 = {deltaOf(0, 2), deltaOf(1, 2)}, dz1 = {deltaOf(2, 2), deltaOf(3, 2)};
  const long long all = std::min(common[0], std::min(common[1], common[2]));
  for (long long r = 0; r < all; ++r) {
    x0 += dx0;
    x1 += dx1;
    y0 += dy0;
    y1 += dy1;
    z0 += dz0;
    z1 += dz1;
  }
  for (long long r = all; r < common[0]; ++r) {
    x0 += dx0;
    x1 += dx1;
  }
  for (long long r = all; r < common[1]; ++r) {
    y0 += dy0;
    y1 += dy1;
  }
  for (long long r = all; r < common[2]; ++r) {
    z0 += dz0;
    z1 += dz1;
  }
  const Pair out[3][2] = {{x0, x1}, {y0, y1}, {z0, z1}};
  for (int g = 0; g < count; ++g) {
    for (int a = 0; a < 3; ++a) {
      t[g][a] = out[a][g / 2][g % 2];
      k[g][a] += static_cast<int>(common[a]) * rays[g]->step[a];
    }
    advanceBelow(*rays[g], targets[g], t[g], k[g]); // what the ray has left
  }
}

/// \brief Where a walk must start to check OctoMap's stop rules (the end voxel, the
/// segment's length): a voxel entered more than two voxels (> sqrt(3), its longest
/// chord) short of the segment's length is left before the length, so it is not the end
/// voxel and the length rule cannot stop there. Walks test the rules only from here on.
inline double stopChecksFrom(const RaySetup& s, const VoxelLattice& lattice)
{
  const float length = s.length;
  return length - 2.0 * lattice.resolution();
}

namespace detail {
/// What traverseRayInRegion's jump did: no brick of the region before the end; the
/// state moved on (the visitor resumes there); or nothing, the gap is walked.
enum class Jump { stop, jumped, walk };

/// Where traverseRayInRegion's jump goes: to kJumpMarginVoxels short of the next brick
/// of the region, at most to `checks_from`. The march starts at `march_from` (at most
/// `checks_from`) when that lies past `t_entry`, the ray's place now: the ray enters no
/// brick of the region before it (a RegionHorizon bound). Otherwise it starts at the
/// ray's place, and a gap shorter than kMinJumpVoxels is walked: `walk_until` is then
/// where it ends, and the result `walk`. `jumped`: the state (at key k) is to be advanced
/// below `advance_to` (advanceBelow); jumpToNextBrick does it at once, a frame's first
/// jumps are advanced several rays together (startRaysInRegion).
template <typename Region>
inline Jump planJump(const MarchRay& march, const VoxelLattice& lattice,
                     const Region& region, double length, double checks_from,
                     double t_entry, double march_from, const int k[3],
                     double& walk_until, double& advance_to)
{
  constexpr int shift = Region::kBrickShift;
  const double margin = kJumpMarginVoxels * lattice.resolution();
  if (march_from > length + margin)
    return Jump::stop; // the march would find no brick of the region before the end
  const double start = std::min(march_from, checks_from);
  const bool advanced = start > t_entry;
  int b[3] = {k[0] >> shift, k[1] >> shift, k[2] >> shift};
  if (advanced) {
    // The march starts from the brick of the ray's point at `start`, and the state is
    // advanced once, to where the jump ends (advanceBelow to `start` and then on is the
    // same additions): a ray that meets no brick of the region is never advanced. The
    // point's rounding (~1e-16 m) can only give a brick the ray touches within that of
    // `start`, and no brick of the region lies there (the bound holds for its bricks
    // grown by 0.01 voxel), so the march passes every brick that matters after it.
    double point[3];
    for (int a = 0; a < 3; ++a)
      point[a] = march.o[a] + march.dir[a] * start;
    int key[3];
    if (lattice.coordToKey(point[0], key[0]) && lattice.coordToKey(point[1], key[1]) &&
        lattice.coordToKey(point[2], key[2]))
      for (int a = 0; a < 3; ++a)
        b[a] = key[a] >> shift;
    // else (rounding at the tree's edge): the march starts from the ray's place, earlier
    t_entry = start;
  }
  const double entry = nextBrickEntry(
      march, lattice, shift, b, length + margin,
      [&region](int x, int y, int z) { return region.containsBrick(x, y, z); });
  if (entry == std::numeric_limits<double>::infinity())
    return Jump::stop;
  const double target = std::min(entry - margin, checks_from);
  // From the march's start the state is advanced anyway, so to the gap's end whatever
  // its length; from the ray's place a short gap is walked.
  if (!advanced && target - t_entry < kMinJumpVoxels * lattice.resolution()) {
    walk_until = entry;
    return Jump::walk;
  }
  advance_to = std::max(target, t_entry);
  return Jump::jumped;
}

/// traverseRayInRegion's jump (planJump, then the state advanced), out of line (rare;
/// the walk's state stays in registers).
template <typename Region>
[[gnu::noinline]] Jump
jumpToNextBrick(const MarchRay& march, const VoxelLattice& lattice, const Region& region,
                double length, double checks_from, double t_entry, double march_from,
                double t[3], int k[3], double& walk_until)
{
  double advance_to;
  const Jump j = planJump(march, lattice, region, length, checks_from, t_entry,
                          march_from, k, walk_until, advance_to);
  if (j == Jump::jumped)
    advanceBelow(march, advance_to, t, k);
  return j;
}

/// The jump as traverseRayInRegion's loop sees it: its state in and out, and the visitor
/// told where the ray resumes when it moved.
template <typename Region, typename Visitor>
inline Jump jumpInRegion(const float origin[3], const RaySetup& s,
                         const VoxelLattice& lattice, const Region& region,
                         double checks_from, double t_entry, double march_from,
                         double& tx, double& ty, double& tz, int& kx, int& ky, int& kz,
                         double& walk_until, Visitor& visitor)
{
  double t[3] = {tx, ty, tz};
  int k[3] = {kx, ky, kz};
  const Jump j = jumpToNextBrick(marchRay(origin, s), lattice, region, s.length,
                                 checks_from, t_entry, march_from, t, k, walk_until);
  if (j == Jump::jumped) {
    tx = t[0], ty = t[1], tz = t[2];
    kx = k[0], ky = k[1], kz = k[2];
    visitor.resume(kx, ky, kz); // the current voxel was not visited
  }
  return j;
}
} // namespace detail

/// \brief A ray of traverseRayInRegion between its start (setupRay, and the first jump
/// planned: startRayInRegion; then advanced, alone or with others: startRaysInRegion)
/// and its walk (walkRayInRegion). Plain data.
struct RegionRayStart {
  /// \brief What the walk does from here.
  enum class State {
    nothing, ///< origin and end share a voxel: no voxel at all
    origin,  ///< the origin's voxel only: no brick of the region on the way
    walk,    ///< walk from the origin (its brick in the region, or a short first gap)
    jumped,  ///< walk from (t, k): the first jump, advanced
    to_jump  ///< the first jump planned, to be advanced below `advance_to`
  };
  State state = State::nothing; ///< what the walk does from here
  RaySetup setup;               ///< setupRay's (valid unless `nothing`)
  MarchRay march;          ///< to_jump / jumped: the ray as the march and advance see it
  double t[3] = {0, 0, 0}; ///< the DDA's t_max per axis
  int k[3] = {0, 0, 0};    ///< the current voxel's key
  double walk_until = 0.0; ///< no brick is checked before (a short gap being walked)
  double advance_to = 0.0; ///< to_jump: the first jump's target
};

/// \brief traverseRayInRegion's start: the setup, and where its first jump goes when the
/// origin's brick is not in the region (planJump; the state not yet advanced: to_jump).
template <typename Region>
inline void startRayInRegion(const float origin[3], const float end[3],
                             const int key_origin[3], const int key_end[3],
                             const VoxelLattice& lattice, const Region& region,
                             double clear_until, RegionRayStart& r)
{
  using State = RegionRayStart::State;
  constexpr int shift = Region::kBrickShift;
  if (!setupRay(origin, end, key_origin, key_end, lattice, r.setup)) {
    r.state = State::nothing;
    return;
  }
  for (int a = 0; a < 3; ++a) {
    r.t[a] = r.setup.t_max[a];
    r.k[a] = key_origin[a];
  }
  r.walk_until = 0.0;
  r.state = State::walk;
  if constexpr (!std::is_same_v<Region, WholeLattice>) {
    if (region.containsBrick(r.k[0] >> shift, r.k[1] >> shift, r.k[2] >> shift))
      return;
    r.march = marchRay(origin, r.setup);
    const detail::Jump j = detail::planJump(r.march, lattice, region, r.setup.length,
                                            stopChecksFrom(r.setup, lattice), 0.0,
                                            clear_until, r.k, r.walk_until, r.advance_to);
    r.state = j == detail::Jump::stop   ? State::origin
              : j == detail::Jump::walk ? State::walk
                                        : State::to_jump;
  }
}

/// \brief startRayInRegion for `count` (1 to kRaysTogether) rays from one origin, their
/// first jumps advanced together (advanceBelowTogether): the same states as one by one.
/// Neighbouring pixels' rays make nearly the same additions from the camera to the
/// region. `clear_until[i]` as traverseRayInRegion's.
template <typename Region>
inline void startRaysInRegion(const float origin[3], const float* const ends[],
                              const int key_origin[3], const int* const key_ends[],
                              const double clear_until[], int count,
                              const VoxelLattice& lattice, const Region& region,
                              RegionRayStart starts[])
{
  using State = RegionRayStart::State;
  const MarchRay* rays[kRaysTogether];
  double targets[kRaysTogether];
  double t[kRaysTogether][3];
  int k[kRaysTogether][3];
  int index[kRaysTogether];
  int jumping = 0;
  for (int i = 0; i < count; ++i) {
    RegionRayStart& r = starts[i];
    startRayInRegion(origin, ends[i], key_origin, key_ends[i], lattice, region,
                     clear_until[i], r);
    if (r.state != State::to_jump)
      continue;
    rays[jumping] = &r.march;
    targets[jumping] = r.advance_to;
    std::copy(r.t, r.t + 3, t[jumping]);
    std::copy(r.k, r.k + 3, k[jumping]);
    index[jumping++] = i;
  }
  if (jumping == 0)
    return;
  advanceBelowTogether(rays, targets, t, k, jumping);
  for (int j = 0; j < jumping; ++j) {
    RegionRayStart& r = starts[index[j]];
    std::copy(t[j], t[j] + 3, r.t);
    std::copy(k[j], k[j] + 3, r.k);
    r.state = State::jumped;
  }
}

/// \brief traverseRayInRegion's walk from a start (startRayInRegion, whose first jump it
/// advances; or startRaysInRegion, which advanced it): the visitor's `begin`, then
/// `resume` after a first jump, then `next` for each voxel, as traverseRayInRegion
/// describes.
template <typename Region, typename Visitor>
void walkRayInRegion(const float origin[3], const int key_origin[3], const int key_end[3],
                     const VoxelLattice& lattice, const Region& region,
                     const RegionRayStart& r, Visitor& visitor)
{
  using State = RegionRayStart::State;
  constexpr bool kJumps = !std::is_same_v<Region, WholeLattice>;
  constexpr int shift = Region::kBrickShift;
  if (r.state == State::nothing)
    return;
  const RaySetup& s = r.setup;
  if (!detail::proceed([&] {
        return visitor.begin(key_origin[0], key_origin[1], key_origin[2], s.step);
      }))
    return;
  if (r.state == State::origin)
    return;

  // The loop in scalars, not arrays indexed by the axis, which the compiler keeps in
  // registers (several times faster per step). Same operations in the same order.
  double tx = r.t[0], ty = r.t[1], tz = r.t[2];
  const double dx = s.t_delta[0], dy = s.t_delta[1], dz = s.t_delta[2];
  const int sx = s.step[0], sy = s.step[1], sz = s.step[2];
  const int ex = key_end[0], ey = key_end[1], ez = key_end[2];
  const float length = s.length;
  int kx = r.k[0], ky = r.k[1], kz = r.k[2];
  const double checks_from = stopChecksFrom(s, lattice);

  // The region's jumps (none over the whole lattice; detail::jumpToNextBrick). Within a
  // gap being walked (shorter than kMinJumpVoxels) no brick is checked.
  double walk_until = r.walk_until;
  const int mask = (1 << shift) - 1;
  // key & mask right after a step into a new brick, per axis.
  const int wrap_x = sx > 0 ? 0 : mask, wrap_y = sy > 0 ? 0 : mask,
            wrap_z = sz > 0 ? 0 : mask;
  if constexpr (kJumps) {
    if (r.state == State::to_jump) { // a start of its own: advanced here
      double t[3] = {tx, ty, tz};
      int k[3] = {kx, ky, kz};
      advanceBelow(r.march, r.advance_to, t, k);
      tx = t[0], ty = t[1], tz = t[2];
      kx = k[0], ky = k[1], kz = k[2];
    }
    if (r.state == State::jumped || r.state == State::to_jump)
      visitor.resume(kx, ky, kz); // the current voxel was not visited
  }

  for (;;) {
    double t_entry;
    const int axis = ddaStep(tx, ty, tz, dx, dy, dz, sx, sy, sz, kx, ky, kz, t_entry);
    if (t_entry >= checks_from) {
      if (kx == ex && ky == ey && kz == ez)
        break;
      // Past the segment's length without reaching the end voxel (rounding): stop.
      if (std::min(std::min(tx, ty), tz) > length)
        break;
    }
    if constexpr (kJumps) {
      const bool new_brick = axis == 0   ? (kx & mask) == wrap_x
                             : axis == 1 ? (ky & mask) == wrap_y
                                         : (kz & mask) == wrap_z;
      if (new_brick && t_entry >= walk_until &&
          !region.containsBrick(kx >> shift, ky >> shift, kz >> shift)) {
        const detail::Jump j =
            detail::jumpInRegion(origin, s, lattice, region, checks_from, t_entry,
                                 t_entry, tx, ty, tz, kx, ky, kz, walk_until, visitor);
        if (j == detail::Jump::stop)
          break;
        if (j == detail::Jump::jumped)
          continue;
      }
    }
    if (!detail::proceed([&] { return visitor.next(axis, kx, ky, kz, t_entry); }))
      break;
  }
}

/// \brief traverseRay restricted to a region of bricks (cubes of voxels aligned with the
/// octree, as the region's brick shift says; e.g. UpdateRegion): every voxel of
/// traverseRay's sequence that lies in a brick of the region (`region.containsBrick(bx,
/// by, bz)`) reaches the visitor, in order, as there; runs of bricks outside it are
/// jumped over (nextBrickEntry, then advanceBelow) where they are long enough to pay, and
/// their voxels may or may not reach it. The visitor gets `begin(kx, ky, kz, step)` for
/// the origin's voxel (whatever its brick), `next(axis, kx, ky, kz, t_entry)` for a voxel
/// one step from the last one it got (either may return bool, as in traverseRay, which
/// is this walk over WholeLattice), and `resume(kx, ky, kz)` after a jump: the ray's
/// current voxel (not visited), from which the next `next` steps. startRayInRegion and
/// walkRayInRegion are its two halves (startRaysInRegion starts several rays together).
/// \param[in] clear_until metres along the ray before which it comes no nearer than far
/// above rounding to a brick of the region (RegionHorizon::clearDistance, whose bricks
/// are grown by 0.01 voxel; 0: unknown): the first jump marches the bricks from the
/// ray's point there instead of from the origin.
template <typename Region, typename Visitor>
void traverseRayInRegion(const float origin[3], const float end[3],
                         const int key_origin[3], const int key_end[3],
                         const VoxelLattice& lattice, const Region& region,
                         Visitor& visitor, double clear_until)
{
  RegionRayStart r;
  startRayInRegion(origin, end, key_origin, key_end, lattice, region, clear_until, r);
  walkRayInRegion(origin, key_origin, key_end, lattice, region, r, visitor);
}

} // namespace ray_traversal
} // namespace plantnbv
