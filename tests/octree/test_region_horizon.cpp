// RegionHorizon (plantnbv/octree/region_horizon.h): no ray of a frame enters the update
// region before the bound of its direction, and a region walk that starts its first
// march there hands over the same voxels.

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include <plantnbv/common/random.h>
#include <plantnbv/octree/ray_traversal.h>
#include <plantnbv/octree/region_horizon.h>
#include <plantnbv/octree/update_region.h>

namespace rt = plantnbv::ray_traversal;
using plantnbv::Box;
using plantnbv::RegionHorizon;
using plantnbv::UpdateRegion;

namespace {

constexpr double kRes = 0.003;

/// Three uniform draws in order (the order of a constructor's arguments is the
/// compiler's: GCC and clang would build other scenes).
Eigen::Vector3d uniform3(plantnbv::Rng& rng, double lo, double hi)
{
  Eigen::Vector3d v;
  for (int a = 0; a < 3; ++a)
    v[a] = rng.uniform(lo, hi);
  return v;
}

/// Three normal draws in order.
Eigen::Vector3d normal3(plantnbv::Rng& rng)
{
  Eigen::Vector3d v;
  for (int a = 0; a < 3; ++a)
    v[a] = rng.normal();
  return v;
}
constexpr double kMaxRange = 0.75;

/// A scene's region: boxes, and the bricks around thin slanted triangles (leaves, a
/// floor), within bounds of 2.4 m around the origin of the lattice (a trial's reach
/// beyond the cameras).
UpdateRegion randomRegion(plantnbv::Rng& rng, double res = kRes)
{
  UpdateRegion region(res, Box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(2.4)));
  for (int i = 0; i < 6; ++i) {
    const Eigen::Vector3d centre = uniform3(rng, -0.5, 0.5);
    const Eigen::Vector3d size = uniform3(rng, 0.005, 0.1);
    region.addBox(Box(centre, size), 2.0 * res);
  }
  plantnbv::TriangleMesh mesh;
  for (int i = 0; i < 40; ++i) {
    const Eigen::Vector3f a = uniform3(rng, -0.6, 0.6).cast<float>();
    const auto v = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back(a);
    mesh.vertices.push_back(a + Eigen::Vector3f(0.08f, 0.01f, 0.02f));
    mesh.vertices.push_back(a + Eigen::Vector3f(0.02f, 0.06f, -0.03f));
    mesh.triangles.push_back({v, v + 1, v + 2});
  }
  region.addMesh(mesh, res);
  return region;
}

/// The rays of a frame: from `origin`, within 75 degrees of `axis` (some outside the
/// horizon's 60), at most kMaxRange long; every fourth along a lattice diagonal or axis,
/// where border crossings tie.
std::vector<std::array<float, 3>> randomEnds(plantnbv::Rng& rng, const float origin[3],
                                             const Eigen::Vector3d& axis, int count)
{
  std::vector<std::array<float, 3>> ends;
  while (static_cast<int>(ends.size()) < count) {
    Eigen::Vector3d d = normal3(rng);
    if (ends.size() % 4 == 0)
      d = Eigen::Vector3d(std::round(d.x()), std::round(d.y()), std::round(d.z()));
    if (d.norm() == 0.0 || d.normalized().dot(axis) < std::cos(75.0 * M_PI / 180.0))
      continue;
    d = d.normalized() * rng.uniform(0.02, kMaxRange);
    ends.push_back({static_cast<float>(origin[0] + d.x()),
                    static_cast<float>(origin[1] + d.y()),
                    static_cast<float>(origin[2] + d.z())});
  }
  return ends;
}

/// Where the exact walk (traverseRay) first enters a voxel of the region, or -1.
struct FirstEntry {
  const UpdateRegion& region;
  double t = -1.0;
  bool begin(int kx, int ky, int kz, const int*) { return !found(kx, ky, kz, 0.0); }
  bool next(int, int kx, int ky, int kz, double t_entry)
  {
    return !found(kx, ky, kz, t_entry);
  }
  bool found(int kx, int ky, int kz, double t_entry)
  {
    if (region.containsKey(kx, ky, kz))
      t = t_entry;
    return t >= 0.0;
  }
};

