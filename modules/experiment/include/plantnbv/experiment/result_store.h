#pragma once
/// \file result_store.h
/// \brief The results of a campaign on disk, one JSON file per trial, written
/// atomically, so that an interrupted campaign resumes with nothing lost or duplicated.

#include <array>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <plantnbv/experiment/campaign.h>
#include <plantnbv/experiment/trial.h>

namespace plantnbv {

/// \brief A trial's result file: none (or unreadable), done, failed, or foreign: a
/// file of the trial's id whose fingerprint is another campaign's (run again).
enum class TrialState { missing, done, failed, foreign };

/// \brief Counts of a campaign's trials against its expansion.
struct StoreStatus {
  /// The trials of the expansion (total), and how many of them have a done result, a
  /// failed one, or none of this campaign (missing, `foreign` included).
  ///@{
  std::size_t total = 0, done = 0, failed = 0, missing = 0;
  ///@}
  std::size_t foreign = 0;                ///< of `missing`: files of another campaign
  std::vector<std::string> failed_ids;    ///< in expansion order
  std::vector<std::string> failed_errors; ///< their errors
  /// The done trials whose file gives their time (total_ms), and those times summed, in
  /// seconds: each trial's own time on one worker, whatever ran beside it.
  ///@{
  std::size_t timed = 0;
  double timed_s = 0.0;
  ///@}
};

/// \brief A trial's times as its file gives them, in milliseconds, each trial's own on
/// one worker: NaN where the file has none or a value that is not a time (a negative
/// or not finite number; a file is read for its scores, which its times do not change).
struct TrialTimes {
  double setup_ms = std::numeric_limits<double>::quiet_NaN(); ///< scene, ground truth
  /// The views' phases, summed over the views: planning, capture, insertion,
  /// evaluation.
  ///@{
  double plan_ms = std::numeric_limits<double>::quiet_NaN();
  double capture_ms = std::numeric_limits<double>::quiet_NaN();
  double insert_ms = std::numeric_limits<double>::quiet_NaN();
  double eval_ms = std::numeric_limits<double>::quiet_NaN();
  ///@}
  double total_ms = std::numeric_limits<double>::quiet_NaN(); ///< the whole trial
  /// \brief Whether the file gave every time.
  bool complete() const;
};

/// \brief TrialTimes' times, in order, for what is done to each of them.
inline constexpr std::array<double TrialTimes::*, 6> kTrialTimes = {
    &TrialTimes::setup_ms,  &TrialTimes::plan_ms, &TrialTimes::capture_ms,
    &TrialTimes::insert_ms, &TrialTimes::eval_ms, &TrialTimes::total_ms};

/// \brief A trial read back from its file (what the report needs).
struct StoredTrial {
  /// As TrialSpec's fields of the same names (`plant`: the plant's name).
  ///@{
  std::string id, study, variant, planner, plant;
  ///@}
  std::string fingerprint;              ///< TrialSpec::fingerprint it was run for
  bool has_fingerprint = false;         ///< false in files of release 0.1.0
  int pattern = 0;                      ///< predefined only, 1-4; 0 for other planners
  double yaw_deg = 0.0;                 ///< the plant's turn about its stem, degrees
  int repetition = 0;                   ///< 0, 1, ...
  bool failed = false;                  ///< the trial threw (its error is kept)
  std::string error;                    ///< the error message of a failed trial
  std::vector<std::string> level_names; ///< the evaluation levels, in order
  std::vector<std::vector<LevelScore>>
      views; ///< [view][level]; NaN where the file has null
  /// [view][organ] recall, organs as evaluatedOrgans(); NaN where the file has null;
  /// empty for files written before organ recall was recorded.
  std::vector<std::vector<double>> organ_recall;
  TrialTimes times; ///< of a done trial
};

/// \class ResultStore
/// \brief A campaign directory:
/// - DIR/campaign.yaml: a copy of the definition the trials were expanded from;
/// - DIR/campaign.json: its record, {"fingerprint": CampaignDefinition::
///   content_fingerprint}: a definition of another fingerprint is another campaign.
///   Release 0.1.0 wrote none: such a directory is taken over once its campaign.yaml
///   holds the same text, with "legacy_trials": true, and its trial files, which have
///   no fingerprint, stay its own (a file without one elsewhere is foreign);
/// - DIR/trials/<id with '/' replaced by '+'>.json: one file per finished trial, written
///   whole or not at all (AtomicFile: a temporary file ".<name>.tmp.*", ignored when
///   reading, renamed over the final name).
///
/// A trial file holds: id; fingerprint (TrialSpec::fingerprint); spec (study, variant,
/// planner, kind, attention, pattern, plant, simplified, yaw_deg, repetition, candidates,
/// resolution, views, seed); status
/// ("done" or "failed"); error (failed only); levels (names); views (per view: index,
/// pose [x, y, z, qx, qy, qz, qw], gain (null for v0), candidates, occupied_voxels, the
/// timings plan_ms, capture_ms, insert_ms, eval_ms, and per level precision, recall, f1,
/// chamfer, null when NaN; organs: recall per organ of evaluatedOrgans() by name, null
/// when NaN; older files have none); stopped_early, setup_ms, total_ms. Numbers are
/// written in their shortest round-trip form, so two runs give the same bytes apart from
/// the keys that end in "_ms". Thread-safe: trials may be written from several threads.

/// \brief The largest Chamfer distance a result file may hold (metres; a scene is a few
/// metres across).
constexpr double kMaxStoredChamferM = 1000.0;

class ResultStore {
public:
  /// \brief The store in directory `dir` (DIR); nothing is read or written yet.
  explicit ResultStore(std::filesystem::path dir);
  /// \brief DIR.
  const std::filesystem::path& dir() const { return dir_; }

