#include <algorithm>
#include <cmath>
#include <future>
#include <iomanip>
#include <list>
#include <map>
#include <mutex>
#include <sstream>
#include <tuple>

#include <plantnbv/common/error.h>
#include <plantnbv/io/mesh_io.h>
#include <plantnbv/io/yaml_reader.h>
#include <plantnbv/scenario/campaign_file.h>
#include <plantnbv/scenario/placed_plant.h>
#include <plantnbv/scenario/trial_config_file.h>
#include <plantnbv/scenario/trial_setup.h>

namespace plantnbv {
namespace scenario {

namespace {

namespace fs = std::filesystem;
using io::YamlReader;

void readPlants(const YamlReader& r, const YAML::Node& node, const std::string& path,
                std::vector<CampaignPlant>& plants)
{
  if (!node.IsSequence())
    r.fail(path, "expected a list of plants ({seed: S} or {model: FILE})");
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string p = YamlReader::index(path, i);
    CampaignPlant plant;
    std::vector<std::uint64_t> seeds;
    bool named = false;
    r.forEach(
        node[i], p,
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
            // One file, or a list: a plant split into several mesh files.
            if (n.IsSequence()) {
              for (std::size_t i = 0; i < n.size(); ++i)
                (i ? plant.model_parts.emplace_back() : plant.model) =
                    r.read<std::string>(n[i], k + "[" + std::to_string(i) + "]",
                                        "a file name");
            } else {
              plant.model = r.read<std::string>(n, k, "a file name or a list of them");
            }
          }},
         {"labels",
          [&](const YAML::Node& n, const std::string& k) {
            plant.labels = r.read<std::string>(n, k, "label rules");
          }},
         {"rois",
          [&](const YAML::Node& n, const std::string& k) {
            plant.rois = r.read<std::string>(n, k, "an ROI file name");
          }},
         {"keep_frame",
          [&](const YAML::Node& n, const std::string& k) {
            plant.keep_frame = r.read<bool>(n, k, "true or false");
          }},
         {"scale",
          [&](const YAML::Node& n, const std::string& k) {
            plant.scale = r.read<double>(n, k, "metres per file unit");
            if (!(std::isfinite(plant.scale) && plant.scale > 0.0))
              r.fail(k, n.Scalar() + " is not a number of metres > 0");
          }},
         {"up_axis",
          [&](const YAML::Node& n, const std::string& k) {
            plant.up_axis = r.read<std::string>(n, k, "file, y or z");
            try {
              io::upAxisFromName(plant.up_axis);
            } catch (const InvalidArgumentError&) {
              r.fail(k, "'" + plant.up_axis + "' is not file, y or z");
            }
          }},
         {"sector_radius",
          [&](const YAML::Node& n, const std::string& k) {
            plant.sector_radius_m = r.read<double>(n, k, "a radius in metres");
            if (!(std::isfinite(*plant.sector_radius_m) && *plant.sector_radius_m > 0.0))
              r.fail(k, n.Scalar() + " is not a radius in metres > 0");
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
      if (plant.stage)
        r.fail(p + ".stage", "only a generated plant has a growth stage");
      if (!named)
        plant.name = fs::path(plant.model).stem().string();
      plants.push_back(plant);
      continue;
    }
    if (!plant.labels.empty())
      r.fail(p + ".labels", "label rules belong to a model file");
    if (plant.scale != 0.0)
      r.fail(p + ".scale", "a scale belongs to a model file");
    if (plant.up_axis != "file")
      r.fail(p + ".up_axis", "an up axis belongs to a model file");
    if (plant.keep_frame)
      r.fail(p + ".keep_frame", "a generated plant has no file frame to keep");
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

CampaignPlanner readPlanner(const YamlReader& r, const YAML::Node& node,
                            const std::string& p)
{
  CampaignPlanner planner;
  std::string type;
  bool has_attention = false, has_patterns = false;
  Attention attention;
  RoiSource roi_source;
  bool has_roi_source = false;
  auto roiKey = [&](auto read) {
    return [&, read](const YAML::Node& n, const std::string& k) {
      read(n, k);
      has_roi_source = true;
    };
  };
  r.forEach(
      node, p,
      {{"type",
        [&](const YAML::Node& n, const std::string& k) {
          type = r.read<std::string>(n, k, "nbv, predefined or random");
          try {
            planner.kind = plannerKindFromName(type);
          } catch (const InvalidArgumentError& e) {
            r.fail(k, e.what());
          }
        }},
       {"name",
        [&](const YAML::Node& n, const std::string& k) {
          planner.name = r.read<std::string>(n, k, "a name");
        }},
       {"attention",
        [&](const YAML::Node& n, const std::string& k) {
          // Kept as written: trial files record it so.
          planner.attention = r.read<std::string>(n, k, "an ROI name or file");
          try {
            attention = Attention::parse(planner.attention);
          } catch (const InvalidArgumentError& e) {
            r.fail(k, e.what());
          }
          has_attention = true;
        }},
       {"roi_source", roiKey([&](const YAML::Node& n, const std::string& k) {
          const std::string name = r.read<std::string>(n, k, "an ROI source name");
          try {
            roi_source.kind = roiSourceKindFromName(name);
          } catch (const InvalidArgumentError& e) {
            r.fail(k, e.what());
          }
        })},
       {"roi_sigma", roiKey([&](const YAML::Node& n, const std::string& k) {
          roi_source.sigma_m = r.read<double>(n, k, "a number (metres)");
        })},
       {"roi_scale", roiKey([&](const YAML::Node& n, const std::string& k) {
          roi_source.scale = r.read<double>(n, k, "a number");
        })},
       {"detector_recall", roiKey([&](const YAML::Node& n, const std::string& k) {
          roi_source.detector_recall = r.read<double>(n, k, "a number in [0, 1]");
        })},
       {"detector_false_positives",
        roiKey([&](const YAML::Node& n, const std::string& k) {
          roi_source.detector_false_positives =
              r.read<double>(n, k, "a number (per frame)");
        })},
       {"detector_box_jitter", roiKey([&](const YAML::Node& n, const std::string& k) {
          roi_source.detector_box_jitter_px = r.read<double>(n, k, "pixels");
        })},
       {"detector_mask_dilation", roiKey([&](const YAML::Node& n, const std::string& k) {
          roi_source.detector_mask_dilation_px =
              r.read<int>(n, k, "whole pixels (< 0: shrink)");
        })},
       {"detector_masks", roiKey([&](const YAML::Node& n, const std::string& k) {
          roi_source.detector_masks = r.read<bool>(n, k, "true or false");
        })},
       {"prior_internode", roiKey([&](const YAML::Node& n, const std::string& k) {
          roi_source.prior_internode_m = r.read<double>(n, k, "a number (metres)");
        })},
       {"detections_explore_views",
        roiKey([&](const YAML::Node& n, const std::string& k) {
          roi_source.detections_explore_views = r.read<int>(n, k, "views (integer)");
        })},
       {"patterns", [&](const YAML::Node& n, const std::string& k) {
          planner.patterns = r.readList<int>(n, k, "patterns 1-4");
          for (std::size_t i = 0; i < planner.patterns.size(); ++i)
            if (planner.patterns[i] < 1 || planner.patterns[i] > 4)
              r.fail(YamlReader::index(k, i),
                     std::to_string(planner.patterns[i]) + " is not a pattern 1-4");
          has_patterns = true;
        }}});
  if (type.empty())
    r.fail(p + ".type", "missing (nbv, predefined or random)");
  if (planner.kind == PlannerKind::nbv) {
    if (!has_attention)
      r.fail(p + ".attention", "missing: an NBV planner needs an attention ROI");
    if (has_patterns)
      r.fail(p + ".patterns", "only a predefined planner has patterns");
    if (has_roi_source) {
      try {
        roi_source.validate();
      } catch (const InvalidArgumentError& e) {
        r.fail(p, e.what());
      }
      planner.roi_source = roi_source;
    }
    if (planner.name.empty())
      planner.name = nbvPlannerName(attention, roi_source);
  } else {
    if (has_attention)
      r.fail(p + ".attention", "only an NBV planner has an attention ROI");
    if (has_roi_source)
      r.fail(p + ".roi_source", "only an NBV planner has an ROI source");
    if (planner.kind == PlannerKind::random && has_patterns)
      r.fail(p + ".patterns", "only a predefined planner has patterns");
    if (planner.kind == PlannerKind::predefined && !has_patterns)
      planner.patterns = {1, 2, 3, 4};
    if (planner.name.empty())
      planner.name = type;
  }
  return planner;
}

CampaignStudy readStudy(const YamlReader& r, const YAML::Node& node, const std::string& p)
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
                  study.planners.push_back(readPlanner(r, n[i], YamlReader::index(k, i)));
              }},
             {"simplified",
              [&](const YAML::Node& n, const std::string& k) {
                study.simplified = r.readList<bool>(n, k, "true or false");
              }},
             {"candidates",
              [&](const YAML::Node& n, const std::string& k) {
                study.candidates = r.readList<int>(n, k, "candidate counts (integers)");
              }},
             {"resolutions",
              [&](const YAML::Node& n, const std::string& k) {
                study.resolutions_m = r.readList<double>(n, k, "resolutions (metres)");
              }},
             {"row_spacings", [&](const YAML::Node& n, const std::string& k) {
                study.row_spacings_m =
                    r.readList<double>(n, k, "distances between plants (metres)");
              }}});
  if (study.name.empty())
    r.fail(p + ".name", "missing");
  return study;
}

