// The shared ray traversal (plantnbv/octree/ray_traversal.h) that the fast gain relies
// on: the same voxels as OctoMap's computeRayKeys, and exact jumps.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <plantnbv/common/random.h>
#include <plantnbv/octree/ray_traversal.h>

namespace rt = plantnbv::ray_traversal;

namespace {

struct KeyCollector {
  std::vector<octomap::OcTreeKey> keys;
  void begin(int kx, int ky, int kz, const int*) { add(kx, ky, kz); }
  void next(int, int kx, int ky, int kz, double) { add(kx, ky, kz); }
  void add(int kx, int ky, int kz)
  {
    keys.emplace_back(static_cast<octomap::key_type>(kx),
                      static_cast<octomap::key_type>(ky),
                      static_cast<octomap::key_type>(kz));
  }
};

} // namespace

TEST(RayTraversal, SameVoxelsAsOctoMapsComputeRayKeys)
{
  const double res = 0.003;
  const plantnbv::VoxelLattice lattice(res);
  octomap::OcTree tree(res);
  plantnbv::Rng rng(11);
  octomap::KeyRay ray;
  for (int i = 0; i < 3000; ++i) {
    float o[3], e[3];
    for (int a = 0; a < 3; ++a) {
      o[a] = static_cast<float>(rng.uniform(-1.0, 1.0));
      e[a] = static_cast<float>(o[a] + rng.uniform(-0.75, 0.75));
    }
    if (i % 10 == 0)
      e[1] = o[1]; // axis-parallel components
    if (i % 17 == 0)
      e[0] = o[0] + 0.001f; // within one or two voxels
    int ko[3], ke[3];
    ASSERT_TRUE(lattice.coordToKey(o, ko));
    ASSERT_TRUE(lattice.coordToKey(e, ke));
    KeyCollector ours;
    rt::traverseRay(o, e, ko, ke, lattice, ours);
    ASSERT_TRUE(tree.computeRayKeys(octomap::point3d(o[0], o[1], o[2]),
                                    octomap::point3d(e[0], e[1], e[2]), ray));
    const std::vector<octomap::OcTreeKey> theirs(ray.begin(), ray.end());
    ASSERT_EQ(ours.keys, theirs) << "segment " << i;
  }
}

TEST(RayTraversal, AdvanceWhileBelowEqualsSequentialAdditions)
{
  plantnbv::Rng rng(5);
  for (int i = 0; i < 200000; ++i) {
    double t = rng.uniform() * (i % 3 == 0 ? 1e-3 : 0.8);
    double delta = 0.003 / (0.05 + rng.uniform());
    const double target = t + rng.uniform() * 2.0;
    if (i % 11 == 0)
      t = 0.0;
    if (i % 13 == 0) {
      // delta an odd number of half ulps of t's binade: ties-to-even alternates.
      int e;
      std::frexp(std::max(t, 1e-3), &e);
      delta = std::ldexp(std::floor(delta / std::ldexp(1.0, e - 53)) + 0.5, e - 53);
    }
    double a = t;
    long long na = 0;
    while (a < target) {
      a += delta;
      ++na;
    }
    double b = t;
    const long long nb = rt::advanceWhileBelow(b, delta, target);
    ASSERT_EQ(na, nb) << "t " << t << " delta " << delta << " target " << target;
    ASSERT_EQ(a, b) << "t " << t << " delta " << delta << " target " << target;
  }
}

