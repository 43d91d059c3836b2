// plantnbv campaign: many trials from one YAML file (the paper's study, or a variant),
// run on all cores, resumable, with statistics at the end.
//   campaign run FILE -o DIR [-j N]     run the trials not done yet
//   campaign run-chunk FILE -o DIR --chunk I --chunks N   one chunk (array jobs)
//   campaign status DIR                 count done, failed and missing trials
//   campaign report DIR [-o OUT]        curves.csv and summary.md

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <yaml-cpp/yaml.h>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/campaign.h>
#include <plantnbv/experiment/campaign_report.h>
#include <plantnbv/experiment/campaign_runner.h>
#include <plantnbv/experiment/result_store.h>
#include <plantnbv/experiment/trial.h>

#include "commands.h"
#include "plant_source.h"
#include "trial_config.h"
#include "trial_setup.h"

namespace plantnbv {
namespace app {

namespace {

namespace fs = std::filesystem;

/// A campaign file: the definition, the trial config shared by its trials and the
/// directory its relative paths are relative to.
struct CampaignFile {
  std::string path;
  std::string text;
  CampaignDefinition definition;
  TrialConfig base; ///< the `trial:` section over the built-in defaults
  fs::path base_dir;
};

/// Key paths for messages: "'quick.yaml' studies[1].planners[0].attention: ...".
class Reader {
public:
  explicit Reader(const std::string& file) : file_(file) {}

  [[noreturn]] void fail(const std::string& key_path, const std::string& message) const
  {
    throw FormatError("'" + file_ + "' " + key_path + ": " + message);
  }

  template <typename T>
  T read(const YAML::Node& node, const std::string& key_path, const char* expected) const
  {
    if (!node.IsScalar())
      fail(key_path, std::string("expected ") + expected);
    try {
      return node.as<T>();
    } catch (const YAML::Exception&) {
      fail(key_path, "'" + node.Scalar() + "' is not " + expected);
    }
  }

  template <typename T>
  std::vector<T> readList(const YAML::Node& node, const std::string& key_path,
                          const char* expected) const
  {
    if (!node.IsSequence())
      fail(key_path, std::string("expected a list of ") + expected);
    std::vector<T> out;
    for (std::size_t i = 0; i < node.size(); ++i)
      out.push_back(read<T>(node[i], key_path + "[" + std::to_string(i) + "]", expected));
    return out;
  }

