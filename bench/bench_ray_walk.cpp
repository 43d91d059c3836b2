// The rays' walk of insertion, alone: rays walked one at a time by the library's
// ray_traversal::traverseRay (OctoMap's 3D DDA, as OccupancyMap::insert walks them)
// against four neighbouring rays stepped in lockstep with AVX2 (or two such packets of
// four, interleaved), a prototype of a packet walk that the library does not use yet
// (docs/performance.md, "A lead: rays in lockstep"). Both mark the voxels of one camera
// frame whose every ray carves 0.75 m at 3 mm (640 x 480 rays, 70 x 55 degrees, as in
// bench_occupancy_map's frames with a background) in the same kind of bitset (a 64-bit
// word per 4^3-voxel cell, as the map's blocks hold them), and the lockstep walks'
// bitsets are compared with the library's.
//
// What this leaves out of insertion: the blocks' lookup, the update region's jumps, the
// tree update. It measures the step and the mark, which take most of a frame's walk.
//
// BM_FirstJumps*: the same frame's first jumps to a region (docs/performance.md, "First
// jumps four rays at a time"), one ray at a time and four neighbours together.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <immintrin.h>
#include <vector>

#include <benchmark/benchmark.h>

#include <plantnbv/common/voxel_lattice.h>
#include <plantnbv/octree/ray_traversal.h>

namespace {

using plantnbv::VoxelLattice;
namespace rt = plantnbv::ray_traversal;

constexpr double kResolution = 0.003;
constexpr double kRange = 0.75;
constexpr int kGrid = 512; ///< voxels per axis around the camera's voxel
constexpr int kWidth = 640, kHeight = 480;

/// One bit per voxel of a kGrid^3 cube, a word per 4^3-voxel cell.
class Bitset {
public:
  explicit Bitset(const int key_base[3])
      : words_(static_cast<std::size_t>(kGrid) * kGrid * kGrid / 64, 0), base_{
                                                                             key_base[0],
                                                                             key_base[1],
                                                                             key_base[2]}
  {
  }

  /// The bit index of a voxel key.
  std::uint64_t index(int kx, int ky, int kz) const
  {
    const auto x = static_cast<std::uint64_t>(kx - base_[0]);
    const auto y = static_cast<std::uint64_t>(ky - base_[1]);
    const auto z = static_cast<std::uint64_t>(kz - base_[2]);
    return ((((x >> 2) << 14) | ((y >> 2) << 7) | (z >> 2)) << 6) | ((x & 3) << 4) |
           ((y & 3) << 2) | (z & 3);
  }

  void set(std::uint64_t i)
  {
    std::uint64_t& word = words_[i >> 6];
    const std::uint64_t bit = std::uint64_t{1} << (i & 63);
    if (!(word & bit)) // most voxels are crossed by many rays: test first, write once
      word |= bit;
  }

  void set(int kx, int ky, int kz) { set(index(kx, ky, kz)); }
  void clear() { std::fill(words_.begin(), words_.end(), 0); }
  const int* base() const { return base_; }
  bool operator==(const Bitset& other) const { return words_ == other.words_; }

private:
  std::vector<std::uint64_t> words_;
  int base_[3];
};

/// traverseRay's visitor: marks every voxel, counts the steps.
struct MarkingVisitor {
  Bitset& bits;
  long long steps = 0;
  void begin(int kx, int ky, int kz, const int*) { bits.set(kx, ky, kz); }
  void next(int, int kx, int ky, int kz, double)
  {
    ++steps;
    bits.set(kx, ky, kz);
  }
};

struct Frame {
  VoxelLattice lattice{kResolution};
  float origin[3] = {0.0011f, -0.0007f, 0.0003f};
  int key_origin[3] = {0, 0, 0};
  /// Ray ends and keys, four neighbouring pixels (2 x 2) after each other.
  std::vector<std::array<float, 3>> ends;
  std::vector<std::array<int, 3>> key_ends;

  Frame()
  {
    lattice.coordToKey(origin, key_origin);
    const double fx = (kWidth / 2.0) / std::tan(35.0 * M_PI / 180.0);
    const double fy = (kHeight / 2.0) / std::tan(27.5 * M_PI / 180.0);
    for (int v = 0; v < kHeight; v += 2)
      for (int u = 0; u < kWidth; u += 2)
        for (int q = 0; q < 4; ++q) {
          const double d[3] = {1.0, (u + (q & 1) - kWidth / 2 + 0.5) / fx,
                               (v + (q >> 1) - kHeight / 2 + 0.5) / fy};
          const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
          std::array<float, 3> end;
          std::array<int, 3> key;
          for (int a = 0; a < 3; ++a)
            end[a] = origin[a] + static_cast<float>(d[a] / n * kRange);
          lattice.coordToKey(end.data(), key.data());
          ends.push_back(end);
          key_ends.push_back(key);
        }
  }

