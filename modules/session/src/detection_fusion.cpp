#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include <plantnbv/common/error.h>
#include <plantnbv/session/detection_fusion.h>

namespace plantnbv {

namespace {

/// The points of a detection: its pixels with a depth, cut to its depth cluster (the
/// nearest for a box, the median's for a mask), back-projected into the world.
std::vector<Eigen::Vector3d> detectionPoints(const Detection& d, const DepthImage& depth,
                                             const CameraIntrinsics& K, const Pose& T_W_O,
                                             double gap_m)
{
  std::vector<std::pair<float, std::uint32_t>> by_depth; // (depth, pixel)
  for (std::uint32_t i : detectionPixels(d, depth.width, depth.height)) {
    const float z = depth.depth_m[i];
    if (z > 0.0f && std::isfinite(z))
      by_depth.emplace_back(z, i);
  }
  if (by_depth.empty())
    return {};
  std::sort(by_depth.begin(), by_depth.end());
  const std::size_t seed = d.mask.empty() ? 0 : by_depth.size() / 2;
  std::size_t first = seed, last = seed;
  while (first > 0 && by_depth[first].first - by_depth[first - 1].first <= gap_m)
    --first;
  while (last + 1 < by_depth.size() &&
         by_depth[last + 1].first - by_depth[last].first <= gap_m)
    ++last;
  const Eigen::Matrix3d R = T_W_O.orientation.toRotationMatrix();
  std::vector<Eigen::Vector3d> points;
  points.reserve(last - first + 1);
  for (std::size_t k = first; k <= last; ++k) {
    const double z = by_depth[k].first;
    const std::uint32_t u = by_depth[k].second % depth.width;
    const std::uint32_t v = by_depth[k].second / depth.width;
    const Eigen::Vector3d p_O((u - K.cx) / K.fx * z, (v - K.cy) / K.fy * z, z);
    points.push_back(R * p_O + T_W_O.position);
  }
  return points;
}

} // namespace

void DetectionFusion::Config::validate() const
{
  std::ostringstream s;
  s.precision(17);
  auto positive = [](double x) { return std::isfinite(x) && x > 0.0; };
  if (class_name.empty())
    s << "class_name: empty";
  else if (!(min_score >= 0.0 && min_score <= 1.0))
    s << "min_score " << min_score << ": expected a value in [0, 1]";
  else if (!positive(association_distance_m))
    s << "association_distance_m " << association_distance_m
      << ": expected a finite value > 0";
  else if (!positive(depth_gap_m))
    s << "depth_gap_m " << depth_gap_m << ": expected a finite value > 0";
  else if (min_points < 1)
    s << "min_points 0: expected at least 1";
  else if (!(std::isfinite(margin_m) && margin_m >= 0.0))
    s << "margin_m " << margin_m << ": expected a finite value >= 0";
  else if (!(min_size_m.allFinite() && (min_size_m.array() > 0.0).all()))
    s << "min_size_m (" << min_size_m.transpose() << "): expected finite values > 0";
  else if (min_views < 1)
    s << "min_views " << min_views << ": expected at least 1";
  if (!s.str().empty())
    throw InvalidArgumentError("DetectionFusion: " + s.str());
}

DetectionFusion::DetectionFusion(const Config& config)
{
  setConfig(config);
}

void DetectionFusion::setConfig(const Config& config)
{
  config.validate();
  config_ = config;
  instances_.clear();
  last_frame_.clear();
  counts_ = Counts();
}

void DetectionFusion::addFrame(const std::vector<Detection>& detections,
                               const DepthImage& depth,
                               const CameraIntrinsics& intrinsics, const Pose& T_W_O)
{
  const std::size_t n = std::size_t(depth.width) * depth.height;
  if (depth.width != intrinsics.width || depth.height != intrinsics.height ||
      depth.depth_m.size() < n)
    throw InvalidArgumentError(
        "DetectionFusion::addFrame: a " + std::to_string(depth.width) + "x" +
        std::to_string(depth.height) + " depth image with " +
        std::to_string(depth.depth_m.size()) + " values for a camera of " +
        std::to_string(intrinsics.width) + "x" + std::to_string(intrinsics.height));
  const std::size_t frame = ++counts_.frames;
  for (const Detection& d : detections) {
    ++counts_.detections;
    if (d.class_name != config_.class_name) {
      ++counts_.other_class;
      continue;
    }
    if (!(d.score >= config_.min_score)) {
      ++counts_.low_score;
      continue;
    }
    const std::vector<Eigen::Vector3d> points =
        detectionPoints(d, depth, intrinsics, T_W_O, config_.depth_gap_m);
    if (points.size() < config_.min_points) {
      ++counts_.too_few_points;
      continue;
    }
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Vector3d lo = points.front(), hi = points.front();
    for (const Eigen::Vector3d& p : points) {
      sum += p;
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const Eigen::Vector3d centroid = sum / double(points.size());
    // The nearest instance within the association distance (ties: the first seen).
    std::size_t best = instances_.size();
    double best_distance = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < instances_.size(); ++k) {
      const double distance = (instances_[k].centroid_W - centroid).norm();
      if (distance <= config_.association_distance_m && distance < best_distance) {
        best = k;
        best_distance = distance;
      }
    }
    if (best == instances_.size()) {
      Instance fresh;
      fresh.min_W = lo;
      fresh.max_W = hi;
      instances_.push_back(fresh);
      last_frame_.push_back(0);
    }
    Instance& instance = instances_[best];
    const double total = double(instance.points + points.size());
    instance.centroid_W = (instance.centroid_W * double(instance.points) + sum) / total;
    instance.points += points.size();
    instance.min_W = instance.min_W.cwiseMin(lo);
    instance.max_W = instance.max_W.cwiseMax(hi);
    instance.best_score = std::max(instance.best_score, d.score);
    if (last_frame_[best] != frame) { // two detections of one frame: one view
      ++instance.views;
      last_frame_[best] = frame;
    }
    ++counts_.fused;
  }
}

Roi DetectionFusion::getRoi() const
{
  Roi roi;
  for (std::size_t k = 0; k < instances_.size(); ++k) {
    const Instance& instance = instances_[k];
    if (instance.views < config_.min_views)
      continue;
    const Eigen::Vector3d lo = instance.min_W.array() - config_.margin_m;
    const Eigen::Vector3d hi = instance.max_W.array() + config_.margin_m;
    roi.addBox(Box(0.5 * (lo + hi), (hi - lo).cwiseMax(config_.min_size_m),
                   config_.class_name + "_" + std::to_string(k)));
  }
  return roi;
}

} // namespace plantnbv
