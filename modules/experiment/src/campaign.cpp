#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/experiment/campaign.h>

namespace plantnbv {

namespace {

[[noreturn]] void bad(const std::string& path, const std::string& message)
{
  throw InvalidArgumentError(path + ": " + message);
}

std::string indexed(const std::string& list, std::size_t i)
{
  return list + "[" + std::to_string(i) + "]";
}

/// Names go into trial ids and file names: letters, digits, '.', '_', '-'.
void checkName(const std::string& path, const std::string& name)
{
  if (name.empty())
    bad(path, "empty name");
  for (char ch : name)
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '_' ||
          ch == '-'))
      bad(path, "'" + name + "' may only hold letters, digits, '.', '_' and '-'");
  if (name == "." || name == "..")
    bad(path, "'" + name + "' is not a name");
}

std::string yawLabel(double yaw_deg)
{
  char buffer[32];
  if (yaw_deg == std::round(yaw_deg))
    std::snprintf(buffer, sizeof(buffer), "yaw%03d", static_cast<int>(yaw_deg));
  else
    std::snprintf(buffer, sizeof(buffer), "yaw%g", yaw_deg);
  return buffer;
}

std::string resolutionLabel(double resolution_m)
{
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "res%gmm", resolution_m * 1000.0);
  return buffer;
}

std::string rowLabel(double spacing_m)
{
  if (spacing_m == 0.0)
    return "alone";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "row%gcm", spacing_m * 100.0);
  return buffer;
}

} // namespace

