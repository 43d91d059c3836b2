// plantnbv campaign submit FILE -o DIR: the trials of the campaign that are not done
// (missing or failed) as a Slurm job array, K trials per array task. Writes
// DIR/slurm/submit-<UTC time>/{tasks.txt, job.sbatch}, runs `sbatch --parsable` and
// records the job id there (job_id), for `campaign status`.

#include "campaign_submit.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>

#include <plantnbv/common/error.h>
#include <plantnbv/common/file_io.h>
#include <plantnbv/experiment/campaign.h>
#include <plantnbv/experiment/result_store.h>
#include <plantnbv/experiment/slurm_array.h>
#include <plantnbv/scenario/campaign_file.h>

namespace plantnbv {
namespace app {

namespace {

namespace fs = std::filesystem;

constexpr const char* kTaskFileName = "tasks.txt";
constexpr const char* kScriptName = "job.sbatch";
constexpr const char* kJobIdFileName = "job_id";

struct SubmitOptions {
  std::string file;
  std::string output_dir;
  std::string partition;
  std::string time_limit;
  int trials_per_task = 10;
  int max_parallel = 0; // 0: no limit
  bool max_parallel_given = false;
  bool dry_run = false;
};

/// An absolute, normalized path without a trailing '/'.
fs::path absolutePath(const std::string& path)
{
  fs::path p = fs::absolute(path).lexically_normal();
  if (!p.has_filename() && p.has_parent_path() && p != p.root_path())
    p = p.parent_path();
  return p;
}

std::string readText(const fs::path& path)
{
  std::ifstream in(path);
  if (!in)
    throw IoError("cannot read '" + path.string() + "'");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool onPath(const std::string& program)
{
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':'))
    if (!dir.empty() && ::access((fs::path(dir) / program).c_str(), X_OK) == 0)
      return true;
  return false;
}

struct CommandResult {
  int exit_code = -1;
  std::string out;
};

/// Runs `command` through the shell; stdout is returned, stderr goes where the command
/// line sends it.
CommandResult runCommand(const std::string& command)
{
  CommandResult r;
  std::FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe)
    return r;
  std::array<char, 4096> buffer;
  std::size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    r.out.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// The most telling line of a command's error output: its last non-empty one.
std::string lastLine(const std::string& text)
{
  std::istringstream lines(text);
  std::string line, last;
  while (std::getline(lines, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos)
      last = line;
  return last;
}

/// The array tasks of job `job_id` still in the queue. A job squeue no longer knows
/// ("Invalid job id": ended and purged) has none; any other failure (no controller)
/// leaves the counts unknown, with squeue's message in `error`.
std::optional<SlurmQueueCounts> queuedTasks(const std::string& job_id, std::string& error)
{
  const CommandResult r = runCommand("squeue -h -r -o %T -j " + job_id + " 2>&1");
  if (r.exit_code == 0)
    return countQueueStates(r.out);
  if (r.out.find("Invalid job id") != std::string::npos)
    return SlurmQueueCounts{};
  error = lastLine(r.out);
  return std::nullopt;
}

/// A submission recorded under DIR/slurm.
struct Submission {
  fs::path dir;
  std::string job_id; ///< empty: not submitted (--dry-run, or sbatch failed)
  std::size_t tasks = 0, trials = 0;
};

std::vector<Submission> recordedSubmissions(const fs::path& campaign_dir)
{
  std::vector<Submission> out;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(campaign_dir / "slurm", ec)) {
    if (!entry.is_directory() ||
        entry.path().filename().string().rfind("submit-", 0) != 0)
      continue;
    Submission s;
    s.dir = entry.path();
    try {
      const auto tasks = parseTaskFile(readText(s.dir / kTaskFileName),
                                       (s.dir / kTaskFileName).string());
      s.tasks = tasks.size();
      for (const auto& t : tasks)
        s.trials += t.size();
    } catch (const Error&) {
    }
    std::ifstream job(s.dir / kJobIdFileName);
    std::string id;
    if (job >> id && !id.empty() &&
        std::all_of(id.begin(), id.end(), [](char c) { return c >= '0' && c <= '9'; }))
      s.job_id = id;
    out.push_back(s);
  }
  std::sort(out.begin(), out.end(),
            [](const Submission& a, const Submission& b) { return a.dir < b.dir; });
  return out;
}

/// DIR/slurm/submit-<UTC time>[-N], created; a second submit in the same second gets -2.
fs::path newSubmitDir(const fs::path& campaign_dir)
{
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  ::gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof(stamp), "%Y%m%dT%H%M%SZ", &utc);
  const fs::path slurm = campaign_dir / "slurm";
  std::error_code ec;
  fs::create_directories(slurm, ec);
  if (ec)
    throw IoError("cannot create '" + slurm.string() + "': " + ec.message());
  for (int n = 1; n < 1000; ++n) {
    const fs::path dir =
        slurm / ("submit-" + std::string(stamp) + (n > 1 ? "-" + std::to_string(n) : ""));
    if (fs::create_directory(dir, ec))
      return dir;
    if (ec)
      throw IoError("cannot create '" + dir.string() + "': " + ec.message());
  }
  throw IoError("cannot create a new submit directory in '" + slurm.string() + "'");
}

void submitCampaign(const SubmitOptions& o)
{
  // Options first: nothing is written for a bad one.
  if (o.trials_per_task < 1)
    throw InvalidArgumentError("--trials-per-task " + std::to_string(o.trials_per_task) +
                               ": expected >= 1");
  if (o.max_parallel_given && o.max_parallel < 1)
    throw InvalidArgumentError("--max-parallel " + std::to_string(o.max_parallel) +
                               ": expected >= 1");
  if (!o.time_limit.empty() && !isSlurmTimeLimit(o.time_limit))
    throw InvalidArgumentError("--time-limit '" + o.time_limit +
                               "': expected [D-]HH:MM:SS, e.g. 02:00:00");

  const scenario::CampaignFile f = scenario::loadCampaignFile(o.file);
  const fs::path dir = absolutePath(o.output_dir);
  const ResultStore store(dir);
  store.create(f.text, f.definition.content_fingerprint);
  const std::vector<TrialSpec> specs = expandCampaign(f.definition);
  std::vector<std::string> to_run;
  std::size_t failed = 0;
  for (const TrialSpec& spec : specs) {
    const TrialState state = store.state(spec);
    failed += state == TrialState::failed;
    if (state != TrialState::done)
      to_run.push_back(spec.id);
  }
  std::cout << "campaign '" << f.definition.name << "': " << specs.size() << " trials, "
            << specs.size() - to_run.size() << " done, " << failed << " failed, "
            << to_run.size() - failed << " missing" << std::endl;
  if (to_run.empty()) {
    std::cout << "nothing to submit: every trial is done" << std::endl;
    return;
  }

  if (!o.dry_run) {
    if (!onPath("sbatch"))
      throw Error("sbatch not found on the PATH: submit from a Slurm login node, or "
                  "write the script only with --dry-run");
    // An earlier array still queued would run the same missing trials a second time.
    if (onPath("squeue"))
      for (const Submission& s : recordedSubmissions(dir)) {
        if (s.job_id.empty())
          continue;
        // Unknown (squeue failed): go on; sbatch reports a controller it cannot reach.
        std::string squeue_error;
        const SlurmQueueCounts q =
            queuedTasks(s.job_id, squeue_error).value_or(SlurmQueueCounts{});
        if (q.queued() > 0)
          throw Error("job " + s.job_id + " (" + s.dir.string() + ") still has " +
                      std::to_string(q.pending) + " pending and " +
                      std::to_string(q.running + q.other) +
                      " running tasks: wait until it ends (plantnbv campaign status " +
                      dir.string() + ") or cancel it (scancel " + s.job_id +
                      "), then submit again");
      }
  }

  const std::vector<std::vector<std::string>> tasks =
      splitIntoArrayTasks(to_run, o.trials_per_task);
  SlurmArrayConfig config;
  config.job_name = slurmJobName(f.definition.name);
  config.tasks = tasks.size();
  config.max_parallel = o.max_parallel_given ? o.max_parallel : 0;
  config.partition = o.partition;
  config.time_limit = o.time_limit;
  std::error_code ec;
  config.executable = fs::read_symlink("/proc/self/exe", ec).string();
  if (ec)
    throw IoError("cannot find the plantnbv binary (/proc/self/exe): " + ec.message());
  config.campaign_file = store.definitionPath().string();
  config.campaign_dir = dir.string();
  // The tasks read DIR/campaign.yaml, which the user cannot edit under them; its
  // relative paths (models, ROI files) stay relative to the original file.
  config.base_dir = absolutePath(o.file).parent_path().string();
  const fs::path submit_dir = newSubmitDir(dir);
  config.task_file = (submit_dir / kTaskFileName).string();
  config.log_dir = submit_dir.string();
  const std::string script = renderSbatchScript(config);
  const fs::path script_path = submit_dir / kScriptName;
  try { // both files or no submit directory: a task list alone would be a submission
    writeFileAtomically(config.task_file, renderTaskFile(tasks));
    writeFileAtomically(script_path, script);
  } catch (const Error&) {
    fs::remove_all(submit_dir, ec);
    throw;
  }

  const std::string shape = std::to_string(tasks.size()) + " array task" +
                            (tasks.size() == 1 ? "" : "s") + " of up to " +
                            std::to_string(o.trials_per_task) + " trials (" +
                            std::to_string(to_run.size()) + " trials)";
  if (o.dry_run) {
    std::cout << "dry run: wrote " << script_path.string() << ": " << shape
              << "; nothing submitted (sbatch " << script_path.string()
              << " would submit it)" << std::endl;
    return;
  }

  const fs::path sbatch_err = submit_dir / "sbatch.err";
  const CommandResult r =
      runCommand("sbatch --parsable " + shellQuote(script_path.string()) + " 2>" +
                 shellQuote(sbatch_err.string()));
  std::string err;
  try {
    err = lastLine(readText(sbatch_err));
  } catch (const Error&) {
  }
  if (r.exit_code != 0)
    throw Error("sbatch " + script_path.string() + " failed (exit " +
                std::to_string(r.exit_code) + ")" + (err.empty() ? "" : ": " + err));
  const std::string job_id = parseSbatchJobId(r.out);
  writeFileAtomically(submit_dir / kJobIdFileName, job_id + "\n");
  std::cout << "submitted job " << job_id << ": " << shape
            << "; logs: " << (submit_dir / ("task-" + job_id + "_<task>.out")).string()
            << " and .err; progress: plantnbv campaign status " << dir.string()
            << std::endl;
}

} // namespace

