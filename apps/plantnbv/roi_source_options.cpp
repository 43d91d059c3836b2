#include "roi_source_options.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <plantnbv/common/box.h>

namespace plantnbv {
namespace app {

void addRoiSourceOptions(CLI::App& cmd, scenario::RoiSourceOverrides& o,
                         const std::string& seed, RoiSourceInput input)
{
  const bool simulation = input == RoiSourceInput::simulation;
  cmd.add_option("--roi-source", o.source,
                 "Where the attended ROI comes from: oracle (the boxes as given; "
                 "default), noisy (each box moved by a Gaussian error, seeded by " +
                     seed + "), " +
                     (simulation ? "detections (a simulated detector's finds, fused), "
                                 : "detections (the --roi file of fused detections, "
                                   "from `integrate --roi-out`), ") +
                     "prior (leaf nodes predicted along the stem in the map) or "
                     "detections+prior (the prior anchored on the detections)");
  cmd.add_option("--roi-sigma", o.sigma_m,
                 "noisy: standard deviation of each box centre's error per axis, metres");
  cmd.add_option("--roi-scale", o.scale,
                 "noisy: factor on every box's sides (default 1)");
  cmd.add_option("--prior-internode", o.prior_internode_m,
                 "prior: distance between leaf nodes along the stem, metres (default "
                 "0.04)");
  cmd.add_option("--detections-explore-views", o.detections_explore_views,
                 std::string("detections: explore the whole plant while at most this "
                             "many views have been taken") +
                     (simulation ? "" : " (--visited's poses; none given: 0)") +
                     ", then attend to the finds (default 1; 0: attend from the first "
                     "plan)");
  if (!simulation)
    return;
  cmd.add_option("--detector-recall", o.detector_recall,
                 "detections: probability that the detector finds a visible object "
                 "(default 1)");
  cmd.add_option("--detector-false-positives", o.detector_false_positives,
                 "detections: false detections per frame, on average (default 0)");
  cmd.add_option("--detector-box-jitter", o.detector_box_jitter_px,
                 "detections: standard deviation of each box edge's error, pixels "
                 "(default 0; needs --detector-masks false)");
  cmd.add_option("--detector-mask-dilation", o.detector_mask_dilation_px,
                 "detections: grow (> 0) or shrink (< 0) the masks by this many pixels "
                 "(default 0)");
  cmd.add_option("--detector-masks", o.detector_masks,
                 "detections: instance masks (true, default) or boxes only (false)");
}

nlohmann::json roiBoxesJson(const Roi& roi)
{
  nlohmann::json boxes = nlohmann::json::array();
  for (const Box& b : roi.boxes())
    boxes.push_back({{"name", b.name},
                     {"center", {b.center.x(), b.center.y(), b.center.z()}},
                     {"size", {b.size.x(), b.size.y(), b.size.z()}}});
  return boxes;
}

} // namespace app
} // namespace plantnbv
