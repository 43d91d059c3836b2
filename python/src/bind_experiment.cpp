// Trials (`plantnbv reconstruct`) and campaigns (`plantnbv campaign run/status/report`).

#include <filesystem>
#include <optional>
#include <pybind11/functional.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/campaign.h>
#include <plantnbv/experiment/campaign_runner.h>
#include <plantnbv/experiment/result_store.h>
#include <plantnbv/experiment/trial.h>
#include <plantnbv/metrics/reconstruction_metrics.h>
#include <plantnbv/scenario/campaign_figures.h>
#include <plantnbv/scenario/campaign_file.h>
#include <plantnbv/scenario/placed_plant.h>
#include <plantnbv/scenario/trial_setup.h>

#include "arrays.h"
#include "bindings.h"

namespace plantnbv {
namespace python {

namespace {

using namespace pybind11::literals;
namespace fs = std::filesystem;
using Path = fs::path;

/// A trial's result with the map's occupied voxels (the reconstruction).
struct TrialRun {
  TrialResult result;
  py::object reconstruction;
  Roi attended_roi; ///< Trial::getAttendedRoi
};

py::dict stepDict(const TrialStep& s, const std::vector<std::string>& levels)
{
  py::dict scores;
  for (std::size_t l = 0; l < s.scores.size() && l < levels.size(); ++l) {
    const LevelScore& x = s.scores[l];
    scores[py::str(levels[l])] =
        py::dict("precision"_a = x.precision, "recall"_a = x.recall, "f1"_a = x.f1,
                 "chamfer"_a = x.chamfer, "reference_points"_a = x.reference_points,
                 "reconstruction_points"_a = x.reconstruction_points);
  }
  py::dict organs;
  for (const OrganRecall& o : s.organs)
    organs[py::str(partLabelName(o.organ))] = o.recall;
  return py::dict("view"_a = s.index, "pose"_a = poseArray(s.view), "gain"_a = s.gain,
                  "unknown_seen"_a = s.unknown_seen, "candidates"_a = s.candidates,
                  "plan_ms"_a = s.plan_ms, "capture_ms"_a = s.capture_ms,
                  "insert_ms"_a = s.insert_ms, "eval_ms"_a = s.eval_ms,
                  "occupied_voxels"_a = s.occupied_voxels, "scores"_a = scores,
                  "organ_recall"_a = organs);
}

/// The columns of `plantnbv reconstruct`'s steps.csv, one NumPy array each.
py::dict stepColumns(const TrialResult& r)
{
  py::dict out;
  auto column = [&](const std::string& name, auto&& value) {
    using T = decltype(value(r.steps.front()));
    std::vector<T> v;
    for (const TrialStep& s : r.steps)
      v.push_back(value(s));
    out[py::str(name)] = columnArray(v);
  };
  if (r.steps.empty())
    return out;
  column("view", [](const TrialStep& s) { return std::int64_t(s.index); });
  const char* pose[] = {"x", "y", "z", "qx", "qy", "qz", "qw"};
  for (int k = 0; k < 7; ++k)
    column(pose[k], [k](const TrialStep& s) {
      return k < 3 ? s.view.position[k] : s.view.orientation.coeffs()[k - 3];
    });
  column("gain", [](const TrialStep& s) { return s.gain; });
  column("unknown_seen", [](const TrialStep& s) { return std::int64_t(s.unknown_seen); });
  column("candidates", [](const TrialStep& s) { return std::int64_t(s.candidates); });
  column("plan_ms", [](const TrialStep& s) { return s.plan_ms; });
  column("capture_ms", [](const TrialStep& s) { return s.capture_ms; });
  column("insert_ms", [](const TrialStep& s) { return s.insert_ms; });
  column("eval_ms", [](const TrialStep& s) { return s.eval_ms; });
  column("occupied_voxels",
         [](const TrialStep& s) { return std::int64_t(s.occupied_voxels); });
  for (std::size_t l = 0; l < r.level_names.size(); ++l) {
    const std::string& n = r.level_names[l];
    column(n + "_precision", [l](const TrialStep& s) { return s.scores[l].precision; });
    column(n + "_recall", [l](const TrialStep& s) { return s.scores[l].recall; });
    column(n + "_f1", [l](const TrialStep& s) { return s.scores[l].f1; });
    column(n + "_chamfer", [l](const TrialStep& s) { return s.scores[l].chamfer; });
  }
  for (std::size_t o = 0; o < evaluatedOrgans().size(); ++o)
    column(std::string("recall_") + partLabelName(evaluatedOrgans()[o]),
           [o](const TrialStep& s) { return s.organs[o].recall; });
  return out;
}

std::size_t levelIndex(const TrialResult& r, const std::string& level)
{
  for (std::size_t l = 0; l < r.level_names.size(); ++l)
    if (r.level_names[l] == level)
      return l;
  std::string names;
  for (const std::string& n : r.level_names)
    names += (names.empty() ? "" : ", ") + n;
  throw InvalidArgumentError("level: expected one of " + names + ", got '" + level + "'");
}

/// Raises KeyboardInterrupt (and other pending signals' exceptions) in a long call.
void checkSignals()
{
  py::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() != 0)
    throw py::error_already_set();
}

TrialRun runTrial(const scenario::PlacedPlant& placed, const std::string& planner,
                  const std::string& attention_name, const scenario::TrialOverrides& o,
                  double row_spacing_m, const std::optional<Path>& map_out,
                  const py::object& progress)
{
  scenario::TrialOverrides overrides = o;
  overrides.planner = planner;
  TrialConfig config;
  {
    Locked lock; // reads the plant (a model's height)
    config = scenario::makeTrialConfig(overrides, placed);
  }
  const scenario::Attention attention = scenario::Attention::parse(attention_name);
  TrialRun run;
  CloudXYZ occupied;
  {
    py::gil_scoped_release release;
    Trial trial(config);
    std::vector<std::string> names;
    {
      // The trial copies the plant; then it runs on objects of its own, unlocked.
      std::lock_guard<std::recursive_mutex> lock(libraryMutex());
      const std::vector<EvaluationLevel> levels = scenario::evaluationLevels(placed);
      scenario::setUpTrial(placed, scenario::attentionRoi(placed, attention), levels,
                           trial);
      trial.setNeighbours(scenario::rowNeighbourPlants(placed, row_spacing_m, config));
      for (const EvaluationLevel& l : levels)
        names.push_back(l.name);
    }
    trial.setStepCallback([&](const TrialStep& s) {
      checkSignals();
      if (!progress.is_none()) {
        py::gil_scoped_acquire gil;
        progress(stepDict(s, names));
      }
    });
    trial.run(run.result);
    run.attended_roi = trial.getAttendedRoi();
    if (map_out)
      trial.getMap().write(map_out->string());
    trial.getMap().getOccupiedVoxelCentres(occupied);
  }
  run.reconstruction = pointsArray(occupied);
  return run;
}

py::dict statusDict(const StoreStatus& s)
{
  return py::dict("total"_a = s.total, "done"_a = s.done, "failed"_a = s.failed,
                  "missing"_a = s.missing, "foreign"_a = s.foreign,
                  "failed_ids"_a = s.failed_ids, "failed_errors"_a = s.failed_errors);
}

py::dict progressDict(const CampaignProgress& p)
{
  const char* events[] = {"started", "finished", "tick"};
  return py::dict("event"_a = events[int(p.event)], "total"_a = p.total,
                  "skipped"_a = p.skipped, "to_run"_a = p.to_run, "ran"_a = p.ran,
                  "failed"_a = p.failed, "running"_a = p.running, "workers"_a = p.workers,
                  "elapsed_s"_a = p.elapsed_s, "id"_a = p.id,
                  "trial_failed"_a = p.trial_failed, "error"_a = p.error,
                  "trial_s"_a = p.trial_s);
}

py::dict runCampaign(const Path& file, const Path& out_dir, int workers,
                     const py::object& progress)
{
  const scenario::CampaignFile f = scenario::loadCampaignFile(file.string());
  const ResultStore store(out_dir);
  store.create(f.text, f.definition.content_fingerprint);
  std::vector<TrialSpec> specs = expandCampaign(f.definition);
  // The trials of one plant and pose one after another: they share its scene.
  scenario::groupTrialsByScene(specs);
  LocalRunner runner(store, scenario::campaignTrialFunction(f), workers);
  // On the calling thread, about once a second: Ctrl-C stops new trials; run() then
  // waits for the running ones and rethrows.
  runner.setProgressCallback([&](const CampaignProgress& p) {
    checkSignals();
    if (!progress.is_none()) {
      py::gil_scoped_acquire gil;
      progress(progressDict(p));
    }
  });
  {
    py::gil_scoped_release release;
    runner.run(specs);
  }
  return statusDict(store.status(specs));
}

py::dict campaignStatus(const Path& dir)
{
  return statusDict(scenario::campaignDirectoryStatus(dir));
}

py::list campaignTiming(const Path& dir)
{
  py::list rows;
  for (const TimingRow& r : scenario::campaignDirectoryTiming(dir))
    rows.append(py::dict("study"_a = r.study, "variant"_a = r.variant,
                         "planner"_a = r.planner, "trials"_a = r.trials,
                         "setup_ms"_a = r.mean.setup_ms, "plan_ms"_a = r.mean.plan_ms,
                         "capture_ms"_a = r.mean.capture_ms,
                         "insert_ms"_a = r.mean.insert_ms, "eval_ms"_a = r.mean.eval_ms,
                         "total_ms"_a = r.mean.total_ms, "share"_a = r.share));
  return rows;
}

std::vector<Path> campaignReport(const Path& dir, std::optional<Path> out, bool figures)
{
  py::gil_scoped_release release;
  return scenario::writeCampaignReportFiles(dir, out ? *out : dir / "report", figures)
      .written;
}

} // namespace

void bindExperiment(py::module_& m)
{
  py::class_<TrialRun>(
      m, "TrialResult",
      "One trial: its steps (v0 first), scores per evaluation level after "
      "every view, and the reconstruction.")
      .def_property_readonly("level_names",
                             [](const TrialRun& r) { return r.result.level_names; })
      .def_property_readonly(
          "steps",
          [](const TrialRun& r) {
            py::list steps;
            for (const TrialStep& s : r.result.steps)
              steps.append(stepDict(s, r.result.level_names));
            return steps;
          },
          "A dict per view: view, pose (7,), gain, candidates, timings, occupied_voxels, "
          "scores {level: {precision, recall, f1, chamfer, ...}}, organ_recall {organ: "
          "the whole plant's recall of it, NaN if the plant has none}.")
      .def(
          "columns", [](const TrialRun& r) { return stepColumns(r.result); },
          "The steps as {column: array}, the columns of reconstruct's steps.csv "
          "(pandas.DataFrame(result.columns())).")
      .def(
          "f1_curve",
          [](const TrialRun& r, const std::string& level) {
            return columnArray(r.result.f1Curve(levelIndex(r.result, level)));
          },
          "level"_a, "F1 after each view for a level.")
      .def(
          "views_to_reach",
          [](const TrialRun& r, const std::string& level,
             double tau) -> std::optional<int> {
            const int v =
                viewsToReach(r.result.f1Curve(levelIndex(r.result, level)), tau);
            return v < 0 ? std::nullopt : std::optional<int>(v);
          },
          "level"_a, "tau"_a, "Views until F1 first reaches tau at the level, or None.")
      .def_readonly("reconstruction", &TrialRun::reconstruction,
                    "The occupied voxel centres after the last view, (N, 3) float32.")
      .def_readonly("attended_roi", &TrialRun::attended_roi,
                    "The ROI the planner attended to: the attention ROI after the ROI "
                    "source (roi_source).")
      .def_property_readonly("stopped_early",
                             [](const TrialRun& r) { return r.result.stopped_early; })
      .def_property_readonly("setup_ms",
                             [](const TrialRun& r) { return r.result.setup_ms; })
      .def_property_readonly("total_ms",
                             [](const TrialRun& r) { return r.result.total_ms; })
      .def("__len__", [](const TrialRun& r) { return r.result.steps.size(); });

  m.def(
      "run_trial",
      [](const scenario::PlacedPlant& placed, const std::string& planner,
         const std::string& attention, std::optional<int> pattern,
         std::optional<int> views, std::optional<int> candidates,
         std::optional<double> resolution_m, std::optional<double> sector_height_m,
         std::optional<double> sector_radius_m, double row_spacing_m,
         std::optional<std::uint64_t> seed, std::optional<int> threads,
         std::optional<double> depth_scale, std::optional<CameraIntrinsics> camera,
         std::optional<bool> noise, std::optional<bool> background,
         std::optional<std::string> roi_source, std::optional<double> roi_sigma,
         std::optional<double> roi_scale, std::optional<double> detector_recall,
         std::optional<double> detector_false_positives,
         std::optional<double> detector_box_jitter,
         std::optional<int> detector_mask_dilation, std::optional<bool> detector_masks,
         std::optional<double> prior_internode,
         std::optional<int> detections_explore_views, std::optional<Path> config,
         std::optional<Path> map_out, const py::object& progress) {
        scenario::TrialOverrides o;
        o.config_file = config ? config->string() : "";
        o.pattern = pattern;
        o.views = views;
        o.candidates = candidates;
        o.resolution_m = resolution_m;
        o.sector_height_m = sector_height_m;
        o.sector_radius_m = sector_radius_m;
        o.seed = seed;
        o.threads = threads;
        o.depth_scale = depth_scale;
        o.camera = camera;
        o.noise = noise;
        o.background = background;
        o.roi.source = roi_source;
        o.roi.sigma_m = roi_sigma;
        o.roi.scale = roi_scale;
        o.roi.detector_recall = detector_recall;
        o.roi.detector_false_positives = detector_false_positives;
        o.roi.detector_box_jitter_px = detector_box_jitter;
        o.roi.detector_mask_dilation_px = detector_mask_dilation;
        o.roi.detector_masks = detector_masks;
        o.roi.prior_internode_m = prior_internode;
        o.roi.detections_explore_views = detections_explore_views;
        return runTrial(placed, planner, attention, o, row_spacing_m, map_out, progress);
      },
      "plant"_a, py::kw_only(), "planner"_a = "nbv", "attention"_a = "whole_plant",
      "pattern"_a = py::none(), "views"_a = py::none(), "candidates"_a = py::none(),
      "resolution_m"_a = py::none(), "sector_height_m"_a = py::none(),
      "sector_radius_m"_a = py::none(), "row_spacing_m"_a = 0.0, "seed"_a = py::none(),
      "threads"_a = py::none(), "depth_scale"_a = py::none(), "camera"_a = py::none(),
      "noise"_a = py::none(), "background"_a = py::none(), "roi_source"_a = py::none(),
      "roi_sigma"_a = py::none(), "roi_scale"_a = py::none(),
      "detector_recall"_a = py::none(), "detector_false_positives"_a = py::none(),
      "detector_box_jitter"_a = py::none(), "detector_mask_dilation"_a = py::none(),
      "detector_masks"_a = py::none(), "prior_internode"_a = py::none(),
      "detections_explore_views"_a = py::none(), "config"_a = py::none(),
      "map_out"_a = py::none(), "progress"_a = py::none(),
      "One trial on a PlacedPlant, as `plantnbv reconstruct` runs it (the same seed "
      "gives "
      "the same steps): capture at v0, then plan, capture, integrate up to `views`, "
      "scored at every level after each view. `config` is a trial YAML (data/paper.yaml) "
      "that the other arguments override (`camera`, `noise`, `background`: the "
      "simulated sensor, as reconstruct's --intrinsics, --noise and --no-background; "
      "`roi_source` 'oracle', 'noisy', 'detections', 'prior' or 'detections+prior', "
      "`roi_sigma` (metres), `roi_scale`, `detector_recall`, `detector_false_positives`, "
      "`detector_box_jitter` (pixels), `detector_mask_dilation` (pixels), "
      "`detector_masks` (False: boxes only), "
      "`prior_internode` (metres), `detections_explore_views`: where the attended ROI "
      "comes from, as the options of "
      "the same names); `sector_radius_m` and `row_spacing_m` (a neighbour plant this "
      "far on each side; 0: alone) as --sector-radius and --row-spacing; "
      "`progress(step)` is called after every view; "
      "`map_out` writes the final map (.ot or .bt).");

  m.def(
      "run_campaign", &runCampaign, "file"_a, "out_dir"_a, "workers"_a = 0,
      "progress"_a = py::none(),
      "Runs the campaign file's trials that out_dir does not hold yet, on `workers` "
      "threads (0: all cores), as `plantnbv campaign run`; resumable. progress(dict) is "
      "called at the start, after each trial and about once a second. Returns the "
      "status (as campaign_status). Ctrl-C stops starting trials.");
  m.def(
      "campaign_status", &campaignStatus, "out_dir"_a,
      "{total, done, failed, missing, foreign, failed_ids, failed_errors} of a campaign "
      "directory.");
  m.def("campaign_timing", &campaignTiming, "out_dir"_a,
        "Where the done trials' time goes, as `plantnbv campaign status --timing`: one "
        "dict per study variant's planner, {study, variant, planner, trials, setup_ms, "
        "plan_ms, capture_ms, insert_ms, eval_ms, total_ms, share}, the means a trial "
        "(the views' phases summed) and the share of all done trials' time.");
  m.def("campaign_report", &campaignReport, "out_dir"_a, "out"_a = py::none(),
        "figures"_a = false,
        "Writes curves.csv and summary.md (and with figures=True the PNG figures, which "
        "need an X display, e.g. xvfb-run) into `out` (default out_dir/report); returns "
        "the files written.");
}

} // namespace python
} // namespace plantnbv
