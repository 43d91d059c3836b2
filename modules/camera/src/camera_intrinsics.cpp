#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/common/error.h>

namespace plantnbv {

namespace {

constexpr std::uint32_t kMaxSide = 16384;

/// tan(35 deg): half the L515's 70 deg horizontal field of view.
const double kTanHalfL515Hfov = std::tan(35.0 * M_PI / 180.0);

std::string describe(double value)
{
  std::ostringstream s;
  s << value;
  return s.str();
}

} // namespace

CameraIntrinsics CameraIntrinsics::l515(L515Mode mode)
{
  CameraIntrinsics c;
  switch (mode) {
  case L515Mode::xga_1024x768:
    c.width = 1024;
    c.height = 768;
    break;
  case L515Mode::vga_640x480:
    c.width = 640;
    c.height = 480;
    break;
  case L515Mode::qvga_320x240:
    c.width = 320;
    c.height = 240;
    break;
  default:
    throw InvalidArgumentError("CameraIntrinsics::l515: unknown mode " +
                               std::to_string(int(mode)));
  }
  c.fx = c.fy = 0.5 * c.width / kTanHalfL515Hfov;
  c.cx = 0.5 * (c.width - 1.0);
  c.cy = 0.5 * (c.height - 1.0);
  c.min_range_m = 0.25;
  c.max_range_m = 9.0;
  return c;
}

CameraIntrinsics CameraIntrinsics::custom(std::uint32_t width, std::uint32_t height,
                                          double fx, double fy, double cx, double cy)
{
  CameraIntrinsics c;
  c.width = width;
  c.height = height;
  c.fx = fx;
  c.fy = fy;
  c.cx = cx;
  c.cy = cy;
  c.validate();
  return c;
}

double CameraIntrinsics::horizontalFov() const
{
  return std::atan((cx + 0.5) / fx) + std::atan((width - 0.5 - cx) / fx);
}

double CameraIntrinsics::verticalFov() const
{
  return std::atan((cy + 0.5) / fy) + std::atan((height - 0.5 - cy) / fy);
}

void CameraIntrinsics::validate() const
{
  if (width < 1 || width > kMaxSide)
    throw InvalidArgumentError("camera width " + std::to_string(width) +
                               " must be in [1, " + std::to_string(kMaxSide) + "]");
  if (height < 1 || height > kMaxSide)
    throw InvalidArgumentError("camera height " + std::to_string(height) +
                               " must be in [1, " + std::to_string(kMaxSide) + "]");
  if (!(std::isfinite(fx) && fx > 0.0))
    throw InvalidArgumentError("camera fx = " + describe(fx) + " must be finite and > 0");
  if (!(std::isfinite(fy) && fy > 0.0))
    throw InvalidArgumentError("camera fy = " + describe(fy) + " must be finite and > 0");
  if (!std::isfinite(cx))
    throw InvalidArgumentError("camera cx = " + describe(cx) + " must be finite");
  if (!std::isfinite(cy))
    throw InvalidArgumentError("camera cy = " + describe(cy) + " must be finite");
  if (!(std::isfinite(min_range_m) && min_range_m >= 0.0))
    throw InvalidArgumentError("camera min_range_m = " + describe(min_range_m) +
                               " must be finite and >= 0");
  if (!(std::isfinite(max_range_m) && max_range_m > min_range_m))
    throw InvalidArgumentError(
        "camera max_range_m = " + describe(max_range_m) +
        " must be finite and > min_range_m = " + describe(min_range_m));
}

std::string CameraIntrinsics::toString() const
{
  std::ostringstream s;
  s << width << "x" << height << " fx=" << fx << " fy=" << fy << " cx=" << cx
    << " cy=" << cy << " range=[" << min_range_m << ", " << max_range_m << "] m";
  return s.str();
}

namespace {

[[noreturn]] void badSpec(const std::string& spec, const std::string& why)
{
  throw InvalidArgumentError("camera '" + spec + "': " + why +
                             "; expected l515, l515-1024, l515-640, l515-320 or "
                             "WxH:fx,fy,cx,cy (e.g. 640x480:457,457,319.5,239.5)");
}

std::uint32_t parseSide(const std::string& text, const std::string& spec)
{
  if (text.empty() || text.size() > 6 ||
      !std::all_of(text.begin(), text.end(), [](char c) { return std::isdigit(c); }))
    badSpec(spec, "image size '" + text + "' is not a positive integer");
  return std::uint32_t(std::stoul(text));
}

double parseNumber(const std::string& text, const std::string& spec)
{
  const char* begin = text.c_str();
  char* end = nullptr;
  const double value = std::strtod(begin, &end);
  if (text.empty() || end != begin + text.size())
    badSpec(spec, "'" + text + "' is not a number");
  return value;
}

} // namespace

CameraIntrinsics parseCameraIntrinsics(const std::string& spec)
{
  std::string lower = spec;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (lower == "l515" || lower == "l515-1024")
    return CameraIntrinsics::l515(L515Mode::xga_1024x768);
  if (lower == "l515-640")
    return CameraIntrinsics::l515(L515Mode::vga_640x480);
  if (lower == "l515-320")
    return CameraIntrinsics::l515(L515Mode::qvga_320x240);

  const std::size_t colon = lower.find(':');
  const std::size_t x = lower.find('x');
  if (colon == std::string::npos || x == std::string::npos || x > colon)
    badSpec(spec, "unknown camera");
  const std::uint32_t width = parseSide(lower.substr(0, x), spec);
  const std::uint32_t height = parseSide(lower.substr(x + 1, colon - x - 1), spec);
  std::vector<double> values;
  std::size_t start = colon + 1;
  while (true) {
    const std::size_t comma = lower.find(',', start);
    values.push_back(parseNumber(lower.substr(start, comma - start), spec));
    if (comma == std::string::npos)
      break;
    start = comma + 1;
  }
  if (values.size() != 4)
    badSpec(spec, std::to_string(values.size()) + " values after ':' (expected 4)");
  return CameraIntrinsics::custom(width, height, values[0], values[1], values[2],
                                  values[3]);
}

} // namespace plantnbv
