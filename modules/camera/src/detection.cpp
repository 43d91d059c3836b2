#include <algorithm>
#include <cmath>
#include <sstream>

#include <plantnbv/camera/detection.h>
#include <plantnbv/common/error.h>

namespace plantnbv {

std::vector<std::uint32_t> detectionPixels(const Detection& d, std::uint32_t width,
                                           std::uint32_t height)
{
  const std::size_t size = std::size_t(width) * height;
  std::vector<std::uint32_t> pixels;
  if (!d.mask.empty()) {
    if (d.mask.size() != size)
      throw InvalidArgumentError("detectionPixels: a mask of " +
                                 std::to_string(d.mask.size()) + " bytes for a " +
                                 std::to_string(width) + "x" + std::to_string(height) +
                                 " image");
    for (std::size_t i = 0; i < size; ++i)
      if (d.mask[i] != 0)
        pixels.push_back(static_cast<std::uint32_t>(i));
    return pixels;
  }
  const Eigen::Vector4d& b = d.box_px;
  if (!b.allFinite()) {
    std::ostringstream s;
    s << "detectionPixels: box [" << b[0] << ", " << b[1] << ", " << b[2] << ", " << b[3]
      << "] has a non-finite number";
    throw InvalidArgumentError(s.str());
  }
  if (width == 0 || height == 0)
    return pixels;
  // u0 <= u + 0.5 <= u1: u from ceil(u0 - 0.5) to floor(u1 - 0.5), clipped to the
  // image (before the conversion to an integer, so that any finite box is defined).
  const auto first = [](double edge, std::uint32_t side) {
    return static_cast<std::int64_t>(
        std::clamp(std::ceil(edge - 0.5), 0.0, double(side)));
  };
  const auto last = [](double edge, std::uint32_t side) {
    return static_cast<std::int64_t>(
        std::clamp(std::floor(edge - 0.5), -1.0, double(side) - 1.0));
  };
  const std::int64_t u_first = first(b[0], width), u_last = last(b[2], width);
  const std::int64_t v_first = first(b[1], height), v_last = last(b[3], height);
  if (u_first > u_last || v_first > v_last)
    return pixels;
  pixels.reserve(std::size_t((u_last - u_first + 1) * (v_last - v_first + 1)));
  for (std::int64_t v = v_first; v <= v_last; ++v)
    for (std::int64_t u = u_first; u <= u_last; ++u)
      pixels.push_back(static_cast<std::uint32_t>(v * std::int64_t(width) + u));
  return pixels;
}

} // namespace plantnbv
