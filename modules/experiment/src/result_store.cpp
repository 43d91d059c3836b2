#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <thread>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/result_store.h>

namespace plantnbv {

namespace {

using nlohmann::json;

/// The shortest text that reads back to the same double (std::to_chars); null for NaN
/// and infinities (JSON has none).
std::string number(double x)
{
  if (!std::isfinite(x))
    return "null";
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof(buffer), x).ptr;
  return std::string(buffer, end);
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

double numberOrNan(const json& j)
{
  return j.is_number() ? j.get<double>() : std::numeric_limits<double>::quiet_NaN();
}

} // namespace

ResultStore::ResultStore(std::filesystem::path dir) : dir_(std::move(dir)) {}

std::filesystem::path ResultStore::resultPath(const std::string& id) const
{
  return dir_ / "trials" / fileName(id);
}

void ResultStore::create(const std::string& definition_text) const
{
  std::error_code ec;
  std::filesystem::create_directories(dir_ / "trials", ec);
  if (ec)
    throw IoError("cannot create campaign directory '" + dir_.string() +
                  "': " + ec.message());
  const std::filesystem::path path = definitionPath();
  if (std::filesystem::exists(path)) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    if (text.str() != definition_text)
      throw InvalidArgumentError(
          "'" + dir_.string() +
          "' holds another campaign (its campaign.yaml differs from "
          "this definition): give another output directory");
    return;
  }
  writeAtomically(path, definition_text);
}

void ResultStore::writeAtomically(const std::filesystem::path& path,
                                  const std::string& text) const
{
  std::ostringstream tmp_name;
  tmp_name << "." << path.filename().string() << ".tmp." << ::getpid() << "."
           << std::hash<std::thread::id>()(std::this_thread::get_id());
  const std::filesystem::path tmp = path.parent_path() / tmp_name.str();
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f)
    throw IoError("cannot write '" + tmp.string() + "'");
  const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size() &&
                       std::fflush(f) == 0 && ::fsync(::fileno(f)) == 0;
  if (std::fclose(f) != 0 || !written) {
    std::remove(tmp.c_str());
    throw IoError("cannot write '" + tmp.string() + "'");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw IoError("cannot rename '" + tmp.string() + "' to '" + path.string() + "'");
  }
}

void ResultStore::writeResult(const TrialSpec& spec, const TrialResult& r) const
{
  nlohmann::ordered_json j;
  j["id"] = spec.id;
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
    views.push_back(v);
  }
  j["views"] = views;
  j["stopped_early"] = r.stopped_early;
  j["setup_ms"] = r.setup_ms;
  j["total_ms"] = r.total_ms;
  writeAtomically(resultPath(spec.id), dumpOrdered(j));
}

void ResultStore::writeFailure(const TrialSpec& spec, const std::string& error) const
{
  nlohmann::ordered_json j;
  j["id"] = spec.id;
  j["spec"] = specJson(spec);
  j["status"] = "failed";
  j["error"] = error;
  writeAtomically(resultPath(spec.id), dumpOrdered(j));
}

TrialState ResultStore::state(const std::string& id) const
{
  std::ifstream in(resultPath(id));
  if (!in)
    return TrialState::missing;
  try {
    const json j = json::parse(in);
    const std::string status = j.at("status").get<std::string>();
    if (j.at("id").get<std::string>() != id)
      return TrialState::missing;
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
    switch (state(spec.id)) {
    case TrialState::done:
      ++s.done;
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
    case TrialState::missing:
      ++s.missing;
      break;
    }
  }
  return s;
}

StoredTrial ResultStore::loadFile(const std::filesystem::path& path)
{
  std::ifstream in(path);
  if (!in)
    throw IoError("cannot read '" + path.string() + "'");
  try {
    const json j = json::parse(in);
    StoredTrial t;
    t.id = j.at("id").get<std::string>();
    const json& spec = j.at("spec");
    t.study = spec.at("study").get<std::string>();
    t.variant = spec.value("variant", std::string());
    t.planner = spec.at("planner").get<std::string>();
    t.plant = spec.at("plant").get<std::string>();
    t.pattern = spec.contains("pattern") && spec["pattern"].is_number()
                    ? spec["pattern"].get<int>()
                    : 0;
    t.yaw_deg = spec.at("yaw_deg").get<double>();
    t.repetition = spec.value("repetition", 0);
    const std::string status = j.at("status").get<std::string>();
    if (status != "done" && status != "failed")
      throw FormatError("'" + path.string() + "': status '" + status +
                        "', expected done or failed");
    t.failed = status == "failed";
    if (t.failed) {
      t.error = j.value("error", std::string());
      return t;
    }
    t.level_names = j.at("levels").get<std::vector<std::string>>();
    for (const json& v : j.at("views")) {
      std::vector<LevelScore> scores;
      const json& levels = v.at("levels");
      for (const std::string& name : t.level_names) {
        LevelScore s;
        const double nan = std::numeric_limits<double>::quiet_NaN();
        s.precision = s.recall = s.f1 = s.chamfer = nan;
        if (levels.contains(name)) {
          const json& l = levels[name];
          s.precision = numberOrNan(l.value("precision", json()));
          s.recall = numberOrNan(l.value("recall", json()));
          s.f1 = numberOrNan(l.value("f1", json()));
          s.chamfer = numberOrNan(l.value("chamfer", json()));
        }
        scores.push_back(s);
      }
      t.views.push_back(std::move(scores));
    }
    return t;
  } catch (const json::exception& e) {
    throw FormatError("'" + path.string() + "' is not a trial result: " + e.what());
  }
}

std::vector<StoredTrial> ResultStore::load() const
{
  std::vector<StoredTrial> trials;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir_ / "trials", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || name[0] == '.' || entry.path().extension() != ".json")
      continue; // temporary files of interrupted writes
    try {
      trials.push_back(loadFile(entry.path()));
    } catch (const Error&) {
    }
  }
  if (ec)
    throw IoError("cannot list '" + (dir_ / "trials").string() + "': " + ec.message());
  std::sort(trials.begin(), trials.end(),
            [](const StoredTrial& a, const StoredTrial& b) { return a.id < b.id; });
  return trials;
}

} // namespace plantnbv
