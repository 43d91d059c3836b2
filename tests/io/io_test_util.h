#pragma once
// Helpers of the io tests: a per-test scratch directory, fixtures, exception messages.

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include <gtest/gtest.h>

namespace plantnbv {
namespace test {

class TempDir {
public:
  TempDir()
  {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = "plantnbv_io_" + std::string(info->test_suite_name()) + "_" +
                       info->name() + "_" + std::to_string(::getpid());
    // Parameterized tests have "/" in their names.
    std::replace(name.begin(), name.end(), '/', '_');
    path_ = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir()
  {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  /// The path of `name` inside the directory.
  std::string file(const std::string& name) const { return (path_ / name).string(); }

  /// Writes `content` byte for byte to `name` and returns its path.
  std::string write(const std::string& name, const std::string& content) const
  {
    const std::string p = file(name);
    std::ofstream out(p, std::ios::binary);
    out << content;
    return p;
  }

private:
  std::filesystem::path path_;
};

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
