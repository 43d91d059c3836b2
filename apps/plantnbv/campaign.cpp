// plantnbv campaign: many trials from one YAML file (the paper's study, or a variant),
// run on all cores, resumable, with statistics at the end.
//   campaign run FILE -o DIR [-j N]     run the trials not done yet
//   campaign run-chunk FILE -o DIR --chunk I --chunks N   one chunk (array jobs)
//   campaign run-chunk FILE -o DIR --task-file F --task I  one task of `submit`
//   campaign submit FILE -o DIR [...]   the missing trials as a Slurm job array
//   campaign status DIR [-j N] [--timing]  count done, failed and missing trials; the
//                                       ETA; where the done trials' time goes
//   campaign report DIR [-o OUT]        curves.csv, summary.md and PNG figures

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
#include <thread>
#include <unistd.h>

#include <CLI/CLI.hpp>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/campaign.h>
#include <plantnbv/experiment/campaign_report.h>
#include <plantnbv/experiment/campaign_runner.h>
#include <plantnbv/experiment/result_store.h>
#include <plantnbv/experiment/trial.h>
#include <plantnbv/scenario/campaign_figures.h>
#include <plantnbv/scenario/campaign_file.h>

#include "campaign_submit.h"
#include "cli_checks.h"
#include "commands.h"

