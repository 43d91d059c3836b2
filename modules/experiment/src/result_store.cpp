#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include <plantnbv/common/error.h>
#include <plantnbv/common/file_io.h>
#include <plantnbv/common/number_text.h>
#include <plantnbv/experiment/result_store.h>

namespace plantnbv {

namespace {

using nlohmann::json;

/// The shortest text that reads back to the same double (std::to_chars); null for NaN
/// and infinities (JSON has none).
std::string number(double x)
{
  return std::isfinite(x) ? shortestText(x) : "null";
}

json finite(double x)
{
  return std::isfinite(x) ? json(x) : json(nullptr);
}

std::string fileName(const std::string& id)
{
  std::string name = id;
  std::replace(name.begin(), name.end(), '/', '+');
  return name + ".json";
}

nlohmann::ordered_json specJson(const TrialSpec& t)
{
  nlohmann::ordered_json s;
  s["study"] = t.study;
  s["variant"] = t.variant;
  s["planner"] = t.planner;
  s["kind"] = plannerKindName(t.kind);
  s["attention"] = t.kind == PlannerKind::nbv ? json(t.attention) : json(nullptr);
  s["pattern"] = t.kind == PlannerKind::predefined ? json(t.pattern) : json(nullptr);
  s["plant"] = t.plant;
  s["simplified"] = t.simplified;
  s["yaw_deg"] = t.yaw_deg;
  s["repetition"] = t.repetition;
  s["candidates"] = t.candidates;
  s["resolution"] = t.resolution_m;
  s["views"] = t.views;
  s["seed"] = t.seed;
  return s;
}

std::string dumpOrdered(const nlohmann::ordered_json& j)
{
  // Objects one key per line in insertion order, arrays of scalars on one line.
  std::string out;
  std::function<void(const nlohmann::ordered_json&, int)> rec =
      [&](const nlohmann::ordered_json& v, int indent) {
        const std::string pad(indent * 2, ' ');
        if (v.is_object() && !v.empty()) {
          out += "{\n";
          bool first = true;
          for (auto it = v.begin(); it != v.end(); ++it) {
            out += first ? "" : ",\n";
            first = false;
            out += pad + "  " + json(it.key()).dump() + ": ";
            rec(it.value(), indent + 1);
          }
          out += "\n" + pad + "}";
        } else if (v.is_array() && std::any_of(v.begin(), v.end(), [](const auto& e) {
                     return e.is_object() || e.is_array();
                   })) {
          out += "[\n";
          for (std::size_t i = 0; i < v.size(); ++i) {
            out += pad + "  ";
            rec(v[i], indent + 1);
            out += i + 1 < v.size() ? ",\n" : "\n";
          }
          out += pad + "]";
        } else if (v.is_array()) {
          out += "[";
          for (std::size_t i = 0; i < v.size(); ++i) {
            out += i ? ", " : "";
            rec(v[i], indent + 1);
          }
          out += "]";
        } else if (v.is_number_float()) {
          out += number(v.get<double>());
        } else {
          out += v.dump();
        }
      };
  rec(j, 0);
  return out + "\n";
}

/// A time of a result file (a key ending in "_ms"): NaN where `object` has none or a
/// value that is not a time.
double timeOf(const json& object, const char* key)
{
  if (!object.contains(key) || !object[key].is_number())
    return std::numeric_limits<double>::quiet_NaN();
  const double ms = object[key].get<double>();
  return std::isfinite(ms) && ms >= 0.0 ? ms : std::numeric_limits<double>::quiet_NaN();
}

} // namespace

ResultStore::ResultStore(std::filesystem::path dir) : dir_(std::move(dir)) {}

std::filesystem::path ResultStore::resultPath(const std::string& id) const
{
  return dir_ / "trials" / fileName(id);
}

void ResultStore::create(const std::string& definition_text,
                         const std::string& fingerprint) const
{
  std::error_code ec;
  std::filesystem::create_directories(dir_ / "trials", ec);
  if (ec)
    throw IoError("cannot create campaign directory '" + dir_.string() +
                  "': " + ec.message());
  const auto another = [&](const std::string& why) {
    return InvalidArgumentError("'" + dir_.string() + "' holds another campaign (" + why +
                                "): give another output directory");
  };
  const std::filesystem::path record = dir_ / "campaign.json";
  const std::filesystem::path definition = definitionPath();
  if (std::filesystem::exists(record)) {
    requireRegularFile(record);
    std::string stored;
    try {
      std::ifstream in(record);
      stored = json::parse(in).at("fingerprint").get<std::string>();
    } catch (const json::exception& e) {
      throw FormatError("'" + record.string() +
                        "' is not a campaign record: " + e.what());
    }
    if (stored != fingerprint)
      throw another("its fingerprint " + stored + " is not this definition's " +
                    fingerprint +
                    "; comments and key order do not count, plantnbv's built-in "
                    "trial defaults do");
    return;
  }
  // A directory of release 0.1.0, which wrote no record and no trial fingerprints: its
  // text decides, and its trial files stay its own.
  const bool legacy = std::filesystem::exists(definition);
  if (legacy) {
    requireRegularFile(definition);
    std::ifstream in(definition);
    std::stringstream text;
    text << in.rdbuf();
    if (text.str() != definition_text)
      throw another("its campaign.yaml differs from this definition");
  } else {
    writeFileAtomically(definition, definition_text);
  }
  writeFileAtomically(record, "{\"fingerprint\": \"" + fingerprint + "\"" +
                                  (legacy ? ", \"legacy_trials\": true" : "") + "}\n");
}

bool ResultStore::acceptsTrialsWithoutFingerprint() const
{
  const std::filesystem::path record = dir_ / "campaign.json";
  std::error_code ec;
  if (!std::filesystem::exists(record, ec))
    return true; // not opened since release 0.1.0
  try {
    std::ifstream in(record);
    return json::parse(in).value("legacy_trials", false);
  } catch (const json::exception&) {
    return false;
  }
}

bool ResultStore::isTrialOf(const std::string& file_fingerprint, bool has_fingerprint,
                            const TrialSpec& spec) const
{
  return has_fingerprint ? file_fingerprint == spec.fingerprint
                         : acceptsTrialsWithoutFingerprint();
}

void ResultStore::writeResult(const TrialSpec& spec, const TrialResult& r) const
{
  nlohmann::ordered_json j;
  j["id"] = spec.id;
  j["fingerprint"] = spec.fingerprint;
  j["spec"] = specJson(spec);
  j["status"] = "done";
  j["levels"] = r.level_names;
  nlohmann::ordered_json views = nlohmann::ordered_json::array();
  for (const TrialStep& s : r.steps) {
    nlohmann::ordered_json v;
    const Eigen::Quaterniond& q = s.view.orientation;
    v["index"] = s.index;
    v["pose"] = {s.view.position.x(),
                 s.view.position.y(),
                 s.view.position.z(),
                 q.x(),
                 q.y(),
                 q.z(),
                 q.w()};
    v["gain"] = finite(s.gain);
    v["candidates"] = s.candidates;
    v["occupied_voxels"] = s.occupied_voxels;
    v["plan_ms"] = s.plan_ms;
    v["capture_ms"] = s.capture_ms;
    v["insert_ms"] = s.insert_ms;
    v["eval_ms"] = s.eval_ms;
    nlohmann::ordered_json levels;
    for (std::size_t l = 0; l < s.scores.size() && l < r.level_names.size(); ++l) {
      const LevelScore& score = s.scores[l];
      levels[r.level_names[l]] = {{"precision", finite(score.precision)},
                                  {"recall", finite(score.recall)},
                                  {"f1", finite(score.f1)},
                                  {"chamfer", finite(score.chamfer)}};
    }
    v["levels"] = levels;
    if (!s.organs.empty()) {
      nlohmann::ordered_json organs;
      for (const OrganRecall& o : s.organs)
        organs[partLabelName(o.organ)] = finite(o.recall);
      v["organs"] = organs;
    }
    views.push_back(v);
  }
  j["views"] = views;
  j["stopped_early"] = r.stopped_early;
  j["setup_ms"] = r.setup_ms;
  j["total_ms"] = r.total_ms;
  writeFileAtomically(resultPath(spec.id), dumpOrdered(j));
}

void ResultStore::writeFailure(const TrialSpec& spec, const std::string& error) const
{
  nlohmann::ordered_json j;
  j["id"] = spec.id;
  j["fingerprint"] = spec.fingerprint;
  j["spec"] = specJson(spec);
  j["status"] = "failed";
  j["error"] = error;
  writeFileAtomically(resultPath(spec.id), dumpOrdered(j));
}

TrialState ResultStore::state(const TrialSpec& spec) const
{
  return readState(spec, nullptr);
}

TrialState ResultStore::readState(const TrialSpec& spec, double* total_s) const
{
  if (total_s)
    *total_s = std::numeric_limits<double>::quiet_NaN();
  const std::filesystem::path path = resultPath(spec.id);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    return TrialState::missing;
  requireRegularFile(path); // a FIFO would block the campaign
  std::ifstream in(path);
  try {
    const json j = json::parse(in);
    const std::string status = j.at("status").get<std::string>();
    if (j.at("id").get<std::string>() != spec.id)
      return TrialState::missing;
    if (!isTrialOf(j.value("fingerprint", std::string()), j.contains("fingerprint"),
                   spec))
      return TrialState::foreign;
    if (total_s && status == "done")
      *total_s = timeOf(j, "total_ms") / 1000.0;
    return status == "done"     ? TrialState::done
           : status == "failed" ? TrialState::failed
                                : TrialState::missing;
  } catch (const json::exception&) {
    return TrialState::missing; // not ours or damaged: run the trial again
  }
}

StoreStatus ResultStore::status(const std::vector<TrialSpec>& specs) const
{
  StoreStatus s;
  s.total = specs.size();
  for (const TrialSpec& spec : specs) {
    double total_s = 0.0;
    switch (readState(spec, &total_s)) {
    case TrialState::done:
      ++s.done;
      if (std::isfinite(total_s)) {
        ++s.timed;
        s.timed_s += total_s;
      }
      break;
    case TrialState::failed: {
      ++s.failed;
      s.failed_ids.push_back(spec.id);
      std::string error;
      try {
        error = loadFile(resultPath(spec.id)).error;
      } catch (const Error&) {
      }
      s.failed_errors.push_back(error);
      break;
    }
    case TrialState::foreign:
      ++s.foreign;
      ++s.missing;
      break;
    case TrialState::missing:
      ++s.missing;
      break;
    }
  }
  return s;
}

namespace {

/// Reads the fields of one result file, each checked for its type and its range.
class TrialFileReader {
public:
  explicit TrialFileReader(const std::filesystem::path& path) : path_(path) {}