void CampaignDefinition::validate() const
{
  checkName("name", name);
  if (plants.empty())
    bad("plants", "expected at least one plant");
  std::set<std::string> plant_names;
  for (std::size_t i = 0; i < plants.size(); ++i) {
    const CampaignPlant& p = plants[i];
    const std::string path = indexed("plants", i);
    if (p.seed.has_value() == !p.model.empty())
      bad(path, "give either a seed (a generated plant) or a model file");
    if (p.stage && !(*p.stage >= 0.0 && *p.stage <= 1.0))
      bad(path + ".stage", std::to_string(*p.stage) + " is not in [0, 1]");
    if (!p.model.empty() && p.simplified)
      bad(path + ".simplified", "only a generated plant can be simplified");
    checkName(path + ".name", p.name);
    if (!plant_names.insert(p.name).second)
      bad(path + ".name", "'" + p.name + "' is used by another plant");
  }
  if (yaws_deg.empty())
    bad("yaws_deg", "expected at least one yaw");
  std::set<std::string> yaw_labels;
  for (std::size_t i = 0; i < yaws_deg.size(); ++i) {
    if (!std::isfinite(yaws_deg[i]) || std::abs(yaws_deg[i]) > 360.0)
      bad(indexed("yaws_deg", i), std::to_string(yaws_deg[i]) + " is not in [-360, 360]");
    if (!yaw_labels.insert(yawLabel(yaws_deg[i])).second)
      bad(indexed("yaws_deg", i), "repeated yaw " + yawLabel(yaws_deg[i]));
  }
  if (views < 1)
    bad("views", std::to_string(views) + ", expected >= 1");
  if (candidates < 1)
    bad("candidates", std::to_string(candidates) + ", expected >= 1");
  if (!(resolution_m > 0.0) || !std::isfinite(resolution_m))
    bad("resolution", std::to_string(resolution_m) + ", expected > 0 metres");
  if (repetitions < 1)
    bad("repetitions", std::to_string(repetitions) + ", expected >= 1");
  for (std::size_t i = 0; i < levels.size(); ++i)
    checkName(indexed("levels", i), levels[i]);
  if (studies.empty())
    bad("studies", "expected at least one study");
  std::set<std::string> study_names;
  for (std::size_t s = 0; s < studies.size(); ++s) {
    const CampaignStudy& study = studies[s];
    const std::string path = indexed("studies", s);
    checkName(path + ".name", study.name);
    if (!study_names.insert(study.name).second)
      bad(path + ".name", "'" + study.name + "' is used by another study");
    if (study.planners.empty())
      bad(path + ".planners", "expected at least one planner");
    std::set<std::string> planner_names;
    for (std::size_t p = 0; p < study.planners.size(); ++p) {
      const CampaignPlanner& planner = study.planners[p];
      const std::string ppath = indexed(path + ".planners", p);
      checkName(ppath + ".name", planner.name);
      if (!planner_names.insert(planner.name).second)
        bad(ppath + ".name",
            "'" + planner.name + "' is used by another planner of the study");
      if (planner.kind == PlannerKind::nbv && planner.attention.empty())
        bad(ppath + ".attention", "an NBV planner needs an attention ROI");
      if (planner.roi_source) {
        if (planner.kind != PlannerKind::nbv)
          bad(ppath + ".roi_source", "only an NBV planner has an ROI source");
        try {
          planner.roi_source->validate();
        } catch (const InvalidArgumentError& e) {
          bad(ppath, e.what());
        }
      }
      if (planner.kind == PlannerKind::predefined) {
        if (planner.patterns.empty())
          bad(ppath + ".patterns", "expected at least one pattern");
        std::set<int> seen;
        for (std::size_t k = 0; k < planner.patterns.size(); ++k)
          if (planner.patterns[k] < 1 || planner.patterns[k] > 4 ||
              !seen.insert(planner.patterns[k]).second)
            bad(indexed(ppath + ".patterns", k),
                std::to_string(planner.patterns[k]) + ", expected distinct patterns 1-4");
      }
    }
    for (std::size_t k = 0; k < study.candidates.size(); ++k)
      if (study.candidates[k] < 1)
        bad(indexed(path + ".candidates", k),
            std::to_string(study.candidates[k]) + ", expected >= 1");
    for (std::size_t k = 0; k < study.resolutions_m.size(); ++k)
      if (!(study.resolutions_m[k] > 0.0) || !std::isfinite(study.resolutions_m[k]))
        bad(indexed(path + ".resolutions", k),
            std::to_string(study.resolutions_m[k]) + ", expected > 0 metres");
    for (std::size_t k = 0; k < study.simplified.size(); ++k)
      if (study.simplified[k])
        for (std::size_t i = 0; i < plants.size(); ++i)
          if (!plants[i].model.empty())
            bad(indexed(path + ".simplified", k), "plant '" + plants[i].name +
                                                      "' is a model file and cannot be "
                                                      "simplified");
    if (std::set<bool>(study.simplified.begin(), study.simplified.end()).size() !=
        study.simplified.size())
      bad(path + ".simplified", "repeated value");
    if (std::set<int>(study.candidates.begin(), study.candidates.end()).size() !=
        study.candidates.size())
      bad(path + ".candidates", "repeated value");
    std::set<std::string> res;
    for (double r : study.resolutions_m)
      if (!res.insert(resolutionLabel(r)).second)
        bad(path + ".resolutions", "repeated value " + resolutionLabel(r));
    std::set<std::string> rows;
    for (std::size_t k = 0; k < study.row_spacings_m.size(); ++k) {
      const double s = study.row_spacings_m[k];
      if (!(s >= 0.0) || !std::isfinite(s))
        bad(indexed(path + ".row_spacings", k),
            std::to_string(s) + ", expected >= 0 metres (0: the plant alone)");
      if (!rows.insert(rowLabel(s)).second)
        bad(path + ".row_spacings", "repeated value " + rowLabel(s));
    }
  }
}

namespace {

std::uint64_t fnv1a64(const std::string& text)
{
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char ch : text) {
    h ^= ch;
    h *= 1099511628211ull;
  }
  return h;
}

} // namespace

std::uint64_t trialIdHash(const std::string& id)
{
  return fnv1a64(id);
}

std::string contentFingerprint(const std::string& text)
{
  char hex[17];
  std::snprintf(hex, sizeof(hex), "%016llx",
                static_cast<unsigned long long>(fnv1a64(text)));
  return hex;
}