/// Keys of `trial:` that the campaign sets per trial.
void rejectCampaignKeys(const YamlReader& r, const YAML::Node& trial)
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

/// A path of the campaign file, relative to the file's directory.
std::string resolve(const CampaignFile& f, const std::string& path)
{
  if (path.empty() || fs::path(path).is_absolute())
    return path;
  return (f.base_dir / path).string();
}

} // namespace

TrialConfig campaignTrialConfig(const CampaignFile& f, const TrialSpec& t)
{
  TrialConfig c = f.base;
  c.planner = t.kind;
  if (t.kind == PlannerKind::predefined)
    c.pattern = t.pattern;
  if (t.roi_source)
    c.roi_source = *t.roi_source;
  c.views = t.views;
  setCandidateCount(t.candidates, "candidates", c);
  c.map.resolution_m = t.resolution_m;
  c.seed = t.seed;
  c.threads = 1; // one trial per worker: no nested parallelism
  return c;
}

CampaignFile loadCampaignFile(const std::string& path)
{
  return parseCampaignFile(YamlReader::readText(path), path);
}

CampaignFile parseCampaignFile(const std::string& text, const std::string& path,
                               const TrialConfig& defaults)
{
  CampaignFile f;
  f.path = path;
  f.text = text;
  f.base = defaults;
  f.base_dir = fs::path(path).parent_path();
  const YamlReader r(path);
  const YAML::Node root = r.parse(f.text);
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
                for (std::size_t i = 0; i < d.yaws_deg.size(); ++i)
                  if (!(std::abs(d.yaws_deg[i]) <= kMaxPlantYawDeg))
                    r.fail(YamlReader::index(k, i),
                           "expected an angle in [-360, 360] degrees, got " +
                               YamlReader::describe(n[i]));
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
                  try {
                    d.levels[i] = canonicalLevelName(d.levels[i]);
                  } catch (const InvalidArgumentError& e) {
                    r.fail(YamlReader::index(k, i), e.what());
                  }
                }
              }},
             {"trial",
              [&](const YAML::Node& n, const std::string& k) {
                rejectCampaignKeys(r, n);
                readTrialConfig(r, n, k, f.base);
              }},
             {"studies", [&](const YAML::Node& n, const std::string& k) {
                if (!n.IsSequence())
                  r.fail(k, "expected a list of studies");
                for (std::size_t i = 0; i < n.size(); ++i)
                  d.studies.push_back(readStudy(r, n[i], YamlReader::index(k, i)));
                has_studies = true;
              }}});
  if (!has_plants)
    r.fail("plants", "missing");
  // A plant in its file's frame is not turned (the yaws would be the same trial again)
  // and has no base to place a row's neighbours from.
  for (std::size_t i = 0; i < d.plants.size(); ++i) {
    if (!d.plants[i].keep_frame)
      continue;
    const std::string key = "plants[" + std::to_string(i) + "].keep_frame";
    for (double yaw : d.yaws_deg)
      if (yaw != 0.0)
        r.fail(key,
               "a plant kept in its file's frame is not turned: yaws_deg must be [0]");
    for (const CampaignStudy& study : d.studies)
      for (double spacing : study.row_spacings_m)
        if (spacing != 0.0)
          r.fail(key, "a plant kept in its file's frame has no base to place the "
                      "neighbours of study '" +
                          study.name + "' from");
  }
  if (!has_studies)
    r.fail("studies", "missing");
  try {
    d.validate();
    f.base.validate();
  } catch (const InvalidArgumentError& e) {
    throw InvalidArgumentError("'" + path + "' " + e.what());
  }
  // The file and the defaults it was read over: a default that changes makes another
  // campaign, whose trials are run again rather than taken from an old directory.
  d.content_fingerprint =
      contentFingerprint(YamlReader::canonical(root) + "\n" + trialConfigText(f.base));
  // Candidates: the rule of setCandidateCount, checked with the key that set them.
  auto checkCandidates = [&](int n, const std::string& k) {
    TrialConfig c = f.base;
    try {
      setCandidateCount(n, k, c);
    } catch (const InvalidArgumentError& e) {
      throw FormatError("'" + path + "' " + e.what());
    }
  };
  checkCandidates(d.candidates, "candidates");
  for (std::size_t s = 0; s < d.studies.size(); ++s)
    for (std::size_t i = 0; i < d.studies[s].candidates.size(); ++i)
      checkCandidates(
          d.studies[s].candidates[i],
          YamlReader::index("studies[" + std::to_string(s) + "].candidates", i));
  // Every trial's config is valid (resolutions, views, ...).
  for (const TrialSpec& t : expandCampaign(d)) {
    try {
      campaignTrialConfig(f, t).validate();
    } catch (const InvalidArgumentError& e) {
      throw InvalidArgumentError("'" + path + "' trial " + t.id + ": " + e.what());
    }
  }
  return f;
}