TEST(RayTraversal, JumpingPerAxisGivesTheStepByStepState)
{
  // OctoMap's steps are the merge of the axes' border crossings ordered by t: taking,
  // per axis, every addition with t_max < T gives the state of stepping while the
  // entry t of the next step is < T.
  const plantnbv::VoxelLattice lattice(0.003);
  plantnbv::Rng rng(8);
  for (int i = 0; i < 2000; ++i) {
    float o[3], e[3];
    for (int a = 0; a < 3; ++a) {
      o[a] = static_cast<float>(rng.uniform(0.0, 1.0));
      e[a] = static_cast<float>(o[a] + rng.uniform(-0.75, 0.75));
    }
    int ko[3] = {0, 0, 0}, ke[3] = {0, 0, 0};
    ASSERT_TRUE(lattice.coordToKey(o, ko));
    ASSERT_TRUE(lattice.coordToKey(e, ke));
    rt::RaySetup s;
    if (!rt::setupRay(o, e, ko, ke, lattice, s))
      continue;
    const double target = rng.uniform() * s.length;
    // Step by step, OctoMap's comparisons.
    double t[3] = {s.t_max[0], s.t_max[1], s.t_max[2]};
    int k[3] = {ko[0], ko[1], ko[2]};
    for (;;) {
      const int axis = t[0] < t[1] ? (t[0] < t[2] ? 0 : 2) : (t[1] < t[2] ? 1 : 2);
      if (!(t[axis] < target))
        break;
      k[axis] += s.step[axis];
      t[axis] += s.t_delta[axis];
    }
    double tj[3] = {s.t_max[0], s.t_max[1], s.t_max[2]};
    int kj[3] = {ko[0], ko[1], ko[2]};
    for (int a = 0; a < 3; ++a)
      kj[a] += static_cast<int>(rt::advanceWhileBelow(tj[a], s.t_delta[a], target)) *
               s.step[a];
    // advanceBelow: the three axes at once, with the march's deltas and steps.
    double tb[3] = {s.t_max[0], s.t_max[1], s.t_max[2]};
    int kb[3] = {ko[0], ko[1], ko[2]};
    rt::advanceBelow(rt::marchRay(o, s), target, tb, kb);
    for (int a = 0; a < 3; ++a) {
      ASSERT_EQ(k[a], kj[a]) << "segment " << i;
      ASSERT_EQ(t[a], tj[a]) << "segment " << i;
      ASSERT_EQ(k[a], kb[a]) << "segment " << i;
      ASSERT_EQ(t[a], tb[a]) << "segment " << i;
    }
  }
}

TEST(RayTraversal, AdvanceBelowEqualsPerAxisAdditionsForRunsOfAnyLength)
{
  // advanceBelow takes short runs axis after axis, longer ones in rounds over the axes,
  // the longest in bulk: the state is per-axis sequential additions whatever the runs'
  // lengths (up to thousands, as on rays of a few metres), their mix over the axes, and
  // axes the ray does not move along (t_max and t_delta at the double maximum, as
  // setupRay leaves them).
  plantnbv::Rng rng(17);
  const double kStill = std::numeric_limits<double>::max();
  int by_longest_run[4] = {0, 0, 0, 0}; // longest run < 16, < 64, < 256, more
  for (int i = 0; i < 100000; ++i) {
    rt::MarchRay ray{};
    double t[3];
    for (int a = 0; a < 3; ++a) {
      ray.step[a] = rng.uniform() < 0.5 ? 1 : -1;
      ray.dt[a] = 0.003 / (0.01 + rng.uniform());
      t[a] = rng.uniform() * ray.dt[a];
      if (i % 7 == a) { // an axis the ray does not move along
        ray.step[a] = 0;
        ray.dt[a] = t[a] = kStill;
      }
    }
    const int along = (i / 7) % 3 == i % 7 ? ((i / 7) + 1) % 3 : (i / 7) % 3;
    const double runs = std::pow(10.0, rng.uniform(0.0, 3.5)); // 1 to ~3000
    const double target = t[along] + runs * ray.dt[along];
    double expected_t[3];
    int expected_k[3], k[3];
    int longest = 0;
    for (int a = 0; a < 3; ++a) {
      expected_t[a] = t[a];
      expected_k[a] = k[a] = 1000;
      int n = 0;
      for (; expected_t[a] < target; ++n)
        expected_t[a] += ray.dt[a];
      expected_k[a] += n * ray.step[a];
      longest = std::max(longest, n);
    }
    ++by_longest_run[longest < 16 ? 0 : longest < 64 ? 1 : longest < 256 ? 2 : 3];
    rt::advanceBelow(ray, target, t, k);
    for (int a = 0; a < 3; ++a) {
      ASSERT_EQ(expected_t[a], t[a]) << "case " << i << " axis " << a;
      ASSERT_EQ(expected_k[a], k[a]) << "case " << i << " axis " << a;
    }
  }
  for (int c : by_longest_run)
    EXPECT_GT(c, 5000); // every length of run was tried
}

