#include <cmath>
#include <sstream>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/session/roi_source.h>

namespace plantnbv {

namespace {

constexpr const char* kRoiSourceNames[] = {"oracle", "noisy"};

} // namespace

const char* roiSourceKindName(RoiSourceKind kind)
{
  return kRoiSourceNames[static_cast<int>(kind)];
}

RoiSourceKind roiSourceKindFromName(const std::string& name)
{
  for (int i = 0; i < 2; ++i)
    if (name == kRoiSourceNames[i])
      return static_cast<RoiSourceKind>(i);
  throw InvalidArgumentError("unknown ROI source '" + name +
                             "' (expected oracle or noisy)");
}

void RoiSource::validate(const std::string& option_prefix) const
{
  auto key = [&option_prefix](const char* name) {
    return option_prefix.empty() ? std::string("roi_") + name
                                 : option_prefix + "roi-" + name;
  };
  std::ostringstream s;
  s.precision(17);
  if (!(std::isfinite(sigma_m) && sigma_m >= 0.0))
    s << key("sigma") << " " << sigma_m << ": expected a finite value >= 0 (metres)";
  else if (!(std::isfinite(scale) && scale > 0.0))
    s << key("scale") << " " << scale << ": expected a finite value > 0";
  else if (kind == RoiSourceKind::oracle && (sigma_m != 0.0 || scale != 1.0))
    s << key(sigma_m != 0.0 ? "sigma" : "scale") << " "
      << (sigma_m != 0.0 ? sigma_m : scale) << ": only the noisy ROI source uses it ("
      << key("source") << " is oracle)";
  if (!s.str().empty())
    throw InvalidArgumentError(s.str());
}

Roi RoiSource::apply(const Roi& given, std::uint64_t seed) const
{
  validate();
  if (kind == RoiSourceKind::oracle)
    return given;
  Rng rng(seed);
  Roi roi;
  for (const Box& box : given.boxes()) {
    Eigen::Vector3d error;
    for (int axis = 0; axis < 3; ++axis)
      error[axis] = sigma_m * rng.normal();
    roi.addBox(Box(box.center + error, box.size * scale, box.name));
  }
  return roi;
}

} // namespace plantnbv
