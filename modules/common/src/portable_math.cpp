#include <cmath>
#include <limits>

#include <plantnbv/common/portable_math.h>

namespace plantnbv {

namespace {

// pi/2 split in a 33-bit head and its tail (fdlibm's pio2_1, pio2_1t): k * head is exact
// for |k| < 2^20, so the reduced argument keeps its accuracy up to |x| ~ 1e5.
constexpr double kPiO2Head = 1.57079632673412561417e+00;
constexpr double kPiO2Tail = 6.07710050650619224932e-11;
constexpr double kTwoOverPi = 6.36619772367581382433e-01;

// Minimax coefficients of fdlibm's __kernel_sin and __kernel_cos on [-pi/4, pi/4].
constexpr double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03,
                 S3 = -1.98412698298579493134e-04, S4 = 2.75573137070700676789e-06,
                 S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
constexpr double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03,
                 C3 = 2.48015872894767294178e-05, C4 = -2.75573143513906633035e-07,
                 C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;

double kernelSin(double r)
{
  const double z = r * r;
  return r + r * z * (S1 + z * (S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)))));
}

double kernelCos(double r)
{
  const double z = r * r;
  return 1.0 - 0.5 * z +
         z * z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
}

} // namespace

void portableSinCos(double x, double& s, double& c)
{
  if (!std::isfinite(x)) {
    s = c = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  const double k = std::floor(x * kTwoOverPi + 0.5);
  const double r = (x - k * kPiO2Head) - k * kPiO2Tail;
  const double sr = kernelSin(r), cr = kernelCos(r);
  // k mod 4 picks the quadrant; fmod of an integer-valued double is exact.
  double q = std::fmod(k, 4.0);
  if (q < 0.0)
    q += 4.0;
  switch (static_cast<int>(q)) {
  case 0:
    s = sr, c = cr;
    break;
  case 1:
    s = cr, c = -sr;
    break;
  case 2:
    s = -sr, c = -cr;
    break;
  default:
    s = -cr, c = sr;
    break;
  }
}

double portableSin(double x)
{
  double s, c;
  portableSinCos(x, s, c);
  return s;
}

double portableCos(double x)
{
  double s, c;
  portableSinCos(x, s, c);
  return c;
}

} // namespace plantnbv