TEST(RayTraversal, AdvanceBelowTogetherEqualsEachRaysSequentialAdditions)
{
  // A frame's first jumps are advanced up to kRaysTogether rays at once (the additions
  // all of them make on an axis side by side, the rest ray by ray): each ray's state is
  // still its per-axis sequential additions, for neighbouring rays (nearly the same
  // runs) and unrelated ones, runs from none (target behind t) to thousands, and axes a
  // ray does not move along.
  plantnbv::Rng rng(23);
  const double kStill = std::numeric_limits<double>::max();
  int groups_with_long_common_runs = 0;
  for (int i = 0; i < 30000; ++i) {
    const int count = 1 + i % rt::kRaysTogether;
    const bool neighbours = (i / 4) % 2 == 0;
    rt::MarchRay rays[rt::kRaysTogether];
    const rt::MarchRay* ray_of[rt::kRaysTogether];
    double targets[rt::kRaysTogether], t[rt::kRaysTogether][3],
        expected_t[rt::kRaysTogether][3];
    int k[rt::kRaysTogether][3], expected_k[rt::kRaysTogether][3];
    const double runs = std::pow(10.0, rng.uniform(-0.5, 3.5)); // 0 to ~3000
    int shortest_run = std::numeric_limits<int>::max();
    for (int g = 0; g < count; ++g) {
      rt::MarchRay& ray = rays[g];
      ray = rt::MarchRay{};
      ray_of[g] = &ray;
      for (int a = 0; a < 3; ++a) {
        ray.step[a] = rng.uniform() < 0.5 ? 1 : -1;
        ray.dt[a] = neighbours && g > 0
                        ? rays[0].dt[a] * (1.0 + 1e-3 * rng.uniform(-1, 1))
                        : 0.003 / (0.01 + rng.uniform());
        t[g][a] = rng.uniform() * ray.dt[a];
        if ((neighbours ? i : i + g) % 11 == a) { // an axis the ray does not move along
          ray.step[a] = 0;
          ray.dt[a] = t[g][a] = kStill;
        }
      }
      const int along = ray.step[0] != 0 ? 0 : 1;
      targets[g] = neighbours && g > 0
                       ? targets[0] + rng.uniform(-3.0, 3.0) * ray.dt[along]
                       : t[g][along] + runs * rng.uniform(0.0, 1.0) * ray.dt[along];
      for (int a = 0; a < 3; ++a) {
        expected_t[g][a] = t[g][a];
        expected_k[g][a] = k[g][a] = 1000 * (g + 1);
        int n = 0;
        for (; expected_t[g][a] < targets[g]; ++n)
          expected_t[g][a] += ray.dt[a];
        expected_k[g][a] += n * ray.step[a];
        if (ray.step[a] != 0)
          shortest_run = std::min(shortest_run, n);
      }
    }
    if (count > 1 && shortest_run >= 16)
      ++groups_with_long_common_runs;
    rt::advanceBelowTogether(ray_of, targets, t, k, count);
    for (int g = 0; g < count; ++g)
      for (int a = 0; a < 3; ++a) {
        ASSERT_EQ(expected_t[g][a], t[g][a])
            << "group " << i << " ray " << g << " axis " << a;
        ASSERT_EQ(expected_k[g][a], k[g][a])
            << "group " << i << " ray " << g << " axis " << a;
      }
  }
  EXPECT_GT(groups_with_long_common_runs, 3000); // the additions side by side were made
}