  void keyBase(int base[3]) const
  {
    for (int a = 0; a < 3; ++a)
      base[a] = key_origin[a] - kGrid / 2;
  }
};

const Frame& frame()
{
  static const Frame f;
  return f;
}

long long walkOneAtATime(const Frame& f, Bitset& bits)
{
  MarkingVisitor visitor{bits};
  for (std::size_t i = 0; i < f.ends.size(); ++i)
    rt::traverseRay(f.origin, f.ends[i].data(), f.key_origin, f.key_ends[i].data(),
                    f.lattice, visitor);
  return visitor.steps;
}

__attribute__((target("avx2"))) inline __m256i load(const std::int64_t* p)
{
  return _mm256_load_si256(reinterpret_cast<const __m256i*>(p));
}

/// Four rays from one origin stepped together, OctoMap's step and stop rules lane by lane
/// (the same comparisons and additions, so the same voxels); a lane that stopped adds
/// zero and marks nothing. Keys and indices in 64-bit lanes.
struct Lanes {
  __m256d tx, ty, tz, dx, dy, dz, length, live;
  __m256i kx, ky, kz, sx, sy, sz, ex, ey, ez, bx, by, bz;

  __attribute__((target("avx2"))) void start(const Frame& f, std::size_t first,
                                             Bitset& bits)
  {
    alignas(32) double t0[3][4], d0[3][4], len0[4];
    alignas(32) std::int64_t k0[3][4], s0[3][4], e0[3][4], base0[3][4], live0[4];
    for (int l = 0; l < 4; ++l) {
      rt::RaySetup s{};
      const float* end = f.ends[first + static_cast<std::size_t>(l)].data();
      const int* key_end = f.key_ends[first + static_cast<std::size_t>(l)].data();
      const bool walks = rt::setupRay(f.origin, end, f.key_origin, key_end, f.lattice, s);
      if (walks)
        bits.set(f.key_origin[0], f.key_origin[1], f.key_origin[2]);
      live0[l] = walks ? -1 : 0;
      for (int a = 0; a < 3; ++a) {
        t0[a][l] = s.t_max[a];
        d0[a][l] = s.t_delta[a];
        k0[a][l] = f.key_origin[a];
        s0[a][l] = s.step[a];
        e0[a][l] = key_end[a];
        base0[a][l] = bits.base()[a];
      }
      len0[l] = s.length;
    }
    tx = _mm256_load_pd(t0[0]), ty = _mm256_load_pd(t0[1]), tz = _mm256_load_pd(t0[2]);
    dx = _mm256_load_pd(d0[0]), dy = _mm256_load_pd(d0[1]), dz = _mm256_load_pd(d0[2]);
    length = _mm256_load_pd(len0);
    kx = load(k0[0]), ky = load(k0[1]), kz = load(k0[2]);
    sx = load(s0[0]), sy = load(s0[1]), sz = load(s0[2]);
    ex = load(e0[0]), ey = load(e0[1]), ez = load(e0[2]);
    bx = load(base0[0]), by = load(base0[1]), bz = load(base0[2]);
    live = _mm256_castsi256_pd(load(live0));
  }