namespace {

PlantSource plantSourceOf(const CampaignFile& f, const TrialSpec& t)
{
  const CampaignPlant& plant = f.definition.plants.at(t.plant_index);
  PlantSource source;
  source.seed = plant.seed;
  if (plant.seed) { // a study's simplified variant applies to generated plants
    source.stage = plant.stage;
    source.simplified = t.simplified;
  }
  source.model = resolve(f, plant.model);
  for (const std::string& part : plant.model_parts)
    source.model_parts.push_back(resolve(f, part));
  source.labels = plant.labels;
  source.scale = plant.scale;
  source.up_axis = io::upAxisFromName(plant.up_axis);
  source.rois = resolve(f, plant.rois);
  source.keep_frame = plant.keep_frame;
  source.yaw_deg = t.yaw_deg;
  return source;
}

/// Trial `t`'s sector (config: campaignTrialConfig) fitted to its plant.
void fitCampaignSector(const CampaignFile& f, const TrialSpec& t,
                       const PlacedPlant& placed, TrialConfig& config)
{
  fitSectorToPlant(placed, std::nullopt, config);
  const CampaignPlant& plant = f.definition.plants.at(t.plant_index);
  if (plant.sector_radius_m)
    config.sector.radius_m = *plant.sector_radius_m;
}

/// Everything a CampaignSceneCache entry is made from, exactly (doubles in hex).
std::string sceneKey(const TrialSpec& t, const TrialConfig& c)
{
  std::ostringstream k;
  k << std::hexfloat << t.plant_index << ' ' << t.simplified << ' ' << t.yaw_deg << ' '
    << t.row_spacing_m << ' ' << c.threads;
  const CylindricalSector& sector = c.sector;
  k << " sector " << sector.axis_base.x() << ' ' << sector.axis_base.y() << ' '
    << sector.axis_base.z() << ' ' << sector.radius_m << ' ' << sector.height_m << ' '
    << sector.bottom_m << ' ' << sector.angle_rad << ' ' << sector.facing_rad;
  const PlantSceneConfig& scene = c.scene;
  k << " scene " << scene.floor << ' ' << scene.floor_height_m << ' '
    << scene.floor_half_size_m << ' ' << scene.support << ' '
    << scene.support_half_width_m << ' ' << scene.surfels.radius_m << ' '
    << scene.surfels.spacing_neighbours << ' ' << scene.surfels.radius_factor;
  return k.str();
}

/// What trial `t` (config: campaignTrialConfig) shares with the others of its plant,
/// pose and row.
std::shared_ptr<const CampaignSceneCache::Entry>
makeSceneEntry(const CampaignFile& f, const TrialSpec& t, const TrialConfig& config)
{
  auto entry = std::make_shared<CampaignSceneCache::Entry>();
  entry->placed = makePlacedPlant(plantSourceOf(f, t));
  TrialConfig fitted = config;
  fitCampaignSector(f, t, entry->placed, fitted);
  entry->neighbours = rowNeighbourPlants(entry->placed, t.row_spacing_m, fitted);
  entry->scene =
      makePlantScene(entry->placed.plant, fitted.scene,
                     static_cast<unsigned int>(fitted.threads), entry->neighbours);
  entry->initial_views = std::make_shared<InitialViewCache>();
  return entry;
}

} // namespace