  [[noreturn]] void fail(const std::string& field, const std::string& message) const
  {
    throw FormatError("'" + path_.string() + "' " + field + ": " + message);
  }
  const json& at(const json& object, const std::string& parent,
                 const std::string& key) const
  {
    if (!object.is_object() || !object.contains(key))
      fail(parent.empty() ? key : parent + "." + key, "missing");
    return object[key];
  }
  std::string text(const json& v, const std::string& field) const
  {
    if (!v.is_string())
      fail(field, "expected a string, got " + v.dump());
    return v.get<std::string>();
  }
  double number(const json& v, const std::string& field, double lo, double hi) const
  {
    if (!v.is_number() || !(v.get<double>() >= lo && v.get<double>() <= hi))
      fail(field, "expected a number in [" + ::plantnbv::number(lo) + ", " +
                      ::plantnbv::number(hi) + "], got " + v.dump());
    return v.get<double>();
  }
  /// A score: null (not defined, e.g. an empty ROI) or a number in [lo, hi].
  double score(const json& levels, const std::string& parent, const std::string& key,
               double hi) const
  {
    const json& v = at(levels, parent, key);
    return v.is_null() ? std::numeric_limits<double>::quiet_NaN()
                       : number(v, parent + "." + key, 0.0, hi);
  }
  int integer(const json& v, const std::string& field, int lo, int hi) const
  {
    if (!v.is_number_integer() || v.get<long long>() < lo || v.get<long long>() > hi)
      fail(field, "expected an integer in [" + std::to_string(lo) + ", " +
                      std::to_string(hi) + "], got " + v.dump());
    return v.get<int>();
  }

private:
  std::filesystem::path path_;
};

} // namespace

bool TrialTimes::complete() const
{
  return std::all_of(kTrialTimes.begin(), kTrialTimes.end(),
                     [this](double TrialTimes::*ms) { return std::isfinite(this->*ms); });
}

StoredTrial ResultStore::loadFile(const std::filesystem::path& path)
{
  requireRegularFile(path);
  std::ifstream in(path);
  if (!in)
    throw IoError("cannot read '" + path.string() + "'");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    throw FormatError("'" + path.string() + "' is not a trial result: " + e.what());
  }
  const TrialFileReader r(path);
  if (!j.is_object())
    r.fail("(top level)", "expected an object, got " + j.dump().substr(0, 80));
  StoredTrial t;
  t.id = r.text(r.at(j, "", "id"), "id");
  t.has_fingerprint = j.contains("fingerprint");
  if (t.has_fingerprint)
    t.fingerprint = r.text(j["fingerprint"], "fingerprint");
  const json& spec = r.at(j, "", "spec");
  t.study = r.text(r.at(spec, "spec", "study"), "spec.study");
  t.variant = spec.contains("variant") ? r.text(spec["variant"], "spec.variant") : "";
  t.planner = r.text(r.at(spec, "spec", "planner"), "spec.planner");
  t.plant = r.text(r.at(spec, "spec", "plant"), "spec.plant");
  if (spec.contains("pattern") && !spec["pattern"].is_null())
    t.pattern = r.integer(spec["pattern"], "spec.pattern", 1, 4);
  t.yaw_deg = r.number(r.at(spec, "spec", "yaw_deg"), "spec.yaw_deg", -1e6, 1e6);
  if (spec.contains("repetition"))
    t.repetition = r.integer(spec["repetition"], "spec.repetition", 0,
                             std::numeric_limits<int>::max());
  const std::string status = r.text(r.at(j, "", "status"), "status");
  if (status != "done" && status != "failed")
    r.fail("status", "'" + status + "', expected done or failed");
  t.failed = status == "failed";
  if (t.failed) {
    t.error = j.contains("error") ? r.text(j["error"], "error") : "";
    return t;
  }
  const json& levels = r.at(j, "", "levels");
  if (!levels.is_array() || levels.empty())
    r.fail("levels", "expected a list of level names, got " + levels.dump());
  for (std::size_t l = 0; l < levels.size(); ++l)
    t.level_names.push_back(r.text(levels[l], "levels[" + std::to_string(l) + "]"));
  const json& views = r.at(j, "", "views");
  if (!views.is_array() || views.empty())
    r.fail("views", "expected the list of a done trial's views (at least one), got " +
                        views.dump().substr(0, 80));
  for (std::size_t v = 0; v < views.size(); ++v) {
    const std::string view = "views[" + std::to_string(v) + "]";
    const json& scores_of = r.at(views[v], view, "levels");
    std::vector<LevelScore> scores;
    for (const std::string& name : t.level_names) {
      const std::string level = view + ".levels." + name;
      const json& l = r.at(scores_of, view + ".levels", name);
      LevelScore s;
      s.precision = r.score(l, level, "precision", 1.0);
      s.recall = r.score(l, level, "recall", 1.0);
      s.f1 = r.score(l, level, "f1", 1.0);
      s.chamfer = r.score(l, level, "chamfer", kMaxStoredChamferM);
      scores.push_back(s);
    }
    t.views.push_back(std::move(scores));
    if (views[v].contains("organs")) {
      const std::string organs = view + ".organs";
      const json& per_organ = r.at(views[v], view, "organs");
      std::vector<double> recall;
      // An organ a file does not name was not measured when it was written (flower came
      // after the first files with organs): not measured, not an error.
      for (PartLabel organ : evaluatedOrgans())
        recall.push_back(per_organ.is_object() &&
                                 !per_organ.contains(partLabelName(organ))
                             ? std::numeric_limits<double>::quiet_NaN()
                             : r.score(per_organ, organs, partLabelName(organ), 1.0));
      t.organ_recall.push_back(std::move(recall));
    }
  }
  if (!t.organ_recall.empty() && t.organ_recall.size() != t.views.size())
    r.fail("views", "organ recall in some views and not in others");
  t.times.setup_ms = timeOf(j, "setup_ms");
  t.times.total_ms = timeOf(j, "total_ms");
  t.times.plan_ms = t.times.capture_ms = t.times.insert_ms = t.times.eval_ms = 0.0;
  for (const json& view : views) {
    t.times.plan_ms += timeOf(view, "plan_ms");
    t.times.capture_ms += timeOf(view, "capture_ms");
    t.times.insert_ms += timeOf(view, "insert_ms");
    t.times.eval_ms += timeOf(view, "eval_ms");
  }
  return t;
}