ArrayTaskTrials arrayTaskTrials(const std::vector<TrialSpec>& specs,
                                const std::string& task_file, int task)
{
  const auto tasks = parseTaskFile(readText(task_file), task_file);
  if (task < 0 || static_cast<std::size_t>(task) >= tasks.size())
    throw InvalidArgumentError(
        "--task " + std::to_string(task) + ": '" + task_file + "' has " +
        std::to_string(tasks.size()) + " tasks" +
        (tasks.empty() ? std::string()
                       : " (0 to " + std::to_string(tasks.size() - 1) + ")"));
  std::map<std::string, const TrialSpec*> by_id;
  for (const TrialSpec& s : specs)
    by_id[s.id] = &s;
  ArrayTaskTrials out;
  out.tasks = tasks.size();
  for (const std::string& id : tasks[static_cast<std::size_t>(task)]) {
    const auto it = by_id.find(id);
    if (it == by_id.end())
      throw InvalidArgumentError("'" + task_file + "' task " + std::to_string(task) +
                                 ": '" + id + "' is not a trial of this campaign");
    out.trials.push_back(*it->second);
  }
  return out;
}

void printSlurmSubmissions(const std::string& campaign_dir, std::ostream& out)
{
  const bool squeue = onPath("squeue");
  for (const Submission& s : recordedSubmissions(campaign_dir)) {
    out << "slurm " << s.dir.filename().string() << ": ";
    const std::string shape =
        std::to_string(s.tasks) + " tasks, " + std::to_string(s.trials) + " trials";
    if (s.job_id.empty()) {
      out << "not submitted (--dry-run, or sbatch failed), " << shape << "\n";
      continue;
    }
    out << "job " << s.job_id << ", " << shape;
    std::string squeue_error;
    const std::optional<SlurmQueueCounts> q =
        squeue ? queuedTasks(s.job_id, squeue_error) : std::nullopt;
    if (q) {
      out << ": " << q->pending << " pending, " << q->running << " running";
      if (q->other)
        out << ", " << q->other << " other (completing, suspended, ...)";
    } else if (squeue) {
      out << " (queue unknown: squeue: " << squeue_error << ")";
    } else {
      out << " (no squeue on the PATH: queue unknown)";
    }
    out << "\n";
  }
}

