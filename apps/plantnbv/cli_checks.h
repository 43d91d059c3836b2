#pragma once
// Checks of option values that CLI11 does not make itself.

#include <string>

#include <CLI/CLI.hpp>

namespace plantnbv {
namespace app {

/// For every option read into an unsigned type: a whole number from 0 to 2^64 - 1,
/// digits only. CLI11 would read "-5" into an unsigned by wrapping it and saturate past
/// 2^64 - 1; this refuses both with a usage error (exit 2) naming the option.
const CLI::Validator& unsignedInteger();

/// For a number whose magnitude is at most `max` (e.g. --yaw-deg, within one turn):
/// NaN, out of range or not a number is a usage error naming the option and the range.
CLI::Validator magnitudeAtMost(double max, const std::string& unit);

/// For an image path (--snapshot, --depth): a name ending in .png, any case; a .jpg
/// would receive PNG bytes. A usage error naming the option otherwise.
const CLI::Validator& pngPath();

/// For a count of workers such as --jobs: 0 (all cores) or a positive count up to
/// INT_MAX; anything else is a usage error "expected 0 (all cores) or a number of
/// `what`, got '-1'".
CLI::Validator workerCount(const std::string& what);

/// For a --threads option: 0 (all cores) or a positive count; a count over the
/// machine's cores (std::thread::hardware_concurrency) only slows the work down (the
/// results do not depend on it), so it is lowered to the core count with a warning on
/// stderr naming `option`. Negative or non-numeric counts are usage errors.
CLI::Validator threadCount(const std::string& option);

} // namespace app
} // namespace plantnbv