struct CampaignSceneCache::Impl {
  using Future = std::shared_future<std::shared_ptr<const Entry>>;
  std::size_t capacity;
  mutable std::mutex mutex;
  std::list<std::pair<std::string, Future>> entries; ///< the last asked for first
  std::size_t builds = 0;
};

CampaignSceneCache::CampaignSceneCache(std::size_t capacity)
    : impl_(std::make_unique<Impl>())
{
  if (capacity == 0)
    throw InvalidArgumentError("CampaignSceneCache: the capacity must be at least 1");
  impl_->capacity = capacity;
}

CampaignSceneCache::~CampaignSceneCache() = default;

std::size_t CampaignSceneCache::builds() const
{
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->builds;
}

std::shared_ptr<const CampaignSceneCache::Entry>
CampaignSceneCache::get(const CampaignFile& f, const TrialSpec& t,
                        const TrialConfig& config)
{
  const std::string key = sceneKey(t, config);
  std::promise<std::shared_ptr<const Entry>> promise;
  Impl::Future future;
  bool make = false;
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    auto& entries = impl_->entries;
    const auto it = std::find_if(entries.begin(), entries.end(),
                                 [&](const auto& e) { return e.first == key; });
    if (it != entries.end()) {
      entries.splice(entries.begin(), entries, it);
    } else {
      entries.emplace_front(key, promise.get_future().share());
      if (entries.size() > impl_->capacity)
        entries.pop_back(); // a build under way goes on for those who wait for it
      ++impl_->builds;
      make = true;
    }
    future = entries.front().second;
  }
  if (make) {
    try {
      promise.set_value(makeSceneEntry(f, t, config));
    } catch (...) {
      promise.set_exception(std::current_exception());
      // Those waiting get the error; a later trial tries again.
      std::lock_guard<std::mutex> lock(impl_->mutex);
      impl_->entries.remove_if([&](const auto& e) { return e.first == key; });
    }
  }
  return future.get();
}

