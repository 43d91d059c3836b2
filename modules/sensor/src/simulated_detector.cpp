#include <algorithm>
#include <cmath>
#include <sstream>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/common/triangle_mesh.h>
#include <plantnbv/sensor/simulated_detector.h>

namespace plantnbv {

namespace {

/// A box edge moved by N(0, sigma^2), clipped to [0, side].
double jittered(double edge, double sigma_px, double side, Rng& rng)
{
  if (sigma_px > 0.0)
    edge += sigma_px * rng.normal();
  return std::clamp(edge, 0.0, side);
}

/// `pixels` (ascending row-major indices of a width x height image) grown (radius > 0)
/// or shrunk (radius < 0) by |radius| pixels with a square: a separable running count
/// over rows, then columns, inside the pixels' bounds grown by |radius|. Pixels outside
/// the image count as not the instance's.
std::vector<std::uint32_t> dilated(const std::vector<std::uint32_t>& pixels,
                                   std::uint32_t width, std::uint32_t height, int radius)
{
  const int r = std::abs(radius);
  int u0 = int(width), v0 = int(height), u1 = -1, v1 = -1;
  for (std::uint32_t i : pixels) {
    u0 = std::min(u0, int(i % width));
    u1 = std::max(u1, int(i % width));
    v0 = std::min(v0, int(i / width));
    v1 = std::max(v1, int(i / width));
  }
  // The window: the bounds grown by r, clipped to the image.
  u0 = std::max(u0 - r, 0);
  v0 = std::max(v0 - r, 0);
  u1 = std::min(u1 + r, int(width) - 1);
  v1 = std::min(v1 + r, int(height) - 1);
  const int w = u1 - u0 + 1, h = v1 - v0 + 1;
  std::vector<std::uint8_t> in(std::size_t(w) * h, 0), rows(in.size(), 0);
  for (std::uint32_t i : pixels)
    in[std::size_t(int(i / width) - v0) * w + (int(i % width) - u0)] = 1;
  const int full = 2 * r + 1;
  // Out of one line of n values (stride apart), into `out`: 1 where the count of ones
  // within r is > 0 (grow) or the whole window (shrink).
  const auto pass = [&](const std::uint8_t* line, std::uint8_t* out, int n,
                        std::size_t stride) {
    int count = 0;
    for (int k = 0; k < std::min(r, n); ++k)
      count += line[k * stride];
    for (int k = 0; k < n; ++k) {
      if (k + r < n)
        count += line[(k + r) * stride];
      if (k - r - 1 >= 0)
        count -= line[(k - r - 1) * stride];
      out[k * stride] = radius > 0 ? count > 0 : count == full;
    }
  };
  for (int y = 0; y < h; ++y)
    pass(&in[std::size_t(y) * w], &rows[std::size_t(y) * w], w, 1);
  for (int x = 0; x < w; ++x)
    pass(&rows[x], &in[x], h, std::size_t(w));
  std::vector<std::uint32_t> out;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (in[std::size_t(y) * w + x])
        out.push_back(std::uint32_t(v0 + y) * width + std::uint32_t(u0 + x));
  return out;
}

} // namespace

void SimulatedDetector::Config::validate() const
{
  std::ostringstream s;
  s.precision(17);
  if (class_name.empty())
    s << "class_name: empty";
  else if (!(recall >= 0.0 && recall <= 1.0))
    s << "recall " << recall << ": expected a value in [0, 1]";
  else if (!(std::isfinite(false_positives) && false_positives >= 0.0 &&
             false_positives <= 1000.0))
    s << "false_positives " << false_positives
      << ": expected a value in [0, 1000] per frame";
  else if (!(std::isfinite(box_jitter_px) && box_jitter_px >= 0.0))
    s << "box_jitter_px " << box_jitter_px << ": expected a finite value >= 0";
  else if (std::abs(mask_dilation_px) > kMaxMaskDilationPx)
    s << "mask_dilation_px " << mask_dilation_px << ": expected pixels in ["
      << -kMaxMaskDilationPx << ", " << kMaxMaskDilationPx << "]";
  if (!s.str().empty())
    throw InvalidArgumentError("SimulatedDetector: " + s.str());
}

SimulatedDetector::SimulatedDetector(const Config& config)
{
  setConfig(config);
}

void SimulatedDetector::setConfig(const Config& config)
{
  config.validate();
  config_ = config;
}

void SimulatedDetector::detect(const CloudXYZL& frame_W, const Roi& truth,
                               std::uint64_t frame_index,
                               std::vector<Detection>& out) const
{
  const std::uint32_t width = frame_W.width, height = frame_W.height;
  if (std::size_t(width) * height != frame_W.size() || frame_W.empty())
    throw InvalidArgumentError(
        "SimulatedDetector::detect: the frame must be an organized "
        "cloud (width x height points)");
  out.clear();
  Rng rng(deriveSeed(config_.seed, frame_index));
  const std::size_t n = frame_W.size();
  for (const Box& box : truth.boxes()) {
    std::vector<std::uint32_t> pixels;
    for (std::size_t i = 0; i < n; ++i) {
      const pcl::PointXYZL& p = frame_W.points[i];
      if (isPlantPart(p.label) && std::isfinite(p.x) && box.contains(p.x, p.y, p.z))
        pixels.push_back(std::uint32_t(i));
    }
    // One draw per instance, seen or not, so that an instance's fate does not depend on
    // the others' visibility.
    const bool detected = rng.uniform() < config_.recall;
    const double score = rng.uniform(0.5, 1.0);
    if (!detected || pixels.size() < config_.min_pixels)
      continue;
    if (config_.mask_dilation_px != 0) {
      pixels = dilated(pixels, width, height, config_.mask_dilation_px);
      if (pixels.empty())
        continue; // shrunk to nothing: the segmenter missed it
    }
    std::uint32_t u0 = width, v0 = height, u1 = 0, v1 = 0;
    for (std::uint32_t i : pixels) {
      u0 = std::min(u0, i % width);
      u1 = std::max(u1, i % width);
      v0 = std::min(v0, i / width);
      v1 = std::max(v1, i / width);
    }
    Detection d;
    d.class_name = config_.class_name;
    d.score = score;
    const double jitter = config_.box_jitter_px;
    d.box_px = {jittered(u0, jitter, width, rng), jittered(v0, jitter, height, rng),
                jittered(u1 + 1.0, jitter, width, rng),
                jittered(v1 + 1.0, jitter, height, rng)};
    if (d.box_px[0] > d.box_px[2])
      std::swap(d.box_px[0], d.box_px[2]);
    if (d.box_px[1] > d.box_px[3])
      std::swap(d.box_px[1], d.box_px[3]);
    if (config_.masks) {
      d.mask.assign(n, 0);
      for (std::uint32_t i : pixels)
        d.mask[i] = 255;
    }
    out.push_back(std::move(d));
  }
  std::size_t false_positives = std::size_t(config_.false_positives);
  if (rng.uniform() < config_.false_positives - double(false_positives))
    ++false_positives;
  for (std::size_t k = 0; k < false_positives; ++k) {
    const double w = std::min<double>(rng.uniform(8.0, 48.0), width);
    const double h = std::min<double>(rng.uniform(8.0, 48.0), height);
    const double u = rng.uniform(0.0, width - w), v = rng.uniform(0.0, height - h);
    Detection d;
    d.class_name = config_.class_name;
    d.score = rng.uniform(0.5, 1.0);
    d.box_px = {u, v, u + w, v + h};
    if (config_.masks) {
      d.mask.assign(n, 0);
      Detection box_only = d;
      box_only.mask.clear();
      for (std::uint32_t i : detectionPixels(box_only, width, height))
        d.mask[i] = 255;
    }
    out.push_back(std::move(d));
  }
}

} // namespace plantnbv