  /// One step of every live lane; their new voxels marked. \return the lanes still live.
  __attribute__((target("avx2"), always_inline)) inline int step(Bitset& bits,
                                                                 long long& steps)
  {
    // ddaStep: x if tx < ty and tx < tz, else y if ty < tz, else z.
    const __m256d x_lt_y = _mm256_cmp_pd(tx, ty, _CMP_LT_OQ);
    const __m256d on_x = _mm256_and_pd(x_lt_y, _mm256_cmp_pd(tx, tz, _CMP_LT_OQ));
    const __m256d on_y = _mm256_andnot_pd(x_lt_y, _mm256_cmp_pd(ty, tz, _CMP_LT_OQ));
    const __m256d sel_x = _mm256_and_pd(on_x, live), sel_y = _mm256_and_pd(on_y, live);
    const __m256d sel_z = _mm256_andnot_pd(_mm256_or_pd(on_x, on_y), live);
    tx = _mm256_add_pd(tx, _mm256_and_pd(dx, sel_x));
    ty = _mm256_add_pd(ty, _mm256_and_pd(dy, sel_y));
    tz = _mm256_add_pd(tz, _mm256_and_pd(dz, sel_z));
    kx = _mm256_add_epi64(kx, _mm256_and_si256(sx, _mm256_castpd_si256(sel_x)));
    ky = _mm256_add_epi64(ky, _mm256_and_si256(sy, _mm256_castpd_si256(sel_y)));
    kz = _mm256_add_epi64(kz, _mm256_and_si256(sz, _mm256_castpd_si256(sel_z)));
    // Stop at the end voxel, or past the segment's length.
    const __m256i at_end = _mm256_and_si256(
        _mm256_and_si256(_mm256_cmpeq_epi64(kx, ex), _mm256_cmpeq_epi64(ky, ey)),
        _mm256_cmpeq_epi64(kz, ez));
    const __m256d past =
        _mm256_cmp_pd(_mm256_min_pd(tx, _mm256_min_pd(ty, tz)), length, _CMP_GT_OQ);
    live = _mm256_andnot_pd(_mm256_or_pd(_mm256_castsi256_pd(at_end), past), live);
    const int marking = _mm256_movemask_pd(live);
    if (!marking)
      return 0;
    steps += __builtin_popcount(static_cast<unsigned>(marking));
    // Bitset::index, lane by lane.
    const __m256i three = _mm256_set1_epi64x(3);
    const __m256i x = _mm256_sub_epi64(kx, bx), y = _mm256_sub_epi64(ky, by),
                  z = _mm256_sub_epi64(kz, bz);
    const __m256i cell =
        _mm256_or_si256(_mm256_or_si256(_mm256_slli_epi64(_mm256_srli_epi64(x, 2), 14),
                                        _mm256_slli_epi64(_mm256_srli_epi64(y, 2), 7)),
                        _mm256_srli_epi64(z, 2));
    const __m256i inside =
        _mm256_or_si256(_mm256_or_si256(_mm256_slli_epi64(_mm256_and_si256(x, three), 4),
                                        _mm256_slli_epi64(_mm256_and_si256(y, three), 2)),
                        _mm256_and_si256(z, three));
    alignas(32) std::uint64_t index[4];
    _mm256_store_si256(reinterpret_cast<__m256i*>(index),
                       _mm256_or_si256(_mm256_slli_epi64(cell, 6), inside));
    for (int m = marking; m; m &= m - 1)
      bits.set(index[__builtin_ctz(static_cast<unsigned>(m))]);
    return marking;
  }
};

__attribute__((target("avx2"))) long long walkFour(const Frame& f, std::size_t first,
                                                   Bitset& bits)
{
  Lanes a;
  a.start(f, first, bits);
  long long steps = 0;
  while (a.step(bits, steps)) {
  }
  return steps;
}

/// Two packets of four interleaved: each one's dependency chain hides the other's.
__attribute__((target("avx2"))) long long walkEight(const Frame& f, std::size_t first,
                                                    Bitset& bits)
{
  Lanes a, b;
  a.start(f, first, bits);
  b.start(f, first + 4, bits);
  long long steps = 0;
  bool live_a = true, live_b = true;
  while (live_a && live_b) {
    live_a = a.step(bits, steps) != 0;
    live_b = b.step(bits, steps) != 0;
  }
  while (live_a && a.step(bits, steps)) {
  }
  while (live_b && b.step(bits, steps)) {
  }
  return steps;
}

long long walkInLockstep8(const Frame& f, Bitset& bits)
{
  long long steps = 0;
  for (std::size_t i = 0; i < f.ends.size(); i += 8)
    steps += walkEight(f, i, bits);
  return steps;
}

long long walkInLockstep4(const Frame& f, Bitset& bits)
{
  long long steps = 0;
  for (std::size_t i = 0; i < f.ends.size(); i += 4)
    steps += walkFour(f, i, bits);
  return steps;
}

/// A frame's first jumps (OccupancyMap::insert with an update region): every ray of the
/// frame advanced from the camera to where it meets a region 0.3 m ahead (the plane x =
/// 0.3 m: neighbouring rays nearly alike, 100-160 additions on the major axis). One ray
/// at a time (advanceBelow) or four neighbours together (advanceBelowTogether).
struct FirstJumps {
  std::vector<rt::MarchRay> rays;
  std::vector<double> targets;
  std::vector<std::array<double, 3>> t;
  std::vector<std::array<int, 3>> k;

