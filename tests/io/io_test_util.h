#pragma once
// Helpers of the io tests: fixtures, exception messages (and TempDir, temp_dir.h).

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <png.h>
#include <string>
#include <unistd.h>
#include <vector>

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

/// The bytes of a file ("" if it cannot be read).
inline std::string readBytes(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in),
                     std::istreambuf_iterator<char>());
}

/// Writes an image with libpng's simplified API in `format`, every sample `sample`.
inline void writePng(const std::string& path, std::uint32_t width, std::uint32_t height,
                     png_uint_32 format, png_byte sample)
{
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = width;
  image.height = height;
  image.format = format;
  std::vector<png_byte> pixels(PNG_IMAGE_SIZE(image), sample);
  ASSERT_NE(png_image_write_to_file(&image, path.c_str(), 0, pixels.data(), 0, nullptr),
            0)
      << image.message;
}

} // namespace test
} // namespace plantnbv
