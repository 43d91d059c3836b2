#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/planning/cylindrical_sector_sampler.h>

using namespace plantnbv;

namespace {

/// Azimuth of `p` as seen from the axis through `base`, in [phi0, phi0 + 2 pi).
double azimuthFrom(const Eigen::Vector3d& base, const Eigen::Vector3d& p, double phi0)
{
  double a = std::atan2(p.y() - base.y(), p.x() - base.x());
  while (a < phi0)
    a += 2.0 * M_PI;
  while (a >= phi0 + 2.0 * M_PI)
    a -= 2.0 * M_PI;
  return a;
}

std::vector<Viewpoint> draw(const CylindricalSectorSampler& sampler, std::uint64_t seed)
{
  Rng rng(seed);
  std::vector<Viewpoint> out;
  sampler.sample(rng, out);
  return out;
}

} // namespace

TEST(CylindricalSectorSampler, DefaultsAreThePapers)
{
  const CylindricalSector s;
  EXPECT_EQ(s.axis_base, Eigen::Vector3d(1.0, 0.0, 0.8));
  EXPECT_DOUBLE_EQ(s.radius_m, 0.4);
  EXPECT_DOUBLE_EQ(s.height_m, 0.7);
  EXPECT_DOUBLE_EQ(s.angle_rad, M_PI / 2);
  EXPECT_TRUE(std::isnan(s.facing_rad));
  // Facing the robot at the origin: the centre line points along -x from the axis.
  EXPECT_DOUBLE_EQ(s.facingAzimuth(), M_PI);
  const CylindricalSectorSampler sampler;
  EXPECT_EQ(sampler.getRows(), 3);
  EXPECT_EQ(sampler.getCols(), 3);
  EXPECT_EQ(sampler.getSamplesPerCell(), 3);
}

TEST(CylindricalSectorSampler, CountsAre9And27And45)
{
  CylindricalSectorSampler sampler;
  for (const int k : {1, 3, 5}) {
    sampler.setSamplesPerCell(k);
    EXPECT_EQ(draw(sampler, 1).size(), static_cast<std::size_t>(9 * k));
  }
  sampler.setGrid(2, 4);
  sampler.setSamplesPerCell(2);
  EXPECT_EQ(draw(sampler, 1).size(), 16u);
}

TEST(CylindricalSectorSampler, SamplesLieOnTheSectorInTheirCellLookingAtTheAxis)
{
  CylindricalSector sector;
  sector.axis_base = Eigen::Vector3d(1.2, -0.3, 0.5);
  sector.radius_m = 0.45;
  sector.height_m = 0.6;
  sector.bottom_m = 0.1;
  sector.angle_rad = 2.0;
  sector.facing_rad = 2.5;
  CylindricalSectorSampler sampler(sector);
  sampler.setGrid(3, 4);
  sampler.setSamplesPerCell(5);
  const std::vector<Viewpoint> views = draw(sampler, 7);
  ASSERT_EQ(views.size(), 60u);
  const double phi0 = sector.facing_rad - 0.5 * sector.angle_rad;
  const double z0 = sector.axis_base.z() + sector.bottom_m;
  for (std::size_t i = 0; i < views.size(); ++i) {
    const Eigen::Vector3d& p = views[i].position;
    const Eigen::Vector2d radial(p.x() - sector.axis_base.x(), p.y() - sector.axis_base.y());
    EXPECT_NEAR(radial.norm(), sector.radius_m, 1e-12);
    const double phi = azimuthFrom(sector.axis_base, p, phi0 - 1e-9);
    EXPECT_GE(phi, phi0 - 1e-9);
    EXPECT_LE(phi, phi0 + sector.angle_rad + 1e-9);
    EXPECT_GE(p.z(), z0);
    EXPECT_LE(p.z(), z0 + sector.height_m);
    // Cell of sample i is i / k: row-major, row 0 at the bottom, col 0 at the smallest
    // azimuth.
    const int cell = static_cast<int>(i / 5);
    const int row = cell / 4, col = cell % 4;
    EXPECT_GE(p.z(), z0 + row * 0.2 - 1e-12);
    EXPECT_LE(p.z(), z0 + (row + 1) * 0.2 + 1e-12);
    EXPECT_GE(phi, phi0 + col * 0.5 - 1e-9);
    EXPECT_LE(phi, phi0 + (col + 1) * 0.5 + 1e-9);
    EXPECT_EQ(sampler.cellOf(phi, p.z()), cell);
    // The optical axis is horizontal and points at the axis point at the same height.
    const Eigen::Vector3d forward = views[i].forward();
    EXPECT_NEAR(forward.z(), 0.0, 1e-12);
    const Eigen::Vector3d to_axis =
        (Eigen::Vector3d(sector.axis_base.x(), sector.axis_base.y(), p.z()) - p).normalized();
    EXPECT_NEAR((forward - to_axis).norm(), 0.0, 1e-12);
    // No roll: the body y axis stays horizontal.
    EXPECT_NEAR((views[i].orientation * Eigen::Vector3d::UnitY()).z(), 0.0, 1e-12);
  }
}

