#pragma once
// Shared by the fuzz targets: the input as a file for readers that take a path, small
// input limits, and the rule of every target: a plantnbv::Error is a normal outcome (the
// readers' documented answer to a bad file); any other exception escapes, and libFuzzer
// reports it as a crash, like a sanitizer report or a leak.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include <plantnbv/common/error.h>
#include <plantnbv/io/input_limits.h>

namespace plantnbv {
namespace fuzz {

/// Caps far below the defaults, so that an input that passes them cannot take more
/// memory than libFuzzer's -rss_limit_mb; the checks themselves are the same code.
inline void useSmallLimits()
{
  static const bool done = [] {
    io::InputLimits limits;
    limits.max_file_bytes = 1 << 20;
    limits.max_points = 1'000'000;
    limits.max_triangles = 1'000'000;
    io::setDefaultInputLimits(limits);
    return true;
  }();
  (void)done;
}

/// A directory of this process for the input files, removed at exit.
class InputDir {
public:
  InputDir()
  {
    const char* shm = "/dev/shm"; // no disk writes, when there is one
    const std::filesystem::path base =
        std::filesystem::is_directory(shm) ? shm : std::filesystem::temp_directory_path();
    path_ = base / ("plantnbv_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(path_);
  }
  ~InputDir()
  {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }

private:
  std::filesystem::path path_;
};

/// Writes the input to a file with this extension (one per extension, overwritten by
/// each run) and returns its path.
inline std::string writeInput(const std::uint8_t* data, std::size_t size,
                              const std::string& extension)
{
  static const InputDir dir;
  const std::string path = (dir.path() / ("input" + extension)).string();
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

/// Runs f; plantnbv::Error is an expected outcome, anything else escapes.
template <typename F>
void run(F&& f)
{
  try {
    f();
  } catch (const Error&) {
  }
}

} // namespace fuzz
} // namespace plantnbv
