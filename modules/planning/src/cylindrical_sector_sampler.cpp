#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Geometry>

#include <plantnbv/common/error.h>
#include <plantnbv/planning/cylindrical_sector_sampler.h>

namespace plantnbv {

namespace {

constexpr double kTwoPi = 2.0 * M_PI;

std::string rangeMessage(const char* field, double value, const char* expected)
{
  std::ostringstream s;
  s << "CylindricalSector: " << field << " = " << value << " must be " << expected;
  return s.str();
}

/// The angle in [0, 2 pi).
double wrapPositive(double a)
{
  a = std::fmod(a, kTwoPi);
  return a < 0.0 ? a + kTwoPi : a;
}

} // namespace

void CylindricalSector::validate() const
{
  if (!axis_base.allFinite()) {
    std::ostringstream s;
    s << "CylindricalSector: axis_base = (" << axis_base.x() << ", " << axis_base.y()
      << ", " << axis_base.z() << ") must be finite (metres)";
    throw InvalidArgumentError(s.str());
  }
  if (!(std::isfinite(radius_m) && radius_m > 0.0))
    throw InvalidArgumentError(rangeMessage("radius_m", radius_m, "finite and > 0 (metres)"));
  if (!(std::isfinite(height_m) && height_m > 0.0))
    throw InvalidArgumentError(rangeMessage("height_m", height_m, "finite and > 0 (metres)"));
  if (!std::isfinite(bottom_m))
    throw InvalidArgumentError(rangeMessage("bottom_m", bottom_m, "finite (metres)"));
  if (!(angle_rad > 0.0 && angle_rad <= kTwoPi))
    throw InvalidArgumentError(rangeMessage("angle_rad", angle_rad, "in (0, 2 pi] (rad)"));
  if (std::isinf(facing_rad))
    throw InvalidArgumentError(
        rangeMessage("facing_rad", facing_rad, "finite, or NaN to face the world origin"));
  if (std::isnan(facing_rad) && axis_base.x() == 0.0 && axis_base.y() == 0.0)
    throw InvalidArgumentError(
        "CylindricalSector: facing_rad = NaN (face the world origin) is undefined for an "
        "axis through the origin (axis_base.x = axis_base.y = 0): set facing_rad");
}

double CylindricalSector::facingAzimuth() const
{
  if (!std::isnan(facing_rad))
    return facing_rad;
  if (axis_base.x() == 0.0 && axis_base.y() == 0.0)
    validate(); // throws
  double a = std::atan2(-axis_base.y(), -axis_base.x());
  if (a <= -M_PI)
    a += kTwoPi; // atan2(-0, -1) = -pi: report (-pi, pi]
  return a;
}

CylindricalSectorSampler::CylindricalSectorSampler() : CylindricalSectorSampler(CylindricalSector())
{
}

CylindricalSectorSampler::CylindricalSectorSampler(const CylindricalSector& sector)
{
  setSector(sector);
}

void CylindricalSectorSampler::setSector(const CylindricalSector& sector)
{
  sector.validate();
  sector_ = sector;
}

void CylindricalSectorSampler::setGrid(int rows, int cols)
{
  if (rows < 1 || cols < 1) {
    std::ostringstream s;
    s << "CylindricalSectorSampler::setGrid: rows = " << rows << ", cols = " << cols
      << ": both must be >= 1";
    throw InvalidArgumentError(s.str());
  }
  rows_ = rows;
  cols_ = cols;
}

void CylindricalSectorSampler::setSamplesPerCell(int k)
{
  if (k < 1) {
    std::ostringstream s;
    s << "CylindricalSectorSampler::setSamplesPerCell: k = " << k << " must be >= 1";
    throw InvalidArgumentError(s.str());
  }
  samples_per_cell_ = k;
}

Viewpoint CylindricalSectorSampler::viewpointAt(double azimuth_rad, double z) const
{
  const Eigen::Vector3d position(sector_.axis_base.x() + sector_.radius_m * std::cos(azimuth_rad),
                                 sector_.axis_base.y() + sector_.radius_m * std::sin(azimuth_rad),
                                 z);
  // Body x towards the axis point at the same height: yaw = azimuth + pi.
  const Eigen::Quaterniond q(Eigen::AngleAxisd(azimuth_rad + M_PI, Eigen::Vector3d::UnitZ()));
  return Viewpoint(position, q);
}

void CylindricalSectorSampler::sample(Rng& rng, std::vector<Viewpoint>& out) const
{
  out.clear();
  out.reserve(static_cast<std::size_t>(rows_ * cols_ * samples_per_cell_));
  const double phi0 = sector_.facingAzimuth() - 0.5 * sector_.angle_rad;
  const double z0 = sector_.axis_base.z() + sector_.bottom_m;
  const double dphi = sector_.angle_rad / cols_;
  const double dz = sector_.height_m / rows_;
  for (int row = 0; row < rows_; ++row)
    for (int col = 0; col < cols_; ++col)
      for (int k = 0; k < samples_per_cell_; ++k) {
        const double u_phi = rng.uniform();
        const double u_z = rng.uniform();
        out.push_back(viewpointAt(phi0 + dphi * (col + u_phi), z0 + dz * (row + u_z)));
      }
}

std::vector<Viewpoint> CylindricalSectorSampler::gridCellCentres() const
{
  std::vector<Viewpoint> out;
  out.reserve(static_cast<std::size_t>(rows_ * cols_));
  const double phi0 = sector_.facingAzimuth() - 0.5 * sector_.angle_rad;
  const double z0 = sector_.axis_base.z() + sector_.bottom_m;
  const double dphi = sector_.angle_rad / cols_;
  const double dz = sector_.height_m / rows_;
  for (int row = 0; row < rows_; ++row)
    for (int col = 0; col < cols_; ++col)
      out.push_back(viewpointAt(phi0 + dphi * (col + 0.5), z0 + dz * (row + 0.5)));
  return out;
}

int CylindricalSectorSampler::cellOf(double azimuth_rad, double z) const
{
  const double phi0 = sector_.facingAzimuth() - 0.5 * sector_.angle_rad;
  const double z0 = sector_.axis_base.z() + sector_.bottom_m;
  const double u = wrapPositive(azimuth_rad - phi0); // along the arc from its start
  const double v = z - z0;
  if (!(u <= sector_.angle_rad) || !(v >= 0.0 && v <= sector_.height_m))
    return -1;
  const int col = std::min(cols_ - 1, static_cast<int>(u / (sector_.angle_rad / cols_)));
  const int row = std::min(rows_ - 1, static_cast<int>(v / (sector_.height_m / rows_)));
  return row * cols_ + col;
}

} // namespace plantnbv