  explicit FirstJumps(const Frame& f)
  {
    for (std::size_t i = 0; i < f.ends.size(); ++i) {
      rt::RaySetup s;
      if (!rt::setupRay(f.origin, f.ends[i].data(), f.key_origin, f.key_ends[i].data(),
                        f.lattice, s))
        continue;
      rays.push_back(rt::marchRay(f.origin, s));
      targets.push_back(0.3 / rays.back().dir[0]);
      t.push_back({s.t_max[0], s.t_max[1], s.t_max[2]});
      k.push_back({f.key_origin[0], f.key_origin[1], f.key_origin[2]});
    }
  }
};

template <bool kTogether>
void advanceFirstJumps(const FirstJumps& jumps, std::vector<std::array<double, 3>>& t,
                       std::vector<std::array<int, 3>>& k)
{
  t = jumps.t;
  k = jumps.k;
  const std::size_t n = jumps.rays.size();
  if (!kTogether) {
    for (std::size_t i = 0; i < n; ++i)
      rt::advanceBelow(jumps.rays[i], jumps.targets[i], t[i].data(), k[i].data());
    return;
  }
  for (std::size_t i = 0; i < n; i += rt::kRaysTogether) {
    const int count = static_cast<int>(std::min<std::size_t>(rt::kRaysTogether, n - i));
    const rt::MarchRay* rays[rt::kRaysTogether];
    double group_t[rt::kRaysTogether][3];
    int group_k[rt::kRaysTogether][3];
    for (int g = 0; g < count; ++g) { // in and out as startRaysInRegion copies them
      const std::size_t j = i + static_cast<std::size_t>(g);
      rays[g] = &jumps.rays[j];
      std::copy(t[j].begin(), t[j].end(), group_t[g]);
      std::copy(k[j].begin(), k[j].end(), group_k[g]);
    }
    rt::advanceBelowTogether(rays, &jumps.targets[i], group_t, group_k, count);
    for (int g = 0; g < count; ++g) {
      const std::size_t j = i + static_cast<std::size_t>(g);
      std::copy(group_t[g], group_t[g] + 3, t[j].begin());
      std::copy(group_k[g], group_k[g] + 3, k[j].begin());
    }
  }
}

/// Counters: ns_per_ray and, four together, same_states (1: each ray's state is the
/// one-at-a-time advance's, bit for bit).
template <bool kTogether>
void BM_FirstJumps(benchmark::State& state)
{
  const FirstJumps jumps(frame());
  std::vector<std::array<double, 3>> t;
  std::vector<std::array<int, 3>> k;
  double seconds = 0.0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    advanceFirstJumps<kTogether>(jumps, t, k);
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    state.SetIterationTime(s);
    seconds += s;
  }
  state.counters["ns_per_ray"] =
      seconds * 1e9 /
      (static_cast<double>(jumps.rays.size()) * static_cast<double>(state.iterations()));
  if (kTogether) {
    std::vector<std::array<double, 3>> t1;
    std::vector<std::array<int, 3>> k1;
    advanceFirstJumps<false>(jumps, t1, k1);
    state.counters["same_states"] =
        std::memcmp(t.data(), t1.data(), t.size() * sizeof t[0]) == 0 && k == k1 ? 1.0
                                                                                 : 0.0;
  }
}

/// Times `Walk` over the frame, the bitset cleared before each iteration. Counters:
/// steps, ns_per_step and, for the lockstep walks, same_voxels (1: their bitset is the
/// library's walk's).
template <long long (*Walk)(const Frame&, Bitset&), bool kLockstep>
void BM_Walk(benchmark::State& state)
{
  if (kLockstep && !__builtin_cpu_supports("avx2")) {
    state.SkipWithError("this CPU has no AVX2");
    return;
  }
  const Frame& f = frame();
  int base[3];
  f.keyBase(base);
  Bitset bits(base);
  long long steps = 0;
  double seconds = 0.0;
  for (auto _ : state) {
    bits.clear();
    const auto start = std::chrono::steady_clock::now();
    steps = Walk(f, bits);
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    state.SetIterationTime(s);
    seconds += s;
  }
  state.counters["steps"] = static_cast<double>(steps);
  state.counters["ns_per_step"] =
      seconds * 1e9 /
      (static_cast<double>(steps) * static_cast<double>(state.iterations()));
  if (kLockstep) {
    Bitset reference(base);
    walkOneAtATime(f, reference);
    state.counters["same_voxels"] = bits == reference ? 1.0 : 0.0;
  }
}

BENCHMARK_TEMPLATE(BM_Walk, walkOneAtATime, false)
    ->Name("BM_OneAtATime")
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(5);
BENCHMARK_TEMPLATE(BM_Walk, walkInLockstep4, true)
    ->Name("BM_Lockstep4")
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(5);
BENCHMARK_TEMPLATE(BM_Walk, walkInLockstep8, true)
    ->Name("BM_Lockstep8")
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(5);

BENCHMARK_TEMPLATE(BM_FirstJumps, false)
    ->Name("BM_FirstJumpsOneAtATime")
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(5);
BENCHMARK_TEMPLATE(BM_FirstJumps, true)
    ->Name("BM_FirstJumpsTogether")
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime()
    ->Iterations(5);

} // namespace

BENCHMARK_MAIN();
