#include <algorithm>
#include <cmath>
#include <sstream>

#include <plantnbv/camera/detection.h>
#include <plantnbv/common/error.h>
#include <plantnbv/common/number_text.h>
#include <plantnbv/common/random.h>
#include <plantnbv/session/roi_source.h>

namespace plantnbv {

namespace {

constexpr const char* kRoiSourceNames[] = {"oracle", "noisy", "detections", "prior",
                                           "detections+prior"};

} // namespace

const char* roiSourceKindName(RoiSourceKind kind)
{
  return kRoiSourceNames[static_cast<int>(kind)];
}

RoiSourceKind roiSourceKindFromName(const std::string& name)
{
  for (int i = 0; i < 5; ++i)
    if (name == kRoiSourceNames[i])
      return static_cast<RoiSourceKind>(i);
  throw InvalidArgumentError("unknown ROI source '" + name +
                             "' (expected oracle, noisy, detections, prior or "
                             "detections+prior)");
}

void RoiSource::validate(const std::string& option_prefix) const
{
  // A config key (roi_sigma), or with a prefix the option (--roi-sigma).
  auto key = [&option_prefix](std::string name) {
    if (!option_prefix.empty())
      std::replace(name.begin(), name.end(), '_', '-');
    return option_prefix + name;
  };
  // A value that only the `owners` sources use, set with another source.
  auto onlyFor = [&](std::ostringstream& s, const char* name, const std::string& value,
                     const char* owners) {
    s << key(name) << " " << value << ": only the " << owners << " ROI source"
      << (std::string(owners).find(" and ") == std::string::npos ? " uses" : "s use")
      << " it (" << key("roi_source") << " is " << roiSourceKindName(kind) << ")";
  };
  std::ostringstream s;
  if (!(std::isfinite(sigma_m) && sigma_m >= 0.0))
    s << key("roi_sigma") << " " << shortestText(sigma_m)
      << ": expected a finite value >= 0 (metres)";
  else if (!(std::isfinite(scale) && scale > 0.0))
    s << key("roi_scale") << " " << shortestText(scale)
      << ": expected a finite value > 0";
  else if (!(detector_recall >= 0.0 && detector_recall <= 1.0))
    s << key("detector_recall") << " " << shortestText(detector_recall)
      << ": expected a value in [0, 1]";
  else if (!(std::isfinite(detector_false_positives) && detector_false_positives >= 0.0 &&
             detector_false_positives <= 1000.0))
    s << key("detector_false_positives") << " " << shortestText(detector_false_positives)
      << ": expected a value in [0, 1000] per frame";
  else if (!(std::isfinite(detector_box_jitter_px) && detector_box_jitter_px >= 0.0 &&
             detector_box_jitter_px <= 1000.0))
    s << key("detector_box_jitter") << " " << shortestText(detector_box_jitter_px)
      << ": expected a value in [0, 1000] (pixels)";
  else if (std::abs(detector_mask_dilation_px) > kMaxMaskDilationPx)
    s << key("detector_mask_dilation") << " " << detector_mask_dilation_px
      << ": expected pixels in [" << -kMaxMaskDilationPx << ", " << kMaxMaskDilationPx
      << "]";
  else if (detections_explore_views < 0 || detections_explore_views > 1000)
    s << key("detections_explore_views") << " " << detections_explore_views
      << ": expected views in [0, 1000] (0: attend from the first plan)";
  else if (!(std::isfinite(prior_internode_m) && prior_internode_m > 0.0))
    s << key("prior_internode") << " " << shortestText(prior_internode_m)
      << ": expected a finite value > 0 (metres)";
  else if (kind != RoiSourceKind::noisy && sigma_m != 0.0)
    onlyFor(s, "roi_sigma", shortestText(sigma_m), "noisy");
  else if (kind != RoiSourceKind::noisy && scale != 1.0)
    onlyFor(s, "roi_scale", shortestText(scale), "noisy");
  else if (!detects() && detector_recall != 1.0)
    onlyFor(s, "detector_recall", shortestText(detector_recall),
            "detections and detections+prior");
  else if (!detects() && detector_false_positives != 0.0)
    onlyFor(s, "detector_false_positives", shortestText(detector_false_positives),
            "detections and detections+prior");
  else if (!detects() && detector_box_jitter_px != 0.0)
    onlyFor(s, "detector_box_jitter", shortestText(detector_box_jitter_px),
            "detections and detections+prior");
  else if (!detects() && detector_mask_dilation_px != 0)
    onlyFor(s, "detector_mask_dilation", shortestText(detector_mask_dilation_px),
            "detections and detections+prior");
  else if (!detects() && !detector_masks)
    onlyFor(s, "detector_masks", "false", "detections and detections+prior");
  else if (detector_masks && detector_box_jitter_px != 0.0)
    s << key("detector_box_jitter") << " " << shortestText(detector_box_jitter_px)
      << ": the fusion back-projects the detector's masks, not its boxes; set "
      << key("detector_masks") << " false for a boxes-only detector";
  else if (kind != RoiSourceKind::detections &&
           detections_explore_views != RoiSource().detections_explore_views)
    onlyFor(s, "detections_explore_views", std::to_string(detections_explore_views),
            "detections");
  else if (!predicts() && prior_internode_m != RoiSource().prior_internode_m)
    onlyFor(s, "prior_internode", shortestText(prior_internode_m),
            "prior and detections+prior");
  if (!s.str().empty())
    throw InvalidArgumentError(s.str());
}

LeafNodePrior::Config RoiSource::priorConfig() const
{
  LeafNodePrior::Config config;
  config.internode_m = prior_internode_m;
  return config;
}

Roi RoiSource::apply(const Roi& given, std::uint64_t seed) const
{
  validate();
  if (kind == RoiSourceKind::oracle)
    return given;
  if (followsFrames())
    return Roi(); // nothing seen yet
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
