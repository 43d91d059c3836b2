#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/session/leaf_node_prior.h>

namespace plantnbv {

namespace {

double median(std::vector<double>& values)
{
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + mid, values.end());
  const double upper = values[mid];
  if (values.size() % 2 == 1)
    return upper;
  return 0.5 * (upper + *std::max_element(values.begin(), values.begin() + mid));
}

/// The stem's x, y at height z: linear between the stem points around it, the end
/// point's beyond them (one point: a vertical stem through it).
Eigen::Vector3d stemAt(const std::vector<Eigen::Vector3d>& stem, double z)
{
  if (z <= stem.front().z())
    return {stem.front().x(), stem.front().y(), z};
  for (std::size_t i = 1; i < stem.size(); ++i)
    if (z <= stem[i].z()) {
      const double t = (z - stem[i - 1].z()) / (stem[i].z() - stem[i - 1].z());
      const Eigen::Vector3d p = stem[i - 1] + t * (stem[i] - stem[i - 1]);
      return {p.x(), p.y(), z};
    }
  return {stem.back().x(), stem.back().y(), z};
}

} // namespace

void LeafNodePrior::Config::validate() const
{
  std::ostringstream s;
  s.precision(17);
  auto positive = [](double x) { return std::isfinite(x) && x > 0.0; };
  if (!positive(internode_m))
    s << "internode_m " << internode_m << ": expected a finite value > 0";
  else if (!(std::isfinite(first_node_m) && first_node_m >= 0.0))
    s << "first_node_m " << first_node_m << ": expected a finite value >= 0";
  else if (!positive(stem_radius_m))
    s << "stem_radius_m " << stem_radius_m << ": expected a finite value > 0";
  else if (!positive(slice_m))
    s << "slice_m " << slice_m << ": expected a finite value > 0";
  else if (!(std::isfinite(top_radius_m) && top_radius_m >= 0.0))
    s << "top_radius_m " << top_radius_m << ": expected a finite value >= 0";
  else if (min_slice_points < 1)
    s << "min_slice_points 0: expected at least 1";
  else if (!(box_size_m.allFinite() && (box_size_m.array() > 0.0).all()))
    s << "box_size_m (" << box_size_m.transpose() << "): expected finite values > 0";
  if (!s.str().empty())
    throw InvalidArgumentError("LeafNodePrior: " + s.str());
}

LeafNodePrior::LeafNodePrior(const Config& config)
{
  setConfig(config);
}

void LeafNodePrior::setConfig(const Config& config)
{
  config.validate();
  config_ = config;
}

void LeafNodePrior::setStemObservations(const Roi& stem_W)
{
  for (const Box& box : stem_W.boxes())
    if (!(box.center.allFinite() && box.size.allFinite()))
      throw InvalidArgumentError("LeafNodePrior: stem observation '" + box.name +
                                 "' is not finite");
  stem_W_ = stem_W;
}

std::vector<Eigen::Vector3d> LeafNodePrior::stemPoints(const CloudXYZ& occupied_W,
                                                       const Eigen::Vector3d& axis_base_W,
                                                       double height_m) const
{
  if (!(std::isfinite(height_m) && height_m > 0.0) || !axis_base_W.allFinite())
    throw InvalidArgumentError("LeafNodePrior: the plant's axis needs a finite base and "
                               "a height > 0");
  std::vector<Eigen::Vector3d> detected;
  for (const Box& box : stem_W_.boxes()) {
    const double dz = box.center.z() - axis_base_W.z();
    if (dz > 0.0 && dz < height_m)
      detected.push_back(box.center);
  }
  if (!detected.empty()) {
    std::stable_sort(
        detected.begin(), detected.end(),
        [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return a.z() < b.z(); });
    return detected;
  }
  const std::size_t slices =
      std::max<std::size_t>(1, std::size_t(std::ceil(height_m / config_.slice_m)));
  std::vector<std::vector<double>> xs(slices), ys(slices);
  const double r2 = config_.stem_radius_m * config_.stem_radius_m;
  for (const pcl::PointXYZ& p : occupied_W.points) {
    const double dz = p.z - axis_base_W.z();
    const double dx = p.x - axis_base_W.x(), dy = p.y - axis_base_W.y();
    if (!(dz > 0.0 && dz < height_m) || dx * dx + dy * dy > r2)
      continue;
    const std::size_t k = std::min(slices - 1, std::size_t(dz / config_.slice_m));
    xs[k].push_back(p.x);
    ys[k].push_back(p.y);
  }
  std::vector<Eigen::Vector3d> stem;
  for (std::size_t k = 0; k < slices; ++k)
    if (xs[k].size() >= config_.min_slice_points)
      stem.emplace_back(median(xs[k]), median(ys[k]),
                        axis_base_W.z() + (double(k) + 0.5) * config_.slice_m);
  return stem;
}

