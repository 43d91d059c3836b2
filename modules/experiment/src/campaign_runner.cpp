#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>

#include <plantnbv/common/error.h>
#include <plantnbv/common/stopwatch.h>
#include <plantnbv/experiment/campaign_runner.h>

namespace plantnbv {

LocalRunner::LocalRunner(const ResultStore& store, TrialFunction run_trial, int workers)
    : store_(store), run_trial_(std::move(run_trial)), workers_(workers)
{
  if (workers_ < 0)
    throw InvalidArgumentError("workers: " + std::to_string(workers_) +
                               ", expected >= 0");
  if (workers_ == 0)
    workers_ = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

CampaignProgress LocalRunner::run(const std::vector<TrialSpec>& specs)
{
  const Stopwatch clock;
  CampaignProgress progress;
  progress.total = specs.size();
  progress.workers = workers_;
  std::deque<const TrialSpec*> queue;
  for (const TrialSpec& spec : specs)
    if (store_.state(spec) == TrialState::done)
      ++progress.skipped;
    else
      queue.push_back(&spec);
  progress.to_run = queue.size();
  if (progress_)
    progress_(progress);

  std::mutex mutex;
  std::condition_variable changed;
  std::deque<CampaignProgress> finished; // events for the calling thread
  std::size_t running = 0;
  // Started from a constant: a worker that finishes before the next one starts lowers
  // active_workers, which as the loop's bound would leave that one unstarted and the
  // count above 0 for ever.
  const int worker_count = std::min<int>(workers_, static_cast<int>(queue.size()));
  int active_workers = worker_count;
  std::atomic<bool> aborted{false}; // the progress callback threw
  auto stopping = [this, &aborted] { return aborted || (stop_ && stop_->load()); };

  auto work = [&] {
    for (;;) {
      const TrialSpec* spec = nullptr;
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (queue.empty() || stopping())
          break;
        spec = queue.front();
        queue.pop_front();
        ++running;
      }
      const Stopwatch trial_clock;
      CampaignProgress event;
      event.event = CampaignProgress::Event::finished;
      event.id = spec->id;
      try {
        TrialResult result;
        run_trial_(*spec, result);
        store_.writeResult(*spec, result);
      } catch (const std::exception& e) {
        event.trial_failed = true;
        event.error = e.what();
        try {
          store_.writeFailure(*spec, e.what());
        } catch (const std::exception& e2) {
          event.error +=
              std::string(" (and its failure could not be stored: ") + e2.what() + ")";
        }
      }
      event.trial_s = trial_clock.ms() / 1000.0;
      {
        std::lock_guard<std::mutex> lock(mutex);
        --running;
        finished.push_back(std::move(event));
      }
      changed.notify_all();
    }
    {
      std::lock_guard<std::mutex> lock(mutex);
      --active_workers;
    }
    changed.notify_all();
  };

  std::vector<std::thread> threads;
  for (int i = 0; i < worker_count; ++i)
    threads.emplace_back(work);

  // The callback runs here, never on the workers; if it throws, the workers finish their
  // trials, then the exception goes on.
  std::exception_ptr callback_error;
  auto notify = [&](const CampaignProgress& p) {
    if (!progress_ || callback_error)
      return;
    try {
      progress_(p);
    } catch (...) {
      callback_error = std::current_exception();
      aborted = true;
    }
  };
  std::unique_lock<std::mutex> lock(mutex);
  for (;;) {
    changed.wait_for(lock, std::chrono::seconds(1));
    std::deque<CampaignProgress> events;
    events.swap(finished);
    const bool done = active_workers == 0;
    const std::size_t now_running = running;
    lock.unlock();
    for (CampaignProgress& e : events) {
      ++progress.ran;
      progress.failed += e.trial_failed ? 1 : 0;
      progress.event = CampaignProgress::Event::finished;
      progress.id = std::move(e.id);
      progress.trial_failed = e.trial_failed;
      progress.error = std::move(e.error);
      progress.trial_s = e.trial_s;
      progress.running = now_running;
      progress.elapsed_s = clock.ms() / 1000.0;
      progress.stopping = stopping();
      notify(progress);
    }
    if (done) {
      lock.lock();
      break;
    }
    if (events.empty()) {
      progress.event = CampaignProgress::Event::tick;
      progress.running = now_running;
      progress.elapsed_s = clock.ms() / 1000.0;
      progress.stopping = stopping();
      notify(progress);
    }
    lock.lock();
  }
  lock.unlock();
  for (std::thread& t : threads)
    t.join();
  progress.running = 0;
  progress.elapsed_s = clock.ms() / 1000.0;
  progress.stopping = stopping();
  if (callback_error)
    std::rethrow_exception(callback_error);
  return progress;
}

std::vector<TrialSpec> campaignChunk(const std::vector<TrialSpec>& specs, int chunk,
                                     int chunks)
{
  if (chunks < 1 || chunk < 0 || chunk >= chunks)
    throw InvalidArgumentError("chunk " + std::to_string(chunk) + " of " +
                               std::to_string(chunks) + ": expected 0 <= chunk < chunks");
  std::vector<TrialSpec> out;
  for (std::size_t i = static_cast<std::size_t>(chunk); i < specs.size();
       i += static_cast<std::size_t>(chunks))
    out.push_back(specs[i]);
  return out;
}

} // namespace plantnbv
