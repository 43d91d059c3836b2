// plantnbv eval: compares a reconstruction with a reference (any mix of cloud, mesh and
// octree files) and prints Chamfer distance, precision, recall and F1.

#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/stopwatch.h>
#include <plantnbv/filters/roi_crop.h>
#include <plantnbv/io/roi_io.h>
#include <plantnbv/metrics/reconstruction_metrics.h>
#include <plantnbv/scenario/geometry_input.h>

#include "cli_checks.h"
#include "commands.h"

namespace plantnbv {
namespace app {

namespace {

struct EvalOptions {
  std::string reference;
  std::string reconstruction;
  double resolution = 0.003;
  double rho = 0.0;
  bool rho_given = false; // otherwise rho = resolution
  std::string roi;
  std::size_t mesh_points = 0;
  std::uint64_t seed = 0;
  bool json = false;
};

void cropToRoi(const Roi& roi, std::shared_ptr<CloudXYZ>& cloud)
{
  RoiCrop<pcl::PointXYZ> crop;
  crop.setRoi(roi);
  crop.setInputCloud(cloud);
  auto cropped = std::make_shared<CloudXYZ>();
  crop.filter(*cropped);
  cloud = cropped;
}

/// JSON numbers cannot be infinite: an undefined distance is written as null.
nlohmann::json distanceJson(double d)
{
  return std::isfinite(d) ? nlohmann::json(d) : nlohmann::json(nullptr);
}

/// Below this share of bounding-box overlap, eval warns that the clouds may be in
/// different frames.
constexpr double kMinEvalOverlap = 0.5;

void runEval(const EvalOptions& o)
{
  if (!(o.resolution > 0.0) || !std::isfinite(o.resolution))
    throw InvalidArgumentError("--resolution must be a finite size > 0 in metres, got " +
                               std::to_string(o.resolution));
  const double rho = o.rho_given ? o.rho : o.resolution;
  if (!(rho > 0.0) || !std::isfinite(rho))
    throw InvalidArgumentError("--rho must be a finite distance > 0 in metres, got " +
                               std::to_string(o.rho));
  Roi roi;
  if (!o.roi.empty())
    roi = io::loadRoi(o.roi);

  // Without --json, tell what is happening; with it, stdout holds only the JSON object.
  std::ostream& log = o.json ? std::cerr : std::cout;
  scenario::GeometryInputOptions input{o.resolution, o.mesh_points, o.seed};
  auto reference = std::make_shared<CloudXYZ>();
  auto reconstruction = std::make_shared<CloudXYZ>();
  std::string summary;
  Stopwatch load_clock;
  scenario::loadGeometryAsCloud(o.reference, "reference", input, *reference, summary);
  if (!o.json)
    log << "reference      " << o.reference << ": " << summary << "\n";
  scenario::loadGeometryAsCloud(o.reconstruction, "reconstruction", input,
                                *reconstruction, summary);
  if (!o.json)
    log << "reconstruction " << o.reconstruction << ": " << summary << "\n";
  const double load_ms = load_clock.ms();
  if (!roi.empty()) {
    cropToRoi(roi, reference);
    cropToRoi(roi, reconstruction);
    if (!o.json)
      log << "cropped to " << roi.size() << " ROI box(es) of " << o.roi << ": "
          << reference->size() << " reference and " << reconstruction->size()
          << " reconstruction points\n";
  }

  // Clouds in different frames score near 0 without an error: say so.
  const double overlap = boundingBoxOverlap(*reference, *reconstruction, rho);
  if (!reference->empty() && !reconstruction->empty() && overlap < kMinEvalOverlap) {
    std::ostringstream w;
    w << std::setprecision(2) << "plantnbv: warning: the bounding boxes of the reference "
      << "and the reconstruction overlap by " << 100.0 * overlap
      << "% of the smaller one "
      << "(less than " << 100.0 * kMinEvalOverlap
      << "%): are they in the same frame (plant yaw, base, units)?\n";
    std::cerr << w.str();
  }

  Stopwatch metrics_clock;
  ReconstructionMetrics metrics;
  metrics.setThreshold(rho);
  metrics.setReference(reference);
  metrics.setReconstruction(reconstruction);
  const MetricsResult m = metrics.compute();
  const double metrics_ms = metrics_clock.ms();
  if (!m.valid)
    std::cerr << "plantnbv: warning: "
              << (m.reference_points ? "the reconstruction" : "the reference")
              << " has no points" << (roi.empty() ? "" : " inside the ROI")
              << ": precision, recall and F1 are 0, distances undefined\n";

  if (o.json) {
    nlohmann::json j;
    j["chamfer"] = distanceJson(m.chamfer);
    j["mean_dist_reconstruction_to_reference"] =
        distanceJson(m.mean_dist_reconstruction_to_reference);
    j["mean_dist_reference_to_reconstruction"] =
        distanceJson(m.mean_dist_reference_to_reconstruction);
    j["precision"] = m.precision;
    j["recall"] = m.recall;
    j["f1"] = m.f1;
    j["rho"] = m.rho;
    j["resolution"] = o.resolution;
    j["reference_points"] = m.reference_points;
    j["reconstruction_points"] = m.reconstruction_points;
    j["valid"] = m.valid;
    j["load_ms"] = load_ms;
    j["metrics_ms"] = metrics_ms;
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::cout << std::setprecision(6) << "rho " << m.rho << " m, " << m.reference_points
            << " reference and " << m.reconstruction_points << " reconstruction points\n"
            << "  precision " << m.precision << "\n"
            << "  recall    " << m.recall << "\n"
            << "  F1        " << m.f1 << "\n"
            << "  Chamfer   " << m.chamfer << " m (reconstruction->reference "
            << m.mean_dist_reconstruction_to_reference << " m, reference->reconstruction "
            << m.mean_dist_reference_to_reconstruction << " m)\n"
            << "loaded in " << load_ms << " ms, metrics in " << metrics_ms << " ms\n";
}

} // namespace

void addEvalCommand(CLI::App& app)
{
  auto o = std::make_shared<EvalOptions>();
  CLI::App* cmd = app.add_subcommand(
      "eval",
      "Compare a reconstruction with a reference: Chamfer, precision, recall, F1");
  cmd->add_option(
         "--reference", o->reference,
         "Reference: cloud (.pcd .ply), mesh (sampled, voxelized) or octree (.bt .ot)")
      ->required();
  cmd->add_option("--reconstruction", o->reconstruction,
                  "Reconstruction: cloud, mesh or octree (occupied voxel centres)")
      ->required();
  cmd->add_option("--resolution", o->resolution,
                  "Voxel size in metres for meshes, and the default rho")
      ->capture_default_str();
  CLI::Option* rho =
      cmd->add_option("--rho", o->rho,
                      "Distance threshold in metres for precision/recall (strict <); "
                      "default: the resolution");
  cmd->add_option("--roi", o->roi, "ROI file (YAML boxes): crop both clouds to it first");
  cmd->add_option("--mesh-points", o->mesh_points,
                  "Surface samples per mesh; default 8 per resolution^2 of surface")
      ->check(unsignedInteger());
  cmd->add_option("--seed", o->seed, "Sampling seed for meshes")
      ->check(unsignedInteger())
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "Print one JSON object instead of text");
  cmd->callback([o, rho]() {
    o->rho_given = rho->count() > 0;
    runEval(*o);
  });
}

} // namespace app
} // namespace plantnbv
