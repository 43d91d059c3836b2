#pragma once
// Checks of option values that CLI11 does not make itself.

#include <CLI/CLI.hpp>

namespace plantnbv {
namespace app {

/// For every option read into an unsigned type: a whole number from 0 to 2^64 - 1,
/// digits only. CLI11 would read "-5" into an unsigned by wrapping it and saturate past
/// 2^64 - 1; this refuses both with a usage error (exit 2) naming the option.
const CLI::Validator& unsignedInteger();

} // namespace app
} // namespace plantnbv
