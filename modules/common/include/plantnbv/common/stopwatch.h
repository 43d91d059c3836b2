#pragma once
/// \file stopwatch.h
/// \brief Wall-clock timing of the steps that tools and trials report.

#include <chrono>

namespace plantnbv {

/// \brief Milliseconds since construction (steady clock).
class Stopwatch {
public:
  /// \brief Milliseconds elapsed since construction.
  double ms() const
  {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() -
                                                     start_)
        .count();
  }

private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

} // namespace plantnbv
