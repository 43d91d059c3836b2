#pragma once
/// \file random.h
/// \brief Seeded, portable randomness. The standard distributions are
/// implementation-defined, so draws are made here from the raw 64-bit engine: the same
/// seed gives the same numbers with any compiler or standard library.

#include <cstdint>
#include <random>

namespace plantnbv {

/// \brief Mixes a 64-bit value (SplitMix64 finaliser); used to derive independent seeds.
std::uint64_t mixSeed(std::uint64_t x);

/// \brief The seed of one trial (or one work item) from a campaign seed and a stable id.
/// Results then depend on neither the thread count nor the order of execution.
std::uint64_t deriveSeed(std::uint64_t base_seed, std::uint64_t id);

/// \brief A seeded random generator with portable draws.
class Rng {
public:
  /// \brief A generator whose draws depend only on `seed` (mixed by mixSeed first).
  explicit Rng(std::uint64_t seed) : engine_(mixSeed(seed)) {}

  /// \brief Uniform in [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  /// \brief Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// \brief Uniform integer in [0, n). \pre n > 0.
  std::uint64_t index(std::uint64_t n);
  /// \brief Standard normal (Box-Muller; one draw per call, the pair's twin discarded).
  double normal();
  /// \brief The raw 64-bit engine output.
  std::uint64_t next() { return engine_(); }

private:
  std::mt19937_64 engine_;
};

} // namespace plantnbv