std::vector<StoredTrial> ResultStore::loadDone(const std::vector<TrialSpec>& specs) const
{
  std::vector<StoredTrial> trials;
  for (const TrialSpec& spec : specs)
    if (state(spec) == TrialState::done)
      trials.push_back(loadFile(resultPath(spec.id)));
  return trials;
}

std::vector<StoredTrial> ResultStore::load() const
{
  std::vector<StoredTrial> trials;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir_ / "trials", ec)) {
    if (isAtomicFileTemporary(entry.path()) || entry.path().extension() != ".json")
      continue;
    trials.push_back(loadFile(entry.path()));
  }
  if (ec)
    throw IoError("cannot list '" + (dir_ / "trials").string() + "': " + ec.message());
  std::sort(trials.begin(), trials.end(),
            [](const StoredTrial& a, const StoredTrial& b) { return a.id < b.id; });
  return trials;
}

std::vector<StoredTrial> ResultStore::load(const std::vector<TrialSpec>& specs) const
{
  std::map<std::string, const TrialSpec*> by_id;
  for (const TrialSpec& spec : specs)
    by_id[spec.id] = &spec;
  std::vector<StoredTrial> trials = load();
  for (const StoredTrial& t : trials) {
    const auto spec = by_id.find(t.id);
    const std::string file = "'" + resultPath(t.id).string() + "'";
    if (spec == by_id.end())
      throw FormatError(file + ": trial '" + t.id + "' is not one of the campaign in '" +
                        definitionPath().string() + "': remove it");
    if (!isTrialOf(t.fingerprint, t.has_fingerprint, *spec->second))
      throw FormatError(file + " is another campaign's result (fingerprint '" +
                        t.fingerprint + "', this campaign's trial has '" +
                        spec->second->fingerprint +
                        "'): remove it, or `plantnbv campaign run` runs the trial again");
  }
  return trials;
}

} // namespace plantnbv