/// The region's voxels a walk hands over, in order, and whether each `next` is one step
/// from the voxel before (the last handed over, or the one `resume` gave).
struct RegionVoxels {
  explicit RegionVoxels(const UpdateRegion& r) : region(r) {}
  const UpdateRegion& region;
  std::vector<std::array<int, 3>> keys;
  std::array<int, 3> at = {0, 0, 0};
  bool one_step_each = true;
  void begin(int kx, int ky, int kz, const int*) { take({kx, ky, kz}); }
  void next(int axis, int kx, int ky, int kz, double)
  {
    const std::array<int, 3> k = {kx, ky, kz};
    for (int a = 0; a < 3; ++a)
      one_step_each = one_step_each && std::abs(k[a] - at[a]) == (a == axis ? 1 : 0);
    take(k);
  }
  void resume(int kx, int ky, int kz) { at = {kx, ky, kz}; }
  void take(const std::array<int, 3>& k)
  {
    at = k;
    if (region.containsKey(k[0], k[1], k[2]))
      keys.push_back(k);
  }
};

} // namespace

TEST(RegionHorizon, NoRayEntersTheRegionBeforeTheBoundOfItsDirection)
{
  // Random regions of boxes and slanted triangles, origins anywhere in them (in every
  // fourth scene in a brick of the region), rays in every direction of the front: the
  // exact walk's first voxel in the region is entered at or after the bound; directions
  // beyond the plane get none. Most rays get a bound, and for those that reach the
  // region it is a good part of the way there.
  const plantnbv::VoxelLattice lattice(kRes);
  plantnbv::Rng rng(5);
  std::size_t bounded = 0, entering = 0, rays = 0;
  double bound_sum = 0.0, entry_sum = 0.0;
  for (int scene = 0; scene < 12; ++scene) {
    UpdateRegion region = randomRegion(rng);
    const float origin[3] = {static_cast<float>(rng.uniform(-0.4, 0.4)),
                             static_cast<float>(rng.uniform(-0.4, 0.4)),
                             static_cast<float>(rng.uniform(-0.4, 0.4))};
    if (scene % 4 == 3)
      region.addBox(Box(Eigen::Vector3d(origin[0], origin[1], origin[2]),
                        Eigen::Vector3d::Constant(kRes)));
    const Eigen::Vector3d axis = normal3(rng).normalized();
    RegionHorizon horizon;
    EXPECT_EQ(horizon.clearDistance(origin), 0.0); // before compute()
    horizon.compute(region, origin, axis, kMaxRange + 2.0 * kRes);
    int ko[3];
    ASSERT_TRUE(lattice.coordToKey(origin, ko));
    for (const auto& end : randomEnds(rng, origin, axis, 3000)) {
      int ke[3];
      ASSERT_TRUE(lattice.coordToKey(end.data(), ke));
      const double clear = horizon.clearDistance(end.data());
      const Eigen::Vector3d d(end[0] - origin[0], end[1] - origin[1], end[2] - origin[2]);
      const double cos_off_axis = d.normalized().dot(axis);
      if (cos_off_axis < std::cos(68.0 * M_PI / 180.0)) {
        EXPECT_EQ(clear, 0.0); // beyond the plane's corners (atan(sqrt(2) tan 60))
      }
      FirstEntry first{region};
      rt::traverseRay(origin, end.data(), ko, ke, lattice, first);
      ++rays;
      bounded += clear > 0.0;
      if (first.t >= 0.0) {
        ASSERT_LE(clear, first.t) << "scene " << scene << ", ray " << rays;
        if (scene % 4 != 3 && cos_off_axis > std::cos(M_PI / 3.0)) {
          ++entering;
          bound_sum += clear;
          entry_sum += first.t;
        }
      }
    }
  }
  EXPECT_GT(bounded * 2, rays);
  EXPECT_GT(entering, 1000u);
  EXPECT_GT(bound_sum, 0.4 * entry_sum); // half the way here: the regions are dense
}