  /// Calls handlers[key] for each key of the map; any other key is an error.
  void forEach(const YAML::Node& map, const std::string& key_path,
               const std::map<std::string,
                              std::function<void(const YAML::Node&, const std::string&)>>&
                   handlers) const
  {
    if (!map.IsMap())
      fail(key_path.empty() ? "(top level)" : key_path, "expected a map of keys");
    for (const auto& item : map) {
      const std::string key = item.first.as<std::string>();
      const std::string path = key_path.empty() ? key : key_path + "." + key;
      const auto handler = handlers.find(key);
      if (handler == handlers.end()) {
        std::string known;
        for (const auto& h : handlers)
          known += (known.empty() ? "" : ", ") + h.first;
        fail(path, "unknown key (expected one of " + known + ")");
      }
      handler->second(item.second, path);
    }
  }

private:
  std::string file_;
};

using Handler = std::function<void(const YAML::Node&, const std::string&)>;

void readPlants(const Reader& r, const YAML::Node& node, const std::string& path,
                std::vector<CampaignPlant>& plants)
{
  if (!node.IsSequence())
    r.fail(path, "expected a list of plants ({seed: S} or {model: FILE})");
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string p = path + "[" + std::to_string(i) + "]";
    CampaignPlant plant;
    std::vector<std::uint64_t> seeds;
    bool named = false;
    r.forEach(node[i], p,
              {{"seed",
                [&](const YAML::Node& n, const std::string& k) {
                  seeds.push_back(r.read<std::uint64_t>(n, k, "a seed (integer >= 0)"));
                }},
               {"seeds",
                [&](const YAML::Node& n, const std::string& k) {
                  seeds = r.readList<std::uint64_t>(n, k, "seeds (integers >= 0)");
                  if (seeds.empty())
                    r.fail(k, "expected at least one seed");
                }},
               {"stage",
                [&](const YAML::Node& n, const std::string& k) {
                  plant.stage = r.read<double>(n, k, "a growth stage in [0, 1]");
                  if (!(*plant.stage >= 0.0 && *plant.stage <= 1.0))
                    r.fail(k, n.Scalar() + " is not in [0, 1]");
                }},
               {"simplified",
                [&](const YAML::Node& n, const std::string& k) {
                  plant.simplified = r.read<bool>(n, k, "true or false");
                }},
               {"model",
                [&](const YAML::Node& n, const std::string& k) {
                  plant.model = r.read<std::string>(n, k, "a file name");
                }},
               {"labels",
                [&](const YAML::Node& n, const std::string& k) {
                  plant.labels = r.read<std::string>(n, k, "label rules");
                }},
               {"rois",
                [&](const YAML::Node& n, const std::string& k) {
                  plant.rois = r.read<std::string>(n, k, "a ROI file name");
                }},
               {"name", [&](const YAML::Node& n, const std::string& k) {
                  plant.name = r.read<std::string>(n, k, "a name");
                  named = true;
                }}});
    if (seeds.empty() == plant.model.empty())
      r.fail(p, "give a seed, seeds or a model file");
    if (!plant.model.empty()) {
      if (plant.simplified)
        r.fail(p + ".simplified", "only a generated plant can be simplified");
      if (!named)
        plant.name = fs::path(plant.model).stem().string();
      plants.push_back(plant);
      continue;
    }
    if (!plant.labels.empty() || !plant.rois.empty())
      r.fail(p, "labels and rois belong to a model file");
    if (named && seeds.size() > 1)
      r.fail(p + ".name", "one name for several seeds");
    for (std::uint64_t seed : seeds) {
      CampaignPlant generated = plant;
      generated.seed = seed;
      if (!named) {
        std::ostringstream name;
        name << "plant" << std::setw(2) << std::setfill('0') << seed;
        generated.name = name.str();
      }
      plants.push_back(generated);
    }
  }
}

CampaignPlanner readPlanner(const Reader& r, const YAML::Node& node, const std::string& p)
{
  CampaignPlanner planner;
  std::string type;
  bool has_attention = false, has_patterns = false;
  r.forEach(node, p,
            {{"type",
              [&](const YAML::Node& n, const std::string& k) {
                type = r.read<std::string>(n, k, "nbv, predefined or random");
                if (type != "nbv" && type != "predefined" && type != "random")
                  r.fail(k, "unknown planner '" + type +
                                "' (expected nbv, predefined or random)");
              }},
             {"name",
              [&](const YAML::Node& n, const std::string& k) {
                planner.name = r.read<std::string>(n, k, "a name");
              }},
             {"attention",
              [&](const YAML::Node& n, const std::string& k) {
                planner.attention = r.read<std::string>(n, k, "a ROI name");
                if (!isAttentionName(planner.attention))
                  r.fail(k,
                         "unknown ROI '" + planner.attention +
                             "' (expected whole-plant, main-stem, leaf-nodes, fruit or "
                             "a ROI file)");
                has_attention = true;
              }},
             {"patterns", [&](const YAML::Node& n, const std::string& k) {
                planner.patterns = r.readList<int>(n, k, "patterns 1-4");
                for (std::size_t i = 0; i < planner.patterns.size(); ++i)
                  if (planner.patterns[i] < 1 || planner.patterns[i] > 4)
                    r.fail(k + "[" + std::to_string(i) + "]",
                           std::to_string(planner.patterns[i]) + " is not a pattern 1-4");
                has_patterns = true;
              }}});
  if (type.empty())
    r.fail(p + ".type", "missing (nbv, predefined or random)");
  planner.kind = plannerKindFromName(type);
  if (planner.kind == PlannerKind::nbv) {
    if (!has_attention)
      r.fail(p + ".attention", "missing: an NBV planner needs an attention ROI");
    if (has_patterns)
      r.fail(p + ".patterns", "only a predefined planner has patterns");
    if (planner.name.empty()) // nbv-leaf-nodes; a ROI file: nbv-<its stem>
      planner.name = "nbv-" + fs::path(planner.attention).stem().string();
  } else {
    if (has_attention)
      r.fail(p + ".attention", "only an NBV planner has an attention ROI");
    if (planner.kind == PlannerKind::random && has_patterns)
      r.fail(p + ".patterns", "only a predefined planner has patterns");
    if (planner.kind == PlannerKind::predefined && !has_patterns)
      planner.patterns = {1, 2, 3, 4};
    if (planner.name.empty())
      planner.name = type;
  }
  return planner;
}

CampaignStudy readStudy(const Reader& r, const YAML::Node& node, const std::string& p)
{
  CampaignStudy study;
  r.forEach(node, p,
            {{"name",
              [&](const YAML::Node& n, const std::string& k) {
                study.name = r.read<std::string>(n, k, "a name");
              }},
             {"planners",
              [&](const YAML::Node& n, const std::string& k) {
                if (!n.IsSequence())
                  r.fail(k, "expected a list of planners");
                for (std::size_t i = 0; i < n.size(); ++i)
                  study.planners.push_back(
                      readPlanner(r, n[i], k + "[" + std::to_string(i) + "]"));
              }},
             {"simplified",
              [&](const YAML::Node& n, const std::string& k) {
                study.simplified = r.readList<bool>(n, k, "true or false");
              }},
             {"candidates",
              [&](const YAML::Node& n, const std::string& k) {
                study.candidates = r.readList<int>(n, k, "candidate counts (integers)");
              }},
             {"resolutions", [&](const YAML::Node& n, const std::string& k) {
                study.resolutions_m = r.readList<double>(n, k, "resolutions (metres)");
              }}});
  if (study.name.empty())
    r.fail(p + ".name", "missing");
  return study;
}

/// Keys of `trial:` that the campaign sets per trial.
void rejectCampaignKeys(const Reader& r, const YAML::Node& trial)
{
  if (!trial.IsMap())
    return; // readTrialConfig names it
  const std::map<std::string, std::string> owned{
      {"planner", "studies[].planners"},
      {"pattern", "studies[].planners[].patterns"},
      {"views", "views"},
      {"seed", "seed"}};
  for (const auto& [key, where] : owned)
    if (trial[key])
      r.fail("trial." + key, "set by the campaign: use " + where);
  if (trial["map"] && trial["map"].IsMap() && trial["map"]["resolution"])
    r.fail("trial.map.resolution", "set by the campaign: use resolution (or a study's "
                                   "resolutions)");
  if (trial["sector"] && trial["sector"].IsMap() && trial["sector"]["samples_per_cell"])
    r.fail("trial.sector.samples_per_cell",
           "set by the campaign: use candidates (or a study's candidates)");
}

/// The config of one trial (without the model's sector height, which needs the plant).
TrialConfig trialConfig(const CampaignFile& f, const TrialSpec& t)
{
  TrialConfig c = f.base;
  c.planner = t.kind;
  if (t.kind == PlannerKind::predefined)
    c.pattern = t.pattern;
  c.views = t.views;
  c.samples_per_cell = t.candidates / (c.grid_rows * c.grid_cols);
  c.map.resolution_m = t.resolution_m;
  c.seed = t.seed;
  c.threads = 1; // one trial per worker: no nested parallelism
  return c;
}

CampaignFile loadCampaign(const std::string& path, const std::string& name_for_messages)
{
  CampaignFile f;
  f.path = path;
  std::ifstream in(path);
  if (!in)
    throw IoError("cannot read campaign file '" + path + "'");
  std::stringstream text;
  text << in.rdbuf();
  f.text = text.str();
  f.base_dir = fs::path(path).parent_path();
  const Reader r(name_for_messages);
  YAML::Node root;
  try {
    root = YAML::Load(f.text);
  } catch (const YAML::Exception& e) {
    throw FormatError("'" + name_for_messages + "' is not valid YAML: " + e.what());
  }
  CampaignDefinition& d = f.definition;
  d.name = fs::path(path).stem().string();
  bool has_plants = false, has_studies = false;
  r.forEach(root, "",
            {{"name",
              [&](const YAML::Node& n, const std::string& k) {
                d.name = r.read<std::string>(n, k, "a name");
              }},
             {"seed",
              [&](const YAML::Node& n, const std::string& k) {
                d.seed = r.read<std::uint64_t>(n, k, "a seed (integer >= 0)");
              }},
             {"plants",
              [&](const YAML::Node& n, const std::string& k) {
                readPlants(r, n, k, d.plants);
                has_plants = true;
              }},
             {"yaws_deg",
              [&](const YAML::Node& n, const std::string& k) {
                d.yaws_deg = r.readList<double>(n, k, "angles in degrees");
              }},
             {"views",
              [&](const YAML::Node& n, const std::string& k) {
                d.views = r.read<int>(n, k, "an integer");
              }},
             {"candidates",
              [&](const YAML::Node& n, const std::string& k) {
                d.candidates = r.read<int>(n, k, "an integer");
              }},
             {"resolution",
              [&](const YAML::Node& n, const std::string& k) {
                d.resolution_m = r.read<double>(n, k, "a length in metres");
              }},
             {"repetitions",
              [&](const YAML::Node& n, const std::string& k) {
                d.repetitions = r.read<int>(n, k, "an integer");
              }},
             {"levels",
              [&](const YAML::Node& n, const std::string& k) {
                d.levels = r.readList<std::string>(n, k, "level names");
                for (std::size_t i = 0; i < d.levels.size(); ++i) {
                  const auto& known = levelSources();
                  if (d.levels[i] != "model_rois" &&
                      std::none_of(known.begin(), known.end(), [&](const LevelSource& l) {
                        return d.levels[i] == l.level;
                      }))
                    r.fail(k + "[" + std::to_string(i) + "]",
                           "unknown level '" + d.levels[i] +
                               "' (expected whole_plant, main_stem, leaf_nodes, fruit or "
                               "model_rois)");
                }
              }},
             {"trial",
              [&](const YAML::Node& n, const std::string&) {
                rejectCampaignKeys(r, n);
                readTrialConfig(n, name_for_messages, "trial.", f.base);
              }},
             {"studies", [&](const YAML::Node& n, const std::string& k) {
                if (!n.IsSequence())
                  r.fail(k, "expected a list of studies");
                for (std::size_t i = 0; i < n.size(); ++i)
                  d.studies.push_back(
                      readStudy(r, n[i], k + "[" + std::to_string(i) + "]"));
                has_studies = true;
              }}});
  if (!has_plants)
    r.fail("plants", "missing");
  if (!has_studies)
    r.fail("studies", "missing");
  try {
    d.validate();
    f.base.validate();
  } catch (const InvalidArgumentError& e) {
    throw InvalidArgumentError("'" + name_for_messages + "' " + e.what());
  }
  // Candidates: multiples of the sector's grid cells.
  const int cells = f.base.grid_rows * f.base.grid_cols;
  auto checkCandidates = [&](int n, const std::string& k) {
    if (n < cells || n % cells != 0)
      r.fail(k, std::to_string(n) + " is not a multiple of the " + std::to_string(cells) +
                    " grid cells (9, 27, 45, ...)");
  };
  checkCandidates(d.candidates, "candidates");
  for (std::size_t s = 0; s < d.studies.size(); ++s)
    for (std::size_t i = 0; i < d.studies[s].candidates.size(); ++i)
      checkCandidates(d.studies[s].candidates[i], "studies[" + std::to_string(s) +
                                                      "].candidates[" +
                                                      std::to_string(i) + "]");
  // Every trial's config is valid (resolutions, views, ...).
  for (const TrialSpec& t : expandCampaign(d)) {
    try {
      trialConfig(f, t).validate();
    } catch (const InvalidArgumentError& e) {
      throw InvalidArgumentError("'" + name_for_messages + "' trial " + t.id + ": " +
                                 e.what());
    }
  }
  return f;
}

/// A path of the campaign file, relative to the file's directory.
std::string resolve(const CampaignFile& f, const std::string& path)
{
  if (path.empty() || fs::path(path).is_absolute())
    return path;
  return (f.base_dir / path).string();
}

/// Runs one trial: its own plant, scene, map; one thread.
void runTrial(const CampaignFile& f, const TrialSpec& t, TrialResult& result)
{
  const CampaignPlant& plant = f.definition.plants.at(t.plant_index);
  PlantSourceOptions source;
  source.seed = plant.seed;
  source.stage = plant.stage;
  source.simplified = t.simplified;
  source.model = resolve(f, plant.model);
  source.labels = plant.labels;
  source.rois = resolve(f, plant.rois);
  source.yaw_deg = t.yaw_deg;
  const PlacedPlant placed = makePlacedPlant(source);
  TrialConfig config = trialConfig(f, t);
  if (!plant.model.empty()) { // as reconstruct: the sector follows a model's height
    Eigen::Vector3f lo, hi;
    placed.plant.bounds(lo, hi);
    config.sector.height_m =
        std::max(0.05, double(hi.z()) - placed.plant.base_position.z());
  }
  std::vector<EvaluationLevel> levels = evaluationLevels(placed);
  const std::vector<std::string>& wanted = f.definition.levels;
  if (!wanted.empty())
    levels.erase(std::remove_if(levels.begin(), levels.end(),
                                [&](const EvaluationLevel& l) {
                                  return std::find(wanted.begin(), wanted.end(),
                                                   l.name) == wanted.end();
                                }),
                 levels.end());
  if (levels.empty())
    throw InvalidArgumentError("plant '" + plant.name +
                               "' has none of the campaign's levels");
  Trial trial(config);
  trial.setPlant(std::make_shared<Plant>(placed.plant));
  // The baselines' gains are reported inside the whole plant, as reconstruct does.
  const std::string attention =
      t.kind == PlannerKind::nbv
          ? (fs::path(t.attention).has_extension() ? resolve(f, t.attention)
                                                   : t.attention)
          : "whole-plant";
  trial.setAttentionRoi(attentionRoi(placed, attention));
  trial.setEvaluationLevels(levels);
  trial.run(result);
}

std::atomic<bool> g_stop{false};

extern "C" void onInterrupt(int)
{
  g_stop = true;
  std::signal(SIGINT, SIG_DFL); // a second Ctrl-C ends the process at once
  std::signal(SIGTERM, SIG_DFL);
}

std::string clockText(double seconds)
{
  if (!std::isfinite(seconds) || seconds < 0)
    return "?";
  const long s = std::lround(seconds);
  char buffer[32];
  if (s >= 3600)
    std::snprintf(buffer, sizeof(buffer), "%ld:%02ld:%02ld", s / 3600, s / 60 % 60,
                  s % 60);
  else
    std::snprintf(buffer, sizeof(buffer), "%ld:%02ld", s / 60, s % 60);
  return buffer;
}

/// "[#####.....] 37/120 trials, 1 failed, 2:31 elapsed, ETA 4:10".
std::string progressLine(const CampaignProgress& p)
{
  const std::size_t finished = p.skipped + p.ran;
  const int width = 30;
  const int filled = p.total ? static_cast<int>(width * finished / p.total) : width;
  std::string line = "[" + std::string(filled, '#') + std::string(width - filled, '.') +
                     "] " + std::to_string(finished) + "/" + std::to_string(p.total) +
                     " trials, " + std::to_string(p.failed) + " failed, " +
                     clockText(p.elapsed_s) + " elapsed";
  if (p.stopping)
    line += ", stopping: waiting for " + std::to_string(p.running) + " running";
  else if (p.ran > 0 && p.to_run > p.ran) {
    // Trials run at `workers` at a time; the rate so far includes that.
    const double eta = p.elapsed_s / double(p.ran) * double(p.to_run - p.ran);
    line += ", ETA " + clockText(eta);
  } else if (p.to_run > p.ran)
    line += ", ETA ?";
  return line;
}

struct RunOptions {
  std::string file;
  std::string output_dir;
  int workers = 0;
  int chunk = -1;
  int chunks = 0;
};

void runCampaign(const RunOptions& o)
{
  const CampaignFile f = loadCampaign(o.file, o.file);
  const ResultStore store(o.output_dir);
  store.create(f.text);
  std::vector<TrialSpec> specs = expandCampaign(f.definition);
  const std::size_t all = specs.size();
  if (o.chunks > 0)
    specs = campaignChunk(specs, o.chunk, o.chunks);

  LocalRunner runner(
      store, [&f](const TrialSpec& t, TrialResult& r) { runTrial(f, t, r); }, o.workers);
  const bool tty = ::isatty(STDOUT_FILENO) != 0;
  bool stop_announced = false;
  runner.setProgressCallback([&](const CampaignProgress& p) {
    if (p.event == CampaignProgress::Event::started) {
      std::cout << "campaign '" << f.definition.name << "': " << all << " trials";
      if (o.chunks > 0)
        std::cout << "; chunk " << o.chunk << " of " << o.chunks << ": " << p.total
                  << " trials";
      std::cout << ", " << p.skipped << " already done, " << p.to_run << " to run on "
                << std::min<std::size_t>(p.to_run, std::size_t(p.workers)) << " worker"
                << (p.to_run == 1 || p.workers == 1 ? "" : "s") << "; results in "
                << (fs::path(o.output_dir) / "trials").string() << std::endl;
      return;
    }
    if (p.stopping && !stop_announced) {
      stop_announced = true;
      std::cout << (tty ? "\n" : "") << "interrupted: no new trials are started";
      if (p.running)
        std::cout << "; waiting for the " << p.running << " running (Ctrl-C again to "
                  << "abandon them)";
      std::cout << std::endl;
    }
    if (tty) {
      std::cout << "\r" << progressLine(p) << "\033[K" << std::flush;
      if (p.event == CampaignProgress::Event::finished && p.trial_failed)
        std::cout << "\r\033[Kfailed: " << p.id << ": " << p.error << "\n"
                  << progressLine(p) << std::flush;
    } else if (p.event == CampaignProgress::Event::finished) {
      std::cout << "[" << p.skipped + p.ran << "/" << p.total << "] " << p.id
                << (p.trial_failed ? " failed: " + p.error : std::string(" done"))
                << " in " << std::fixed << std::setprecision(1) << p.trial_s
                << std::defaultfloat << " s" << std::endl;
    }
  });
  g_stop = false;
  runner.setStopFlag(&g_stop);
  auto previous_int = std::signal(SIGINT, onInterrupt);
  auto previous_term = std::signal(SIGTERM, onInterrupt);
  CampaignProgress p;
  try {
    p = runner.run(specs);
  } catch (...) {
    std::signal(SIGINT, previous_int);
    std::signal(SIGTERM, previous_term);
    throw;
  }
  std::signal(SIGINT, previous_int);
  std::signal(SIGTERM, previous_term);
  if (tty && p.to_run > 0)
    std::cout << "\n";
  const std::size_t finished = p.skipped + p.ran;
  std::cout << finished - p.failed << " of " << p.total << " trials done"
            << (p.failed ? ", " + std::to_string(p.failed) + " failed" : std::string())
            << " (" << p.ran << " run now in " << clockText(p.elapsed_s) << ")"
            << std::endl;
  if (g_stop)
    throw Error("interrupted with " + std::to_string(p.total - finished + p.failed) +
                " trials left: run the same command again to resume");
  if (p.failed)
    throw Error(std::to_string(p.failed) + " of " + std::to_string(p.total) +
                " trials failed (their errors: plantnbv campaign status " + o.output_dir +
                "; run again to retry them)");
}

void statusCampaign(const std::string& dir)
{
  const ResultStore store(dir);
  const std::string file = store.definitionPath().string();
  if (!fs::exists(file))
    throw IoError("'" + dir + "' is not a campaign directory (no campaign.yaml)");
  const CampaignFile f = loadCampaign(file, file);
  const std::vector<TrialSpec> specs = expandCampaign(f.definition);
  const StoreStatus s = store.status(specs);
  std::cout << "campaign '" << f.definition.name << "': " << s.total << " trials, "
            << s.done << " done, " << s.failed << " failed, " << s.missing
            << " missing\n";
  const std::size_t shown = std::min<std::size_t>(s.failed_ids.size(), 20);
  for (std::size_t i = 0; i < shown; ++i)
    std::cout << "failed: " << s.failed_ids[i] << ": " << s.failed_errors[i] << "\n";
  if (shown < s.failed_ids.size())
    std::cout << "... and " << s.failed_ids.size() - shown << " more failed\n";
}

void reportCampaign(const std::string& dir, std::string out)
{
  const ResultStore store(dir);
  if (!fs::is_directory(fs::path(dir) / "trials"))
    throw IoError("'" + dir + "' is not a campaign directory (no trials/)");
  const std::vector<StoredTrial> trials = store.load();
  if (trials.empty())
    throw InvalidArgumentError("'" + dir + "' holds no trial results yet");
  std::string title = "Campaign " + fs::path(dir).filename().string();
  std::string missing;
  if (fs::exists(store.definitionPath())) {
    const CampaignFile f =
        loadCampaign(store.definitionPath().string(), store.definitionPath().string());
    title = "Campaign '" + f.definition.name + "'";
    const StoreStatus s = store.status(expandCampaign(f.definition));
    if (s.missing)
      missing = ", " + std::to_string(s.missing) + " of " + std::to_string(s.total) +
                " still missing";
  }
  if (out.empty())
    out = (fs::path(dir) / "report").string();
  writeCampaignReport(trials, out, title);
  const std::size_t failed = std::count_if(trials.begin(), trials.end(),
                                           [](const StoredTrial& t) { return t.failed; });
  std::cout << trials.size() - failed << " trials done, " << failed << " failed"
            << missing << "; wrote " << (fs::path(out) / "curves.csv").string()
            << " and summary.md\n";
}

} // namespace

void addCampaignCommand(CLI::App& app)
{
  CLI::App* cmd = app.add_subcommand(
      "campaign", "Run many trials from a campaign file (resumable, on all cores), count "
                  "them, and report their statistics");
  cmd->require_subcommand(1);

  auto run = std::make_shared<RunOptions>();
  CLI::App* r = cmd->add_subcommand("run", "Run the campaign's trials that are not done "
                                           "yet (Ctrl-C stops; run again to resume)");
  r->add_option("file", run->file, "Campaign file (YAML, e.g. data/campaigns/quick.yaml)")
      ->required();
  r->add_option("-o,--output", run->output_dir, "Campaign directory")->required();
  r->add_option("-j,--jobs", run->workers, "Trials at a time (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  r->callback([run]() { runCampaign(*run); });

  auto chunk = std::make_shared<RunOptions>();
  CLI::App* c = cmd->add_subcommand(
      "run-chunk",
      "Run one chunk of the trials (every N-th from the I-th), e.g. one task of "
      "an array job");
  c->add_option("file", chunk->file, "Campaign file (YAML)")->required();
  c->add_option("-o,--output", chunk->output_dir, "Campaign directory")->required();
  c->add_option("--chunk", chunk->chunk, "Chunk index, 0 to N-1")->required();
  c->add_option("--chunks", chunk->chunks, "Number of chunks N")->required();
  c->add_option("-j,--jobs", chunk->workers, "Trials at a time (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  c->callback([chunk]() { runCampaign(*chunk); });

  auto status_dir = std::make_shared<std::string>();
  CLI::App* s = cmd->add_subcommand("status", "Count done, failed and missing trials");
  s->add_option("dir", *status_dir, "Campaign directory")->required();
  s->callback([status_dir]() { statusCampaign(*status_dir); });

  auto report_dir = std::make_shared<std::string>();
  auto report_out = std::make_shared<std::string>();
  CLI::App* p = cmd->add_subcommand("report", "Write curves.csv (mean, sd, n, 95% CI per "
                                              "view) and summary.md");
  p->add_option("dir", *report_dir, "Campaign directory")->required();
  p->add_option("-o,--output", *report_out, "Report directory (default: DIR/report)");
  p->callback([report_dir, report_out]() { reportCampaign(*report_dir, *report_out); });
}

} // namespace app
} // namespace plantnbv