TEST(CylindricalSectorSampler, SameSeedSameSamplesOtherSeedOthers)
{
  const CylindricalSectorSampler sampler;
  const std::vector<Viewpoint> a = draw(sampler, 42), b = draw(sampler, 42), c = draw(sampler, 43);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].position, b[i].position);
    EXPECT_EQ(a[i].orientation.coeffs(), b[i].orientation.coeffs());
  }
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    differ += a[i].position != c[i].position ? 1 : 0;
  EXPECT_EQ(differ, a.size());
}

TEST(CylindricalSectorSampler, MovingTheAxisBaseMovesAllSamples)
{
  CylindricalSector sector;
  sector.facing_rad = M_PI; // fixed, so that only the translation changes
  const CylindricalSectorSampler a(sector);
  sector.axis_base += Eigen::Vector3d(0.25, -0.5, 0.125);
  const CylindricalSectorSampler b(sector);
  const std::vector<Viewpoint> va = draw(a, 3), vb = draw(b, 3);
  ASSERT_EQ(va.size(), vb.size());
  for (std::size_t i = 0; i < va.size(); ++i) {
    EXPECT_NEAR((vb[i].position - va[i].position - Eigen::Vector3d(0.25, -0.5, 0.125)).norm(),
                0.0, 1e-12);
    EXPECT_NEAR(vb[i].orientation.angularDistance(va[i].orientation), 0.0, 1e-12);
  }
}

TEST(CylindricalSectorSampler, GridCellCentresInRowMajorOrderFromTheBottomLeft)
{
  const CylindricalSectorSampler sampler; // the paper's: phi in [3/4 pi, 5/4 pi]
  const std::vector<Viewpoint> centres = sampler.gridCellCentres();
  ASSERT_EQ(centres.size(), 9u);
  const Eigen::Vector3d base(1.0, 0.0, 0.8);
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) {
      const Viewpoint& v = centres[static_cast<std::size_t>(row * 3 + col)];
      const double phi = 0.75 * M_PI + (col + 0.5) * (0.5 * M_PI / 3.0);
      const double z = 0.8 + (row + 0.5) * (0.7 / 3.0);
      const Viewpoint expected = sampler.viewpointAt(phi, z);
      EXPECT_NEAR((v.position - expected.position).norm(), 0.0, 1e-12);
      EXPECT_NEAR(v.orientation.angularDistance(expected.orientation), 0.0, 1e-12);
      EXPECT_NEAR(v.position.z(), z, 1e-12);
      EXPECT_NEAR(azimuthFrom(base, v.position, 0.0), phi, 1e-12);
    }
  // Col 0 has the smallest azimuth: on the paper's sector that is the robot's left (y > 0).
  EXPECT_GT(centres[0].position.y(), 0.0);
  EXPECT_NEAR(centres[1].position.y(), 0.0, 1e-12);
  EXPECT_LT(centres[2].position.y(), 0.0);
}

TEST(CylindricalSectorSampler, ViewpointAtLooksAtTheAxisLikeThePapersV0)
{
  // v0 (Table 1) is 0.5 m from the axis at azimuth 135 deg, yaw -45 deg.
  CylindricalSector sector;
  sector.radius_m = 0.5;
  const CylindricalSectorSampler sampler(sector);
  const Viewpoint v = sampler.viewpointAt(0.75 * M_PI, 1.383);
  const Pose v0 = Pose::fromXyzQuat(0.646, 0.353, 1.383, 0.0, 0.0, -0.383, 0.924);
  EXPECT_NEAR((v.position - v0.position).norm(), 0.0, 1e-3);
  EXPECT_NEAR(v.orientation.angularDistance(v0.orientation), 0.0, 1e-3);
}

TEST(CylindricalSectorSampler, InvalidSettingsThrowNamingTheValue)
{
  CylindricalSectorSampler sampler;
  auto message = [](auto&& f) {
    try {
      f();
    } catch (const InvalidArgumentError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([&] { sampler.setGrid(0, 3); }).find("rows = 0"), std::string::npos);
  EXPECT_NE(message([&] { sampler.setSamplesPerCell(-1); }).find("k = -1"), std::string::npos);
  CylindricalSector s;
  s.radius_m = -0.1;
  EXPECT_NE(message([&] { sampler.setSector(s); }).find("radius_m = -0.1"), std::string::npos);
  s = CylindricalSector();
  s.angle_rad = 7.0;
  EXPECT_NE(message([&] { sampler.setSector(s); }).find("angle_rad = 7"), std::string::npos);
  s = CylindricalSector();
  s.height_m = 0.0;
  EXPECT_THROW(sampler.setSector(s), InvalidArgumentError);
  s = CylindricalSector();
  s.axis_base = Eigen::Vector3d(0.0, 0.0, 0.8); // "facing the origin" is undefined
  EXPECT_THROW(sampler.setSector(s), InvalidArgumentError);
  s.facing_rad = 0.0;
  EXPECT_NO_THROW(sampler.setSector(s));
}
