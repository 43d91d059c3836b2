#include <mutex>

#include <plantnbv/io/input_limits.h>

namespace plantnbv {
namespace io {

namespace {

// A mutex rather than std::atomic<InputLimits>: the struct is 24 bytes, which is not
// lock-free on every target, and it is read once per file.
std::mutex& limitsMutex()
{
  static std::mutex m;
  return m;
}

InputLimits& limitsStorage()
{
  static InputLimits limits;
  return limits;
}

} // namespace

InputLimits defaultInputLimits()
{
  std::lock_guard<std::mutex> lock(limitsMutex());
  return limitsStorage();
}

void setDefaultInputLimits(const InputLimits& limits)
{
  std::lock_guard<std::mutex> lock(limitsMutex());
  limitsStorage() = limits;
}

} // namespace io
} // namespace plantnbv
