#include <plantnbv/io/depth_image_io.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <vector>

#include <png.h>

#include <plantnbv/common/error.h>

namespace plantnbv {
namespace io {

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
  std::vector<png_uint_16> pixels(depth_m.size(), 0);
  for (std::size_t i = 0; i < depth_m.size(); ++i) {
    const double units = std::round(double(depth_m[i]) * units_per_metre);
    if (units >= 1.0 && units <= 65535.0) // NaN fails both
      pixels[i] = static_cast<png_uint_16>(units);
  }
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = width;
  image.height = height;
  image.format = PNG_FORMAT_LINEAR_Y;
  if (!png_image_write_to_file(&image, path.c_str(), 0, pixels.data(), 0, nullptr))
    throw IoError("cannot write depth image '" + path + "': " + image.message);
}

void loadDepthPng(const std::string& path, std::uint32_t& width, std::uint32_t& height,
                  std::vector<float>& depth_m, double units_per_metre)
{
  if (!(units_per_metre > 0.0) || !std::isfinite(units_per_metre))
    throw InvalidArgumentError("loadDepthPng: units_per_metre must be > 0, got " +
                               std::to_string(units_per_metre));
  if (!std::ifstream(path, std::ios::binary))
    throw IoError("cannot read depth image '" + path + "'");
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
  image.format = PNG_FORMAT_LINEAR_Y;
  std::vector<png_uint_16> pixels(std::size_t(image.width) * image.height);
  if (!png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr))
    throw FormatError("cannot decode depth image '" + path + "': " + image.message);
  width = image.width;
  height = image.height;
  depth_m.resize(pixels.size());
  for (std::size_t i = 0; i < pixels.size(); ++i)
    depth_m[i] = pixels[i] == 0 ? std::numeric_limits<float>::quiet_NaN()
                                : float(pixels[i] / units_per_metre);
}

} // namespace io
} // namespace plantnbv