TEST(RegionHorizon, AWalkFromTheBoundHandsOverTheSameVoxelsOfTheRegion)
{
  // traverseRayInRegion with clear_until from the horizon: the region's voxels of the
  // full walk, in order, each `next` one step from the voxel before.
  const plantnbv::VoxelLattice lattice(kRes);
  plantnbv::Rng rng(8);
  for (int scene = 0; scene < 8; ++scene) {
    const UpdateRegion region = randomRegion(rng);
    const float origin[3] = {static_cast<float>(rng.uniform(-0.4, 0.4)),
                             static_cast<float>(rng.uniform(-0.4, 0.4)),
                             static_cast<float>(rng.uniform(-0.4, 0.4))};
    const Eigen::Vector3d axis = normal3(rng).normalized();
    RegionHorizon horizon;
    horizon.compute(region, origin, axis, kMaxRange + 2.0 * kRes);
    int ko[3];
    ASSERT_TRUE(lattice.coordToKey(origin, ko));
    int i = 0;
    for (const auto& end : randomEnds(rng, origin, axis, 2000)) {
      int ke[3];
      ASSERT_TRUE(lattice.coordToKey(end.data(), ke));
      RegionVoxels all(region), from_origin(region), from_bound(region);
      rt::traverseRay(origin, end.data(), ko, ke, lattice, all);
      rt::traverseRayInRegion(origin, end.data(), ko, ke, lattice, region, from_origin);
      rt::traverseRayInRegion(origin, end.data(), ko, ke, lattice, region, from_bound,
                              horizon.clearDistance(end.data()));
      ASSERT_EQ(all.keys, from_origin.keys) << "scene " << scene << ", ray " << i;
      ASSERT_EQ(all.keys, from_bound.keys) << "scene " << scene << ", ray " << i;
      ASSERT_TRUE(from_bound.one_step_each) << "scene " << scene << ", ray " << i;
      ++i;
    }
  }
}

TEST(RegionHorizon, AMarchFromABrickCornerHandsOverTheSameVoxelsOfTheRegion)
{
  // The first march starts from the brick of the ray's point at clear_until, where the
  // ray may cross two or three brick borders at once. Rays from brick corners along
  // diagonals and axes (at 2^-8 m the corners are floats), each started at a brick
  // border it crosses before the exact walk's first voxel in the region, or as late as
  // the horizon's margin allows (a hundredth of a voxel before that voxel): the same
  // voxels of the region, in order, each `next` one step from the voxel before.
  constexpr double res = 1.0 / 256.0;
  constexpr double brick = 8.0 * res;
  const plantnbv::VoxelLattice lattice(res);
  plantnbv::Rng rng(11);
  int checked = 0, corners = 0;
  for (int scene = 0; scene < 8; ++scene) {
    const UpdateRegion region = randomRegion(rng, res);
    float origin[3];
    for (float& o : origin)
      o = static_cast<float>(brick * std::floor(rng.uniform(-12.0, 12.0)));
    int ko[3];
    ASSERT_TRUE(lattice.coordToKey(origin, ko));
    for (int i = 0; i < 2000; ++i) {
      Eigen::Vector3d d;
      for (int a = 0; a < 3; ++a)
        d[a] = std::floor(rng.uniform(-1.0, 2.0)); // -1, 0 or 1
      if (d.norm() == 0.0)
        continue;
      d = d.normalized() * rng.uniform(0.05, kMaxRange);
      const float end[3] = {static_cast<float>(origin[0] + d.x()),
                            static_cast<float>(origin[1] + d.y()),
                            static_cast<float>(origin[2] + d.z())};
      int ke[3];
      ASSERT_TRUE(lattice.coordToKey(end, ke));
      rt::RaySetup s;
      if (!rt::setupRay(origin, end, ko, ke, lattice, s))
        continue;
      FirstEntry first{region};
      rt::traverseRay(origin, end, ko, ke, lattice, first);
      const double before = first.t >= 0.0 ? first.t - 0.01 * res : s.length;
      // The brick borders the ray crosses along its longest axis (all of them on a
      // diagonal) up to `before`, the last one mostly; or `before`.
      const double longest =
          std::max({std::fabs(s.direction[0]), std::fabs(s.direction[1]),
                    std::fabs(s.direction[2])});
      const double per_brick = brick / longest;
      const int borders = static_cast<int>(std::floor(before / per_brick));
      if (borders < 1)
        continue;
      const double u = rng.uniform();
      const double clear_until =
          u < 0.25   ? before
          : u < 0.75 ? borders * per_brick
                     : (1 + static_cast<int>(rng.uniform() * borders)) * per_brick;
      RegionVoxels all(region), from_border(region);
      rt::traverseRay(origin, end, ko, ke, lattice, all);
      rt::traverseRayInRegion(origin, end, ko, ke, lattice, region, from_border,
                              clear_until);
      ASSERT_EQ(all.keys, from_border.keys) << "scene " << scene << ", ray " << i;
      ASSERT_TRUE(from_border.one_step_each) << "scene " << scene << ", ray " << i;
      ++checked;
      corners += std::count(std::begin(s.step), std::end(s.step), 0) == 0;
    }
  }
  EXPECT_GT(checked, 8000);
  EXPECT_GT(corners, 3000);
}