void runCampaignTrial(const CampaignFile& f, const TrialSpec& t, TrialResult& result,
                      CampaignSceneCache* cache)
{
  TrialConfig config = campaignTrialConfig(f, t);
  const std::shared_ptr<const CampaignSceneCache::Entry> shared =
      cache ? cache->get(f, t, config) : makeSceneEntry(f, t, config);
  const PlacedPlant& placed = shared->placed;
  fitCampaignSector(f, t, placed, config);
  const CampaignPlant& plant = f.definition.plants.at(t.plant_index);
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
  // The baselines' gains are reported inside the whole plant, as reconstruct's default.
  Attention attention;
  if (t.kind != PlannerKind::nbv)
    attention.kind = RoiKind::whole_plant;
  else {
    attention = Attention::parse(t.attention);
    attention.file = resolve(f, attention.file);
  }
  Trial trial(config);
  setUpTrial(placed, attentionRoi(placed, attention), levels, trial);
  trial.setNeighbours(shared->neighbours);
  trial.setScene(shared->scene);
  trial.setInitialViewCache(shared->initial_views);
  trial.setKeepFullMap(false); // a campaign keeps the steps and scores, not the map
  trial.run(result);
}

LocalRunner::TrialFunction campaignTrialFunction(const CampaignFile& f)
{
  auto scenes = std::make_shared<CampaignSceneCache>(2);
  return [&f, scenes](const TrialSpec& t, TrialResult& result) {
    runCampaignTrial(f, t, result, scenes.get());
  };
}

void groupTrialsByScene(std::vector<TrialSpec>& specs)
{
  std::stable_sort(
      specs.begin(), specs.end(), [](const TrialSpec& a, const TrialSpec& b) {
        return std::tie(a.plant_index, a.simplified, a.yaw_deg, a.row_spacing_m) <
               std::tie(b.plant_index, b.simplified, b.yaw_deg, b.row_spacing_m);
      });
}

namespace {

/// The campaign file a campaign directory holds. \throws as campaignDirectoryStatus.
CampaignFile directoryCampaignFile(const ResultStore& store)
{
  if (!std::filesystem::exists(store.definitionPath()))
    throw FileNotFoundError("'" + store.dir().string() +
                            "' is not a campaign directory (no campaign.yaml)");
  return loadCampaignFile(store.definitionPath().string());
}

} // namespace

StoreStatus campaignDirectoryStatus(const std::filesystem::path& dir, CampaignFile* file)
{
  const ResultStore store(dir);
  CampaignFile f = directoryCampaignFile(store);
  const StoreStatus status = store.status(expandCampaign(f.definition));
  if (file)
    *file = std::move(f);
  return status;
}

std::vector<TimingRow> campaignDirectoryTiming(const std::filesystem::path& dir)
{
  const ResultStore store(dir);
  return campaignTiming(
      store.loadDone(expandCampaign(directoryCampaignFile(store).definition)));
}

} // namespace scenario
} // namespace plantnbv