void addCampaignSubmitCommand(CLI::App& campaign)
{
  auto o = std::make_shared<SubmitOptions>();
  CLI::App* s = campaign.add_subcommand(
      "submit",
      "Submit the trials not done yet (missing or failed) as a Slurm job array: K trials "
      "per array task, one core each. DIR must be on a filesystem the compute nodes "
      "share (as must the plantnbv binary and the campaign's model files); the script, "
      "task list and logs go to DIR/slurm/submit-<time>/. Submitting again covers only "
      "what is still missing");
  s->add_option("file", o->file, "Campaign file (YAML)")->required();
  s->add_option("-o,--output", o->output_dir,
                "Campaign directory, on a filesystem shared with the compute nodes")
      ->required();
  s->add_option("--partition", o->partition, "Slurm partition (default: the cluster's)");
  s->add_option("--trials-per-task", o->trials_per_task,
                "Trials per array task, run one after the other (default: 10)");
  CLI::Option* max_parallel =
      s->add_option("--max-parallel", o->max_parallel,
                    "Array tasks running at once (default: no limit)");
  s->add_option("--time-limit", o->time_limit,
                "Time limit of one array task, [D-]HH:MM:SS (default: the partition's)");
  s->add_flag("--dry-run", o->dry_run, "Write the script and task list; submit nothing");
  s->callback([o, max_parallel]() {
    o->max_parallel_given = max_parallel->count() > 0;
    submitCampaign(*o);
  });
}

} // namespace app
} // namespace plantnbv
