#include <cmath>

#include <plantnbv/common/random.h>

namespace plantnbv {

std::uint64_t mixSeed(std::uint64_t x)
{
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

std::uint64_t deriveSeed(std::uint64_t base_seed, std::uint64_t id)
{
  return mixSeed(mixSeed(base_seed) ^ (id * 0xd1342543de82ef95ULL + 1));
}

std::uint64_t Rng::index(std::uint64_t n)
{
  // Rejection keeps the draw exactly uniform (Lemire's bound would be faster; n is
  // small).
  const std::uint64_t limit = ~std::uint64_t{0} - (~std::uint64_t{0} % n);
  std::uint64_t x;
  do
    x = engine_();
  while (x >= limit);
  return x % n;
}

double Rng::normal()
{
  double u1;
  do
    u1 = uniform();
  while (u1 <= 0.0);
  const double u2 = uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

} // namespace plantnbv
