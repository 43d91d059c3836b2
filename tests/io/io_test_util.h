#pragma once
// Helpers of the io tests: fixtures, exception messages (and TempDir, temp_dir.h).

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include <gtest/gtest.h>

#include "temp_dir.h"

namespace plantnbv {
namespace test {

/// A committed fixture in data/fixtures.
inline std::string fixture(const std::string& name)
{
  return std::string(PLANTNBV_DATA_DIR) + "/fixtures/" + name;
}

/// The message of the exception of type E that f throws; a test failure if none is thrown
/// (an exception of another type propagates and fails the test as well).
template <typename E, typename F>
std::string thrownMessage(F&& f)
{
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an exception";
  return "";
}

} // namespace test
} // namespace plantnbv
