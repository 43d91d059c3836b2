#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/statistics.h>

namespace plantnbv {

namespace {

/// Continued fraction of the incomplete beta function (modified Lentz).
double betaContinuedFraction(double a, double b, double x)
{
  const double tiny = 1e-300;
  double c = 1.0;
  double d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::abs(d) < tiny)
    d = tiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m <= 10000; ++m) {
    const double m2 = 2.0 * m;
    double aa = m * (b - m) * x / ((a - 1.0 + m2) * (a + m2));
    d = 1.0 + aa * d;
    d = std::abs(d) < tiny ? tiny : d;
    c = 1.0 + aa / c;
    c = std::abs(c) < tiny ? tiny : c;
    d = 1.0 / d;
    h *= d * c;
    aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + 1.0 + m2));
    d = 1.0 + aa * d;
    d = std::abs(d) < tiny ? tiny : d;
    c = 1.0 + aa / c;
    c = std::abs(c) < tiny ? tiny : c;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-15)
      break;
  }
  return h;
}

/// The regularized incomplete beta function I_x(a, b).
double regularizedBeta(double a, double b, double x)
{
  if (x <= 0.0)
    return 0.0;
  if (x >= 1.0)
    return 1.0;
  const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) +
                                a * std::log(x) + b * std::log1p(-x));
  if (x < (a + 1.0) / (a + b + 2.0))
    return front * betaContinuedFraction(a, b, x) / a;
  return 1.0 - front * betaContinuedFraction(b, a, 1.0 - x) / b;
}

/// P(T > t) for t >= 0.
double studentTUpperTail(double t, double dof)
{
  return 0.5 * regularizedBeta(0.5 * dof, 0.5, dof / (dof + t * t));
}

} // namespace

double studentTQuantile(double p, double dof)
{
  if (!(p > 0.0 && p < 1.0))
    throw InvalidArgumentError("t quantile: p = " + std::to_string(p) +
                               ", expected a probability in (0, 1)");
  if (!(dof > 0.0) || !std::isfinite(dof))
    throw InvalidArgumentError("t quantile: dof = " + std::to_string(dof) +
                               ", expected > 0");
  if (p == 0.5)
    return 0.0;
  const double tail = p > 0.5 ? 1.0 - p : p;
  // Bracket, then bisect: the upper tail falls monotonically in t.
  double lo = 0.0, hi = 1.0;
  while (studentTUpperTail(hi, dof) > tail && hi < 1e300)
    hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-12 * std::max(1.0, hi); ++i) {
    const double mid = 0.5 * (lo + hi);
    (studentTUpperTail(mid, dof) > tail ? lo : hi) = mid;
  }
  const double t = 0.5 * (lo + hi);
  return p > 0.5 ? t : -t;
}

SampleSummary summarize(const std::vector<double>& values)
{
  SampleSummary s;
  double sum = 0.0;
  for (double v : values)
    if (std::isfinite(v)) {
      sum += v;
      ++s.n;
    }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  s.mean = s.n ? sum / double(s.n) : nan;
  if (s.n < 2) {
    s.sd = s.ci_low = s.ci_high = nan;
    return s;
  }
  double sqr = 0.0;
  for (double v : values)
    if (std::isfinite(v))
      sqr += (v - s.mean) * (v - s.mean);
  s.sd = std::sqrt(sqr / double(s.n - 1));
  const double half =
      studentTQuantile(0.975, double(s.n - 1)) * s.sd / std::sqrt(double(s.n));
  s.ci_low = s.mean - half;
  s.ci_high = s.mean + half;
  return s;
}

double median(std::vector<double> values)
{
  if (values.empty())
    return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  if (n % 2)
    return values[n / 2];
  const double a = values[n / 2 - 1], b = values[n / 2];
  return std::isinf(a) || std::isinf(b) ? std::max(a, b) : 0.5 * (a + b);
}

} // namespace plantnbv
