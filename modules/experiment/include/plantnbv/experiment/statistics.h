#pragma once
/// \file statistics.h
/// \brief Summary statistics over trials: mean, sample standard deviation and the 95%
/// confidence interval of the mean with Student's t distribution (the paper's shaded
/// bands, section 4).

#include <cstddef>
#include <vector>

namespace plantnbv {

/// \brief The p-quantile of Student's t distribution with `dof` degrees of freedom
/// (p in (0, 1), dof > 0), e.g. studentTQuantile(0.975, 9) = 2.2622. Computed by
/// bisection on the CDF, written with the regularized incomplete beta function (a
/// continued fraction, Numerical Recipes 6.4); accurate to about 1e-10.
/// \throws InvalidArgumentError for p outside (0, 1) or dof <= 0.
double studentTQuantile(double p, double dof);

/// \brief Mean, sample standard deviation (n - 1) and the two-sided 95% confidence
/// interval of the mean, mean -+ t(0.975, n - 1) sd / sqrt(n), of the finite values.
struct SampleSummary {
  std::size_t n = 0;    ///< finite values (NaN ones are left out)
  double mean = 0.0;    ///< NaN when n = 0
  double sd = 0.0;      ///< NaN when n < 2
  double ci_low = 0.0;  ///< NaN when n < 2
  double ci_high = 0.0; ///< NaN when n < 2
};

/// \brief Summarizes the finite values of `values` (NaN and infinities are left out).
SampleSummary summarize(const std::vector<double>& values);

/// \brief The median of the values (the mean of the two middle ones for an even count;
/// +infinity counts as larger than any value). NaN for an empty list.
double median(std::vector<double> values);

} // namespace plantnbv
