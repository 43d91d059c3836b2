#pragma once
/// \file campaign_runner.h
/// \brief Runs a campaign's trials on a pool of worker threads, one trial per worker at
/// a time, skipping those already done, and stores each result as it finishes.

#include <atomic>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <plantnbv/experiment/campaign.h>
#include <plantnbv/experiment/result_store.h>
#include <plantnbv/experiment/trial.h>

namespace plantnbv {

/// \brief Where a run stands; passed to the progress callback.
struct CampaignProgress {
  /// \brief Why the callback is called.
  enum class Event {
    started,  ///< once, before the first trial
    finished, ///< a trial finished (done or failed): see id, trial_failed, error
    tick,     ///< about once a second while trials run
  };
  Event event = Event::started; ///< why this call
  std::size_t total = 0;        ///< trials of the run (its chunk)
  std::size_t skipped = 0;      ///< already done before the run
  std::size_t to_run = 0;       ///< total - skipped
  std::size_t ran = 0;          ///< finished in this run (done or failed)
  std::size_t failed = 0;       ///< failed in this run
  std::size_t running = 0;      ///< trials on the workers now
  int workers = 0;              ///< worker threads of the run
  double elapsed_s = 0.0;       ///< since the run started
  bool stopping = false;        ///< the stop flag was seen: no new trials are started
  // Event::finished only: the trial that just finished.
  std::string id;            ///< finished only: the trial's id
  bool trial_failed = false; ///< finished only: whether it failed
  std::string error;         ///< finished only: its error if it failed
  double trial_s = 0.0;      ///< finished only: its run time, seconds
};

/// \brief A local executor: N worker threads take the next trial that is not done, run
/// it through a TrialFunction (which sets up the plant, ROIs and levels, then runs a
/// Trial with TrialConfig::threads = 1) and write its result, or its error, to the
/// ResultStore. A trial that throws is stored as failed and the others go on.
/// Trials already done in the store are skipped (failed ones are run again).
class LocalRunner {
public:
  /// \brief Runs one trial of the campaign into its result; throws if it fails.
  using TrialFunction = std::function<void(const TrialSpec&, TrialResult&)>;
  /// \brief Receives the progress (see setProgressCallback).
  using ProgressCallback = std::function<void(const CampaignProgress&)>;

  /// \param[in] workers threads; 0: std::thread::hardware_concurrency().
  LocalRunner(const ResultStore& store, TrialFunction run_trial, int workers = 0);

  /// \brief Called on the thread that calls run(): once at the start, after every
  /// finished trial and about once a second (tick) in between. If it throws, no new
  /// trial is started and run() rethrows once the running trials have finished.
  void setProgressCallback(ProgressCallback callback) { progress_ = std::move(callback); }
  /// \brief When *stop becomes true, no new trial is started; run() returns when the
  /// running ones have finished. E.g. set from a SIGINT handler.
  void setStopFlag(const std::atomic<bool>* stop) { stop_ = stop; }

  /// \brief Runs the trials of `specs` that are not done. Returns the last progress.
  CampaignProgress run(const std::vector<TrialSpec>& specs);

  /// \brief The worker threads (hardware_concurrency() when 0 was given).
  int workers() const { return workers_; }

private:
  const ResultStore& store_;
  TrialFunction run_trial_;
  int workers_;
  ProgressCallback progress_;
  const std::atomic<bool>* stop_ = nullptr;
};

/// \brief Chunk `chunk` (0-based) of `chunks` of the trial list: every chunks-th trial
/// from the chunk-th on, so that every chunk gets a share of every study (for array
/// jobs). \throws InvalidArgumentError unless 0 <= chunk < chunks.
std::vector<TrialSpec> campaignChunk(const std::vector<TrialSpec>& specs, int chunk,
                                     int chunks);

} // namespace plantnbv