  /// \brief Creates DIR and DIR/trials and writes DIR/campaign.yaml and campaign.json,
  /// or checks that the record there holds the same fingerprint (the copy of the
  /// definition is then kept as it is: comments and key order may differ). A directory
  /// without campaign.json (written before fingerprints) must hold the same text.
  /// \throws IoError if it cannot; InvalidArgumentError if DIR holds another campaign.
  void create(const std::string& definition_text, const std::string& fingerprint) const;
  /// \brief DIR/campaign.yaml's path.
  std::filesystem::path definitionPath() const { return dir_ / "campaign.yaml"; }
  /// \brief The file of a trial.
  std::filesystem::path resultPath(const std::string& id) const;

  /// \brief missing if there is no readable result file of spec.id; foreign if its
  /// fingerprint is not spec.fingerprint.
  TrialState state(const TrialSpec& spec) const;
  /// \brief Writes the trial's file with status "done" and its views (replacing any).
  /// \throws IoError if it cannot.
  void writeResult(const TrialSpec& spec, const TrialResult& result) const;
  /// \brief Writes the trial's file with status "failed" and `error` (replacing any).
  /// \throws IoError if it cannot.
  void writeFailure(const TrialSpec& spec, const std::string& error) const;
  /// \brief The state of each trial of `specs`, counted (state()), and the done
  /// trials' times (StoreStatus::timed_s), e.g. for an ETA.
  StoreStatus status(const std::vector<TrialSpec>& specs) const;

  /// \brief All result files of DIR/trials, sorted by id (temporary files of
  /// interrupted writes, ".name.tmp...", are not read).
  /// \throws FormatError naming the first file that loadFile refuses.
  std::vector<StoredTrial> load() const;
  /// \brief The same, each checked against the campaign's trials.
  /// \throws FormatError naming a file whose id is not among `specs` or whose
  /// fingerprint is not its trial's (another campaign's result: remove it, or `campaign
  /// run` replaces it), and as load().
  std::vector<StoredTrial> load(const std::vector<TrialSpec>& specs) const;
  /// \brief The done trials of `specs` (state() done: missing, failed and foreign files
  /// are left out), in the order of `specs`.
  /// \throws FormatError naming a done trial's file that loadFile refuses.
  std::vector<StoredTrial> loadDone(const std::vector<TrialSpec>& specs) const;
  /// \brief One result file, every field of the right type and every score possible:
  /// precision, recall and F1 in [0, 1], Chamfer in [0, kMaxStoredChamferM] metres (or
  /// null), at least one view in a done trial, a level per name.
  /// \throws IoError if it cannot be read; FormatError naming the file and the field.
  static StoredTrial loadFile(const std::filesystem::path& path);

private:
  /// True where trial files without a fingerprint (release 0.1.0's) are the campaign's
  /// own: DIR has no campaign.json yet, or its record says legacy_trials.
  bool acceptsTrialsWithoutFingerprint() const;
  /// state(spec), and for a done trial whose file has total_ms, that time in seconds
  /// (else NaN) into `*total_s`.
  TrialState readState(const TrialSpec& spec, double* total_s) const;
  bool isTrialOf(const std::string& file_fingerprint, bool has_fingerprint,
                 const TrialSpec& spec) const;
  std::filesystem::path dir_;
};

} // namespace plantnbv