TEST(RegionHorizon, TheRegionInABoxGivesItsBricksThatMeetTheBox)
{
  plantnbv::Rng rng(5);
  const UpdateRegion region = randomRegion(rng);
  using Brick = std::tuple<double, double, double, double, double, double>;
  std::vector<Brick> all;
  region.forEachBrick([&](const double* lo, const double* hi) {
    all.emplace_back(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
  });
  int partial = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    // Boxes inside, across and outside the bounds, thin to wide (rows of many words).
    double box_lo[3], box_hi[3];
    for (int a = 0; a < 3; ++a) {
      const double centre = rng.uniform(-1.6, 1.6), half = rng.uniform(0.0, 0.8);
      box_lo[a] = centre - half;
      box_hi[a] = centre + half;
    }
    std::set<Brick> got;
    region.forEachBrick(box_lo, box_hi, [&](const double* lo, const double* hi) {
      EXPECT_TRUE(got.emplace(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]).second);
    });
    std::size_t meeting = 0;
    for (const Brick& b : all) {
      const double lo[3] = {std::get<0>(b), std::get<1>(b), std::get<2>(b)};
      const double hi[3] = {std::get<3>(b), std::get<4>(b), std::get<5>(b)};
      bool overlaps = true, touches = true;
      for (int a = 0; a < 3; ++a) {
        overlaps = overlaps && lo[a] < box_hi[a] && hi[a] > box_lo[a];
        touches = touches && lo[a] <= box_hi[a] && hi[a] >= box_lo[a];
      }
      if (overlaps) {
        ++meeting;
        EXPECT_EQ(got.count(b), 1u) << "trial " << trial;
      } else if (!touches) {
        EXPECT_EQ(got.count(b), 0u) << "trial " << trial;
      }
    }
    for (const Brick& b : got) // only the region's bricks
      EXPECT_EQ(std::count(all.begin(), all.end(), b), 1) << "trial " << trial;
    partial += meeting > 0 && meeting < all.size();
  }
  EXPECT_GT(partial, 100);
}

TEST(RegionHorizon, TheRegionGivesEachOfItsBricksOnceWithItsBox)
{
  plantnbv::Rng rng(3);
  const UpdateRegion region = randomRegion(rng);
  const double edge = kRes * (1 << UpdateRegion::kBrickShift);
  std::set<std::tuple<long, long, long>> seen;
  region.forEachBrick([&](const double* lo, const double* hi) {
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(hi[a] - lo[a], edge, 1e-12);
    const double centre[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]),
                              0.5 * (lo[2] + hi[2])};
    const plantnbv::VoxelLattice lattice(kRes);
    int key[3];
    const float c[3] = {static_cast<float>(centre[0]), static_cast<float>(centre[1]),
                        static_cast<float>(centre[2])};
    ASSERT_TRUE(lattice.coordToKey(c, key));
    EXPECT_TRUE(region.containsKey(key[0], key[1], key[2]));
    EXPECT_TRUE(seen.emplace(std::lround(lo[0] / edge), std::lround(lo[1] / edge),
                             std::lround(lo[2] / edge))
                    .second);
  });
  EXPECT_EQ(seen.size(), region.brickCount());
  EXPECT_GT(seen.size(), 100u);
  double lo[3], hi[3];
  region.getBounds(lo, hi);
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(lo[a], -1.2);
    EXPECT_GE(hi[a], 1.2);
    EXPECT_LT(hi[a] - lo[a], 2.4 + 2.0 * edge);
  }
}
