#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <png.h>
#include <vector>

#include <plantnbv/camera/depth_image.h>
#include <plantnbv/common/error.h>
#include <plantnbv/io/depth_image_io.h>

#include "io_util.h"

namespace plantnbv {
namespace io {

namespace {

/// The largest side of a camera (CameraIntrinsics::validate): a larger PNG is refused
/// before its pixels are allocated.
constexpr png_uint_32 kMaxDepthPngSide = 16384;

} // namespace

// libpng's simplified API: no setjmp, errors come back in png_image::message. A 16-bit
// "linear" grey image is stored as it is (libpng scales only 8-bit sRGB data).

void saveDepthPng(const std::string& path, std::uint32_t width, std::uint32_t height,
                  const std::vector<float>& depth_m, double units_per_metre)
{
  if (width == 0 || height == 0 || std::size_t(width) * height != depth_m.size())
    throw InvalidArgumentError("saveDepthPng: image " + std::to_string(width) + "x" +
                               std::to_string(height) + " does not match " +
                               std::to_string(depth_m.size()) + " depth values");
  if (!(units_per_metre > 0.0) || !std::isfinite(units_per_metre))
    throw InvalidArgumentError("saveDepthPng: units_per_metre must be > 0, got " +
                               std::to_string(units_per_metre));
  std::vector<png_uint_16> pixels(depth_m.size());
  for (std::size_t i = 0; i < depth_m.size(); ++i)
    pixels[i] = depthToUnits(depth_m[i], units_per_metre);
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = width;
  image.height = height;
  image.format = PNG_FORMAT_LINEAR_Y;
  // Encoded in memory, then written whole or not at all.
  png_alloc_size_t bytes = 0;
  if (!png_image_write_get_memory_size(image, bytes, 0, pixels.data(), 0, nullptr))
    throw IoError("cannot encode depth image '" + path + "': " + image.message);
  std::string encoded(bytes, '\0');
  if (!png_image_write_to_memory(&image, encoded.data(), &bytes, 0, pixels.data(), 0,
                                 nullptr))
    throw IoError("cannot encode depth image '" + path + "': " + image.message);
  encoded.resize(bytes);
  writeFileAtomically(path, encoded);
}

namespace {

void loadDepthPngOfSize(const std::string& path, std::uint32_t& width,
                        std::uint32_t& height, std::vector<float>& depth_m,
                        double units_per_metre, std::uint32_t expected_width,
                        std::uint32_t expected_height)
{
  if (!(units_per_metre > 0.0) || !std::isfinite(units_per_metre))
    throw InvalidArgumentError("loadDepthPng: units_per_metre must be > 0, got " +
                               std::to_string(units_per_metre));
  requireRegularFile(path);
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str()))
    throw FormatError("'" + path + "' is not a PNG file: " + image.message);
  // A depth image is one 16-bit grey channel; anything else would be rescaled.
  if ((image.format & PNG_FORMAT_FLAG_COLOR) || (image.format & PNG_FORMAT_FLAG_ALPHA) ||
      !(image.format & PNG_FORMAT_FLAG_LINEAR)) {
    png_image_free(&image);
    throw FormatError("'" + path + "' is not a 16-bit grey PNG (a depth image)");
  }
  if (image.width > kMaxDepthPngSide || image.height > kMaxDepthPngSide) {
    png_image_free(&image);
    throw FormatError("'" + path + "' is " + std::to_string(image.width) + "x" +
                      std::to_string(image.height) + " pixels, more than " +
                      std::to_string(kMaxDepthPngSide) + " per side");
  }
  if (expected_width != 0 &&
      (image.width != expected_width || image.height != expected_height)) {
    png_image_free(&image);
    throw FormatError("'" + path + "' is " + std::to_string(image.width) + "x" +
                      std::to_string(image.height) + ", camera.yaml says " +
                      std::to_string(expected_width) + "x" +
                      std::to_string(expected_height));
  }
  image.format = PNG_FORMAT_LINEAR_Y;
  std::vector<png_uint_16> pixels(std::size_t(image.width) * image.height);
  if (!png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr))
    throw FormatError("cannot decode depth image '" + path + "': " + image.message);
  width = image.width;
  height = image.height;
  depth_m.resize(pixels.size());
  for (std::size_t i = 0; i < pixels.size(); ++i)
    depth_m[i] = depthFromUnits(pixels[i], units_per_metre);
}

} // namespace

void loadDepthPng(const std::string& path, std::uint32_t& width, std::uint32_t& height,
                  std::vector<float>& depth_m, double units_per_metre)
{
  loadDepthPngOfSize(path, width, height, depth_m, units_per_metre, 0, 0);
}

void loadDepthPng(const std::string& path, DepthImage& depth, double units_per_metre,
                  std::uint32_t expected_width, std::uint32_t expected_height)
{
  loadDepthPngOfSize(path, depth.width, depth.height, depth.depth_m, units_per_metre,
                     expected_width, expected_height);
}

} // namespace io
} // namespace plantnbv
