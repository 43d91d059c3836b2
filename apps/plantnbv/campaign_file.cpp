#include "campaign_file.h"

#include <algorithm>
#include <fstream>
#include <functional>
#include <iomanip>
#include <map>
#include <memory>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include <plantnbv/common/error.h>

#include "plant_source.h"
#include "trial_config.h"
#include "trial_setup.h"

namespace plantnbv {
namespace app {

namespace {

namespace fs = std::filesystem;

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
      // A key may be a list or a map in YAML ("? [a]: 1"); ours are names (found by
      // fuzzing: as<std::string>() threw a YAML exception).
      if (!item.first.IsScalar())
        fail(key_path.empty() ? "(top level)" : key_path,
             "a key must be a name, not a list or a map");
      const std::string key = item.first.Scalar();
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

} // namespace

TrialConfig campaignTrialConfig(const CampaignFile& f, const TrialSpec& t)
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

CampaignFile loadCampaignFile(const std::string& path,
                              const std::string& name_for_messages)
{
  std::ifstream in(path);
  if (!in)
    throw IoError("cannot read campaign file '" + path + "'");
  std::stringstream text;
  text << in.rdbuf();
  return parseCampaignFile(text.str(), path, name_for_messages);
}

CampaignFile parseCampaignFile(const std::string& text, const std::string& path,
                               const std::string& name_for_messages)
{
  CampaignFile f;
  f.path = path;
  f.text = text;
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
      campaignTrialConfig(f, t).validate();
    } catch (const InvalidArgumentError& e) {
      throw InvalidArgumentError("'" + name_for_messages + "' trial " + t.id + ": " +
                                 e.what());
    }
  }
  return f;
}

namespace {

/// A path of the campaign file, relative to the file's directory.
std::string resolve(const CampaignFile& f, const std::string& path)
{
  if (path.empty() || fs::path(path).is_absolute())
    return path;
  return (f.base_dir / path).string();
}

} // namespace

void runCampaignTrial(const CampaignFile& f, const TrialSpec& t, TrialResult& result)
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
  TrialConfig config = campaignTrialConfig(f, t);
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

} // namespace app
} // namespace plantnbv