std::vector<TrialSpec> expandCampaign(const CampaignDefinition& d)
{
  d.validate();
  std::vector<TrialSpec> specs;
  for (const CampaignStudy& study : d.studies) {
    // The study's variant axes; an empty list is one variant with the campaign's value.
    const std::vector<int> simplified_axis =
        study.simplified.empty()
            ? std::vector<int>{-1}
            : std::vector<int>(study.simplified.begin(), study.simplified.end());
    const std::vector<int> candidate_axis =
        study.candidates.empty() ? std::vector<int>{d.candidates} : study.candidates;
    const std::vector<double> resolution_axis = study.resolutions_m.empty()
                                                    ? std::vector<double>{d.resolution_m}
                                                    : study.resolutions_m;
    const std::vector<double> row_axis =
        study.row_spacings_m.empty() ? std::vector<double>{0.0} : study.row_spacings_m;
    for (const CampaignPlanner& planner : study.planners) {
      const std::vector<int> patterns = planner.kind == PlannerKind::predefined
                                            ? planner.patterns
                                            : std::vector<int>{0};
      for (int simplified : simplified_axis)
        for (int candidates : candidate_axis)
          for (double resolution : resolution_axis)
            for (double row_spacing : row_axis) {
              std::string variant;
              auto add = [&variant](const std::string& part) {
                variant += (variant.empty() ? "" : "-") + part;
              };
              if (!study.simplified.empty())
                add(simplified ? "simplified" : "original");
              if (!study.candidates.empty()) {
                char buffer[16];
                std::snprintf(buffer, sizeof(buffer), "c%02d", candidates);
                add(buffer);
              }
              if (!study.resolutions_m.empty())
                add(resolutionLabel(resolution));
              if (!study.row_spacings_m.empty())
                add(rowLabel(row_spacing));
              for (int pattern : patterns)
                for (std::size_t p = 0; p < d.plants.size(); ++p)
                  for (double yaw : d.yaws_deg)
                    for (int rep = 0; rep < d.repetitions; ++rep) {
                      // Checked while expanding: the product of the axes can overflow
                      // (found by fuzzing: an out-of-memory from a 1 KB file).
                      if (specs.size() >= kMaxCampaignTrials)
                        throw InvalidArgumentError("campaign: more than " +
                                                   std::to_string(kMaxCampaignTrials) +
                                                   " trials (plants x yaws x repetitions "
                                                   "x planners x variants); "
                                                   "split it into several campaigns");
                      TrialSpec t;
                      t.study = study.name;
                      t.variant = variant;
                      t.planner = planner.name;
                      t.kind = planner.kind;
                      if (planner.kind == PlannerKind::nbv) {
                        t.attention = planner.attention;
                        t.roi_source = planner.roi_source;
                      }
                      t.pattern = pattern;
                      t.plant_index = p;
                      t.plant = d.plants[p].name;
                      t.simplified =
                          simplified < 0 ? d.plants[p].simplified : simplified != 0;
                      t.yaw_deg = yaw;
                      t.repetition = rep;
                      t.candidates = candidates;
                      t.resolution_m = resolution;
                      t.row_spacing_m = row_spacing;
                      t.views = d.views;
                      t.id = study.name + "/" + planner.name +
                             (pattern ? "-p" + std::to_string(pattern) : std::string()) +
                             "/" + (variant.empty() ? std::string() : variant + "/") +
                             t.plant + "/" + yawLabel(yaw) + "/rep" + std::to_string(rep);
                      t.seed = deriveSeed(d.seed, trialIdHash(t.id));
                      t.fingerprint =
                          contentFingerprint(d.content_fingerprint + "\n" + t.id + "\n" +
                                             std::to_string(t.seed));
                      specs.push_back(std::move(t));
                    }
            }
    }
  }
  std::set<std::string> ids;
  for (const TrialSpec& t : specs)
    if (!ids.insert(t.id).second) // e.g. planners "a" with pattern 1 and "a-p1"
      throw InvalidArgumentError("two trials have the id '" + t.id +
                                 "': rename a planner or a plant");
  return specs;
}

} // namespace plantnbv