namespace {

/// A region of bricks of 4^3 voxels drawn at random (about one in `one_in`).
struct RandomRegion {
  static constexpr int kBrickShift = 2;
  std::uint64_t seed;
  int one_in;
  bool containsBrick(int bx, int by, int bz) const
  {
    std::uint64_t h = seed ^ (static_cast<std::uint64_t>(bx) * 0x9E3779B97F4A7C15ull) ^
                      (static_cast<std::uint64_t>(by) * 0xC2B2AE3D27D4EB4Full) ^
                      (static_cast<std::uint64_t>(bz) * 0x165667B19E3779F9ull);
    h ^= h >> 29;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 32;
    return h % static_cast<std::uint64_t>(one_in) == 0;
  }
};

/// The voxels a region walk hands over, checking that each `next` is one step from the
/// voxel before (the last visited or the one `resume` gave).
struct RegionCollector {
  std::vector<std::array<int, 3>> keys;
  int at[3] = {0, 0, 0};
  bool steps_ok = true;
  void begin(int kx, int ky, int kz, const int*) { visit(kx, ky, kz); }
  void next(int axis, int kx, int ky, int kz, double)
  {
    const int k[3] = {kx, ky, kz};
    for (int a = 0; a < 3; ++a)
      steps_ok = steps_ok && std::abs(k[a] - at[a]) == (a == axis ? 1 : 0);
    visit(kx, ky, kz);
  }
  void resume(int kx, int ky, int kz)
  {
    at[0] = kx;
    at[1] = ky;
    at[2] = kz;
  }
  void visit(int kx, int ky, int kz)
  {
    keys.push_back({kx, ky, kz});
    resume(kx, ky, kz);
  }
};

} // namespace

TEST(RayTraversal, ARegionWalkVisitsEveryVoxelOfTheRegionInOrder)
{
  // Random segments, and segments from lattice corners along diagonals and axes, whose
  // border crossings tie or nearly tie (where the geometric march and OctoMap's sums
  // may order them differently): the region walk hands over exactly traverseRay's
  // voxels in the region, in order, and skips most of the others.
  const double res = 0.003;
  const plantnbv::VoxelLattice lattice(res);
  plantnbv::Rng rng(21);
  std::size_t visited = 0, walked = 0;
  for (int i = 0; i < 6000; ++i) {
    float o[3], e[3];
    if (i % 3 == 0) {
      const double corner[3] = {std::round(rng.uniform(0.0, 0.3) / res) * res,
                                std::round(rng.uniform(0.0, 0.3) / res) * res,
                                std::round(rng.uniform(0.0, 0.3) / res) * res};
      const double d[3] = {static_cast<double>(1 - 2 * (i % 2)), i % 5 == 0 ? 0.0 : 1.0,
                           i % 7 == 0 ? 0.0 : (i % 4 == 0 ? 1.0 : 2.0)};
      const double len =
          rng.uniform(0.1, 0.75) / std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      for (int a = 0; a < 3; ++a) {
        o[a] = static_cast<float>(corner[a] + (i % 6 == 0 ? 0.5 * res : 0.0));
        e[a] = static_cast<float>(o[a] + len * d[a]);
      }
    } else {
      for (int a = 0; a < 3; ++a) {
        o[a] = static_cast<float>(rng.uniform(0.0, 0.3));
        e[a] = static_cast<float>(o[a] + rng.uniform(-0.75, 0.75));
      }
    }
    int ko[3], ke[3];
    ASSERT_TRUE(lattice.coordToKey(o, ko));
    ASSERT_TRUE(lattice.coordToKey(e, ke));
    const RandomRegion region{static_cast<std::uint64_t>(i), i % 2 == 0 ? 40 : 4};
    KeyCollector all;
    rt::traverseRay(o, e, ko, ke, lattice, all);
    RegionCollector part;
    rt::traverseRayInRegion(o, e, ko, ke, lattice, region, part);
    ASSERT_TRUE(part.steps_ok) << "segment " << i;
    auto inRegion = [&](int kx, int ky, int kz) {
      return region.containsBrick(kx >> RandomRegion::kBrickShift,
                                  ky >> RandomRegion::kBrickShift,
                                  kz >> RandomRegion::kBrickShift);
    };
    std::vector<std::array<int, 3>> expected, got;
    for (const octomap::OcTreeKey& k : all.keys)
      if (inRegion(k[0], k[1], k[2]))
        expected.push_back({k[0], k[1], k[2]});
    for (const auto& k : part.keys)
      if (inRegion(k[0], k[1], k[2]))
        got.push_back(k);
    ASSERT_EQ(expected, got) << "segment " << i;
    visited += all.keys.size();
    walked += part.keys.size();
  }
  EXPECT_LT(walked * 4, visited * 3); // the sparse regions' rays jumped
}
