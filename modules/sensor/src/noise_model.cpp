#include <cmath>
#include <sstream>

#include <plantnbv/common/error.h>
#include <plantnbv/sensor/noise_model.h>

namespace plantnbv {

namespace {

void requireInRange(double value, double lo, double hi, const char* name,
                    const char* expected)
{
  if (!(std::isfinite(value) && value >= lo && value <= hi)) {
    std::ostringstream s;
    s << "NoiseConfig::" << name << " = " << value << " must be " << expected;
    throw InvalidArgumentError(s.str());
  }
}

constexpr double kInf = HUGE_VAL;

} // namespace

double NoiseConfig::grazingDropoutProbability(double incidence_rad) const
{
  if (incidence_rad < grazing_start_rad)
    return 0.0;
  if (incidence_rad >= grazing_end_rad)
    return 1.0;
  return (incidence_rad - grazing_start_rad) / (grazing_end_rad - grazing_start_rad);
}

void NoiseConfig::validate() const
{
  requireInRange(axial_sigma_m, 0.0, kInf, "axial_sigma_m", "finite and >= 0");
  requireInRange(axial_sigma_per_m, 0.0, kInf, "axial_sigma_per_m", "finite and >= 0");
  requireInRange(lateral_sigma_px, 0.0, kInf, "lateral_sigma_px", "finite and >= 0");
  requireInRange(grazing_start_rad, 0.0, M_PI / 2, "grazing_start_rad", "in [0, pi/2]");
  requireInRange(grazing_end_rad, grazing_start_rad, M_PI / 2, "grazing_end_rad",
                 "in [grazing_start_rad, pi/2]");
  requireInRange(edge_jump_m, 0.0, kInf, "edge_jump_m", "finite and > 0");
  if (edge_jump_m == 0.0)
    throw InvalidArgumentError("NoiseConfig::edge_jump_m = 0 must be > 0");
  requireInRange(edge_dropout_probability, 0.0, 1.0, "edge_dropout_probability",
                 "in [0, 1]");
}

std::string NoiseConfig::toString() const
{
  std::ostringstream s;
  s << "enabled: " << (enabled ? "true" : "false") << "\nseed: " << seed
    << "\naxial_sigma_m: " << axial_sigma_m
    << "\naxial_sigma_per_m: " << axial_sigma_per_m
    << "\nlateral_sigma_px: " << lateral_sigma_px
    << "\ngrazing_start_rad: " << grazing_start_rad
    << "\ngrazing_end_rad: " << grazing_end_rad << "\nedge_jump_m: " << edge_jump_m
    << "\nedge_dropout_probability: " << edge_dropout_probability << "\n";
  return s.str();
}

} // namespace plantnbv
