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

/// What one kind of grey PNG is called in messages, and its sample format.
struct GreyPngKind {
  bool sixteen_bit;          ///< 16-bit linear samples, else 8-bit
  const char* noun;          ///< "depth image", "mask"
  const char* expected_kind; ///< "a 16-bit grey PNG (a depth image)"
  const char* size_source;   ///< who gives the expected size: "camera.yaml says"
};

const GreyPngKind kDepthPng{true, "depth image", "a 16-bit grey PNG (a depth image)",
                            "camera.yaml says"};
const GreyPngKind kMaskPng{false, "mask", "an 8-bit grey PNG (an instance mask)",
                           "the depth image is"};

// libpng's simplified API: no setjmp, errors come back in png_image::message. A 16-bit
// "linear" grey image is stored as it is (libpng scales only 8-bit sRGB data); an
// 8-bit grey image is written with an sRGB chunk, which reading leaves as it is.

/// Encodes row-major grey samples (png_uint_16 or png_byte, as kind says) in memory,
/// then writes the file whole or not at all.
void saveGreyPng(const std::string& path, const GreyPngKind& kind, std::uint32_t width,
                 std::uint32_t height, const void* pixels)
{
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = width;
  image.height = height;
  image.format = kind.sixteen_bit ? PNG_FORMAT_LINEAR_Y : PNG_FORMAT_GRAY;
  png_alloc_size_t bytes = 0;
  if (!png_image_write_get_memory_size(image, bytes, 0, pixels, 0, nullptr))
    throw IoError(std::string("cannot encode ") + kind.noun + " '" + path +
                  "': " + image.message);
  std::string encoded(bytes, '\0');
  if (!png_image_write_to_memory(&image, encoded.data(), &bytes, 0, pixels, 0, nullptr))
    throw IoError(std::string("cannot encode ") + kind.noun + " '" + path +
                  "': " + image.message);
  encoded.resize(bytes);
  writeFileAtomically(path, encoded);
}

/// Reads a grey PNG of `kind` (a PNG of another sample format would be rescaled, so it
/// is refused) into row-major samples; with an expected size (not 0), a PNG of another
/// size is refused before its pixels are allocated.
template <typename Sample>
void loadGreyPng(const std::string& path, const GreyPngKind& kind, std::uint32_t& width,
                 std::uint32_t& height, std::vector<Sample>& pixels,
                 std::uint32_t expected_width, std::uint32_t expected_height)
{
  requireRegularFile(path);
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str()))
    throw FormatError("'" + path + "' is not a PNG file: " + image.message);
  const bool linear = (image.format & PNG_FORMAT_FLAG_LINEAR) != 0;
  if ((image.format & PNG_FORMAT_FLAG_COLOR) || (image.format & PNG_FORMAT_FLAG_ALPHA) ||
      linear != kind.sixteen_bit) {
    png_image_free(&image);
    throw FormatError("'" + path + "' is not " + kind.expected_kind);
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
                      std::to_string(image.height) + ", " + kind.size_source + " " +
                      std::to_string(expected_width) + "x" +
                      std::to_string(expected_height));
  }
  image.format = kind.sixteen_bit ? PNG_FORMAT_LINEAR_Y : PNG_FORMAT_GRAY;
  std::vector<Sample> read(std::size_t(image.width) * image.height);
  if (!png_image_finish_read(&image, nullptr, read.data(), 0, nullptr))
    throw FormatError(std::string("cannot decode ") + kind.noun + " '" + path +
                      "': " + image.message);
  width = image.width;
  height = image.height;
  pixels = std::move(read);
}

void loadDepthPngOfSize(const std::string& path, std::uint32_t& width,
                        std::uint32_t& height, std::vector<float>& depth_m,
                        double units_per_metre, std::uint32_t expected_width,
                        std::uint32_t expected_height)
{
  if (!(units_per_metre > 0.0) || !std::isfinite(units_per_metre))
    throw InvalidArgumentError("loadDepthPng: units_per_metre must be > 0, got " +
                               std::to_string(units_per_metre));
  std::vector<png_uint_16> pixels;
  loadGreyPng(path, kDepthPng, width, height, pixels, expected_width, expected_height);
  depth_m.resize(pixels.size());
  for (std::size_t i = 0; i < pixels.size(); ++i)
    depth_m[i] = depthFromUnits(pixels[i], units_per_metre);
}

} // namespace

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
  saveGreyPng(path, kDepthPng, width, height, pixels.data());
}

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

void saveMaskPng(const std::string& path, std::uint32_t width, std::uint32_t height,
                 const std::vector<std::uint8_t>& mask)
{
  if (width == 0 || height == 0 || std::size_t(width) * height != mask.size())
    throw InvalidArgumentError("saveMaskPng: image " + std::to_string(width) + "x" +
                               std::to_string(height) + " does not match " +
                               std::to_string(mask.size()) + " mask bytes");
  saveGreyPng(path, kMaskPng, width, height, mask.data());
}

void loadMaskPng(const std::string& path, std::uint32_t& width, std::uint32_t& height,
                 std::vector<std::uint8_t>& mask, std::uint32_t expected_width,
                 std::uint32_t expected_height)
{
  loadGreyPng(path, kMaskPng, width, height, mask, expected_width, expected_height);
}

} // namespace io
} // namespace plantnbv
