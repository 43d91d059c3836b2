#pragma once
/// \file result_store.h
/// \brief The results of a campaign on disk, one JSON file per trial, written
/// atomically, so that an interrupted campaign resumes with nothing lost or duplicated.

#include <filesystem>
#include <string>
#include <vector>

#include <plantnbv/experiment/campaign.h>
#include <plantnbv/experiment/trial.h>

namespace plantnbv {

enum class TrialState { missing, done, failed };

/// \brief Counts of a campaign's trials against its expansion.
struct StoreStatus {
  std::size_t total = 0, done = 0, failed = 0, missing = 0;
  std::vector<std::string> failed_ids;    ///< in expansion order
  std::vector<std::string> failed_errors; ///< their errors
};

/// \brief A trial read back from its file (what the report needs).
struct StoredTrial {
  std::string id, study, variant, planner, plant;
  int pattern = 0;
  double yaw_deg = 0.0;
  int repetition = 0;
  bool failed = false;
  std::string error;
  std::vector<std::string> level_names;
  std::vector<std::vector<LevelScore>>
      views; ///< [view][level]; NaN where the file has null
};

/// \brief A campaign directory:
/// - DIR/campaign.yaml: a copy of the definition the trials were expanded from;
/// - DIR/trials/<id with '/' replaced by '+'>.json: one file per finished trial, written
///   to a temporary file (".<name>.tmp.<pid>.<thread>", ignored when reading) in the
///   same directory, flushed to disk, then renamed over the final name.
///
/// A trial file holds: id; spec (study, variant, planner, kind, attention, pattern,
/// plant, simplified, yaw_deg, repetition, candidates, resolution, views, seed); status
/// ("done" or "failed"); error (failed only); levels (names); views (per view: index,
/// pose [x, y, z, qx, qy, qz, qw], gain (null for v0), candidates, occupied_voxels, the
/// timings plan_ms, capture_ms, insert_ms, eval_ms, and per level precision, recall, f1,
/// chamfer, null when NaN); stopped_early, setup_ms, total_ms. Numbers are written in
/// their shortest round-trip form, so two runs give the same bytes apart from the keys
/// that end in "_ms". Thread-safe: trials may be written from several threads.
class ResultStore {
public:
  explicit ResultStore(std::filesystem::path dir);
  const std::filesystem::path& dir() const { return dir_; }

  /// \brief Creates DIR and DIR/trials and writes DIR/campaign.yaml, or checks that the
  /// one there holds the same text. \throws IoError if it cannot; InvalidArgumentError
  /// if DIR holds another campaign.
  void create(const std::string& definition_text) const;
  /// \brief DIR/campaign.yaml's path.
  std::filesystem::path definitionPath() const { return dir_ / "campaign.yaml"; }
  /// \brief The file of a trial.
  std::filesystem::path resultPath(const std::string& id) const;

  /// \brief missing if there is no readable result file for the id.
  TrialState state(const std::string& id) const;
  void writeResult(const TrialSpec& spec, const TrialResult& result) const;
  void writeFailure(const TrialSpec& spec, const std::string& error) const;
  StoreStatus status(const std::vector<TrialSpec>& specs) const;

  /// \brief All result files of DIR/trials, sorted by id. Unreadable files are skipped.
  std::vector<StoredTrial> load() const;
  /// \brief One result file. \throws FormatError if it is not a trial result.
  static StoredTrial loadFile(const std::filesystem::path& path);

private:
  void writeAtomically(const std::filesystem::path& path, const std::string& text) const;
  std::filesystem::path dir_;
};

} // namespace plantnbv