double LeafNodePrior::plantTop(const CloudXYZ& occupied_W,
                               const Eigen::Vector3d& axis_base_W, double height_m) const
{
  const double top = axis_base_W.z() + height_m;
  if (config_.top_radius_m == 0.0)
    return top;
  const double r2 = config_.top_radius_m * config_.top_radius_m;
  double highest = -std::numeric_limits<double>::infinity();
  for (const pcl::PointXYZ& p : occupied_W.points) {
    const double dx = p.x - axis_base_W.x(), dy = p.y - axis_base_W.y();
    if (p.z > axis_base_W.z() && p.z < top && dx * dx + dy * dy <= r2)
      highest = std::max(highest, double(p.z));
  }
  return std::isfinite(highest) ? highest : top;
}

Roi LeafNodePrior::predict(const CloudXYZ& occupied_W, const Eigen::Vector3d& axis_base_W,
                           double height_m,
                           const std::vector<Eigen::Vector3d>& anchors_W) const
{
  std::vector<Eigen::Vector3d> stem = stemPoints(occupied_W, axis_base_W, height_m);
  if (stem.empty()) // nothing of the stem seen yet: it stands on the plant's axis
    stem.push_back(axis_base_W);
  const double s = config_.internode_m;
  // The whole plant's height: the stem goes on where leaves hide it, and the nodes
  // behind them are the ones attention has to find. Above the plant's top is air.
  const double bottom = axis_base_W.z();
  const double top = plantTop(occupied_W, axis_base_W, height_m);
  std::vector<Eigen::Vector3d> anchors;
  for (const Eigen::Vector3d& a : anchors_W)
    if (a.allFinite() && a.z() >= bottom - s && a.z() <= top + s)
      anchors.push_back(a);
  std::sort(
      anchors.begin(), anchors.end(),
      [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return a.z() < b.z(); });
  std::vector<double> heights; // every node's height, anchors' included
  auto free = [&](double z) {
    return std::all_of(heights.begin(), heights.end(),
                       [&](double h) { return std::abs(h - z) > 0.5 * s; });
  };
  for (const Eigen::Vector3d& a : anchors)
    heights.push_back(a.z());
  std::vector<double> predicted;
  auto walk = [&](double from, double step) {
    for (double z = from; z >= bottom && z <= top; z += step)
      if (free(z)) {
        predicted.push_back(z);
        heights.push_back(z);
      }
  };
  if (anchors.empty()) {
    walk(bottom + config_.first_node_m, s);
  } else {
    for (const Eigen::Vector3d& a : anchors) {
      walk(a.z() + s, s);
      walk(a.z() - s, -s);
    }
  }
  std::sort(predicted.begin(), predicted.end());
  Roi roi;
  for (std::size_t k = 0; k < predicted.size(); ++k)
    roi.addBox(Box(stemAt(stem, predicted[k]), config_.box_size_m,
                   "leaf_node_prior_" + std::to_string(k)));
  return roi;
}

Roi LeafNodePrior::predictAround(const Roi& found_W, const CloudXYZ& occupied_W,
                                 const Eigen::Vector3d& axis_base_W,
                                 double height_m) const
{
  std::vector<Eigen::Vector3d> anchors;
  if (config_.anchor_on_found)
    for (const Box& box : found_W.boxes())
      anchors.push_back(box.center);
  Roi roi = found_W;
  const Roi predicted = predict(occupied_W, axis_base_W, height_m, anchors);
  for (const Box& box : predicted.boxes())
    roi.addBox(box);
  return roi;
}

} // namespace plantnbv