namespace plantnbv {
namespace app {

namespace {

namespace fs = std::filesystem;

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

/// ", ETA 4:10" while trials are left to run ("?" before the first has run), else "".
std::string etaText(const CampaignProgress& p)
{
  if (p.stopping || p.to_run <= p.ran)
    return "";
  if (p.ran == 0)
    return ", ETA ?";
  // Trials run at `workers` at a time; the rate so far includes that.
  return ", ETA " + clockText(p.elapsed_s / double(p.ran) * double(p.to_run - p.ran));
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
  return line + etaText(p);
}

struct RunOptions {
  std::string file;
  std::string output_dir;
  int workers = 0;
  int chunk = -1;
  int chunks = 0;
  bool chunked = false;  ///< run-chunk --chunk/--chunks given (checked by campaignChunk)
  std::string task_file; ///< run-chunk: one task of a `submit` task file
  int task = -1;
  std::string base_dir; ///< relative paths of the file are read from here if set
};

void runCampaign(const RunOptions& o)
{
  scenario::CampaignFile f = scenario::loadCampaignFile(o.file);
  if (!o.base_dir.empty())
    f.base_dir = o.base_dir;
  const ResultStore store(o.output_dir);
  store.create(f.text, f.definition.content_fingerprint);
  std::vector<TrialSpec> specs = expandCampaign(f.definition);
  const std::size_t all = specs.size();
  std::size_t tasks = 0;
  if (!o.task_file.empty()) {
    ArrayTaskTrials task = arrayTaskTrials(specs, o.task_file, o.task);
    specs = std::move(task.trials);
    tasks = task.tasks;
  } else if (o.chunked) {
    specs = campaignChunk(specs, o.chunk, o.chunks);
  }

  // The trials of one plant and pose one after another: they share its scene.
  scenario::groupTrialsByScene(specs);
  LocalRunner runner(store, scenario::campaignTrialFunction(f), o.workers);
  const bool tty = ::isatty(STDOUT_FILENO) != 0;
  bool stop_announced = false;
  runner.setProgressCallback([&](const CampaignProgress& p) {
    if (p.event == CampaignProgress::Event::started) {
      std::cout << "campaign '" << f.definition.name << "': " << all << " trials";
      if (!o.task_file.empty())
        std::cout << "; array task " << o.task << " of " << tasks << ": " << p.total
                  << " trials";
      else if (o.chunked)
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
      // A log (nohup, Slurm): one line a trial, with the totals a terminal's bar shows.
      std::cout << "[" << p.skipped + p.ran << "/" << p.total << "] " << p.id
                << (p.trial_failed ? " failed: " + p.error : std::string(" done"))
                << " in " << std::fixed << std::setprecision(1) << p.trial_s
                << std::defaultfloat << " s; " << p.failed << " failed, "
                << clockText(p.elapsed_s) << " elapsed" << etaText(p) << std::endl;
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

/// The ETA of the trials still to run (missing and failed) from the done trials' own
/// times, by etaText's rule, as if `workers` ran them (0: all cores, as `campaign run`):
/// ", ETA 4:10 at 2 trials at a time (a trial took 1.4 s on average)"; "" when none is
/// left.
std::string statusEtaText(const StoreStatus& s, int workers)
{
  const std::size_t left = s.missing + s.failed;
  if (workers <= 0)
    workers = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const std::size_t at_once =
      std::max<std::size_t>(1, std::min<std::size_t>(workers, left));
  CampaignProgress p;
  p.ran = s.timed;
  p.to_run = s.timed + left;
  p.elapsed_s = s.timed_s / double(at_once); // the timed trials, run `at_once` at a time
  const std::string eta = etaText(p);
  if (eta.empty() || s.timed == 0)
    return eta;
  std::ostringstream text;
  text << eta << " at " << at_once << " trial" << (at_once == 1 ? "" : "s")
       << " at a time (a trial took " << std::fixed << std::setprecision(1)
       << s.timed_s / double(s.timed) << " s on average)";
  return text.str();
}

/// The done trials' mean times per study variant's planner, as a Markdown table.
void printTiming(const std::vector<TimingRow>& rows, std::ostream& out)
{
  std::size_t timed = 0;
  for (const TimingRow& r : rows)
    timed += r.trials;
  if (timed == 0) {
    out << "no done trial gives its times yet\n";
    return;
  }
  out << "where the time goes (" << timed << " done trial" << (timed == 1 ? "" : "s")
      << "; mean ms a trial, each on one worker):\n"
      << "| study | variant | planner | trials | setup | plan | capture | insert | "
         "evaluate | total | share |\n"
      << "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n"
      << std::fixed;
  for (const TimingRow& r : rows)
    out << "| " << r.study << " | " << r.variant << " | " << r.planner << " | "
        << r.trials << std::setprecision(0) << " | " << r.mean.setup_ms << " | "
        << r.mean.plan_ms << " | " << r.mean.capture_ms << " | " << r.mean.insert_ms
        << " | " << r.mean.eval_ms << " | " << r.mean.total_ms << " | "
        << std::setprecision(1) << 100.0 * r.share << " % |\n";
}

void statusCampaign(const std::string& dir, int workers, bool timing)
{
  scenario::CampaignFile f;
  const StoreStatus s = scenario::campaignDirectoryStatus(dir, &f);
  std::cout << "campaign '" << f.definition.name << "': " << s.total << " trials, "
            << s.done << " done, " << s.failed << " failed, " << s.missing << " missing";
  if (s.foreign)
    std::cout << " (" << s.foreign << " of them files of another campaign, run again)";
  std::cout << statusEtaText(s, workers) << "\n";
  const std::size_t shown = std::min<std::size_t>(s.failed_ids.size(), 20);
  for (std::size_t i = 0; i < shown; ++i)
    std::cout << "failed: " << s.failed_ids[i] << ": " << s.failed_errors[i] << "\n";
  if (shown < s.failed_ids.size())
    std::cout << "... and " << s.failed_ids.size() - shown << " more failed\n";
  printSlurmSubmissions(dir, std::cout);
  if (timing)
    printTiming(scenario::campaignDirectoryTiming(dir), std::cout);
}

void reportCampaign(const std::string& dir, std::string out, bool figures)
{
  if (figures)
    requireDisplayOrReexec();
  if (out.empty())
    out = (fs::path(dir) / "report").string();
  const scenario::CampaignReportFiles r =
      scenario::writeCampaignReportFiles(dir, out, figures);
  std::cout << r.trials - r.failed << " trials done, " << r.failed << " failed";
  if (r.missing)
    std::cout << ", " << r.missing << " of " << r.total << " still missing";
  std::cout << "; wrote " << r.written[0].string() << " and summary.md";
  for (std::size_t i = 2; i < r.written.size(); ++i)
    std::cout << ", " << r.written[i].filename().string();
  std::cout << "\n";
}

} // namespace

void addCampaignCommand(CLI::App& app)
{
  CLI::App* cmd = app.add_subcommand(
      "campaign", "Run many trials from a campaign file (resumable, on all cores or as a "
                  "Slurm job array), count them, and report their statistics");
  cmd->require_subcommand(1);

  auto run = std::make_shared<RunOptions>();
  CLI::App* r = cmd->add_subcommand("run", "Run the campaign's trials that are not done "
                                           "yet (Ctrl-C stops; run again to resume)");
  r->add_option("file", run->file, "Campaign file (YAML, e.g. data/campaigns/quick.yaml)")
      ->required();
  r->add_option("-o,--output", run->output_dir, "Campaign directory")->required();
  r->add_option("-j,--jobs", run->workers, "Trials at a time (default: all cores)")
      ->check(workerCount("trials at a time"));
  r->callback([run]() { runCampaign(*run); });

  auto chunk = std::make_shared<RunOptions>();
  CLI::App* c = cmd->add_subcommand(
      "run-chunk",
      "Run one chunk of the trials (every N-th from the I-th), or one task of a task "
      "file that `submit` wrote, e.g. one task of an array job");
  c->add_option("file", chunk->file, "Campaign file (YAML)")->required();
  c->add_option("-o,--output", chunk->output_dir, "Campaign directory")->required();
  CLI::Option* chunk_index =
      c->add_option("--chunk", chunk->chunk, "Chunk index, 0 to N-1");
  CLI::Option* chunk_count =
      c->add_option("--chunks", chunk->chunks, "Number of chunks N");
  CLI::Option* task_file =
      c->add_option("--task-file", chunk->task_file, "Task file written by `submit`");
  CLI::Option* task_index =
      c->add_option("--task", chunk->task, "Task of the task file, 0 to T-1");
  chunk_index->needs(chunk_count);
  chunk_count->needs(chunk_index);
  task_file->needs(task_index)->excludes(chunk_index)->excludes(chunk_count);
  task_index->needs(task_file);
  c->add_option(
      "--base-dir", chunk->base_dir,
      "Directory the file's relative paths are read from (default: the file's)");
  c->add_option("-j,--jobs", chunk->workers, "Trials at a time (default: all cores)")
      ->check(workerCount("trials at a time"));
  c->callback([chunk, chunk_index, task_file]() {
    if (chunk_index->count() == 0 && task_file->count() == 0)
      throw CLI::RequiredError("give --chunk and --chunks, or --task-file and --task",
                               CLI::ExitCodes::RequiredError);
    chunk->chunked = chunk_index->count() > 0;
    runCampaign(*chunk);
  });

  addCampaignSubmitCommand(*cmd);

  auto status_dir = std::make_shared<std::string>();
  auto status_jobs = std::make_shared<int>(0);
  CLI::App* s = cmd->add_subcommand(
      "status", "Count done, failed and missing trials, with the ETA of those left");
  s->add_option("dir", *status_dir, "Campaign directory")->required();
  s->add_option("-j,--jobs", *status_jobs,
                "Trials at a time the ETA assumes (default: all cores, as `run`)")
      ->check(workerCount("trials at a time"));
  auto status_timing = std::make_shared<bool>(false);
  s->add_flag("--timing", *status_timing,
              "Also the done trials' mean times (setup, plan, capture, insert, evaluate, "
              "total) per study variant's planner");
  s->callback([status_dir, status_jobs, status_timing]() {
    statusCampaign(*status_dir, *status_jobs, *status_timing);
  });

  auto report_dir = std::make_shared<std::string>();
  auto report_out = std::make_shared<std::string>();
  CLI::App* p = cmd->add_subcommand("report", "Write curves.csv (mean, sd, n, 95% CI per "
                                              "view), summary.md and the PNG figures");
  p->add_option("dir", *report_dir, "Campaign directory")->required();
  p->add_option("-o,--output", *report_out, "Report directory (default: DIR/report)");
  auto no_figures = std::make_shared<bool>(false);
  p->add_flag(
      "--no-figures", *no_figures,
      "Skip the PNG figures (they need an X display; without one the tool re-runs "
      "itself under xvfb-run)");
  p->callback([report_dir, report_out, no_figures]() {
    reportCampaign(*report_dir, *report_out, !*no_figures);
  });
}

} // namespace app
} // namespace plantnbv
