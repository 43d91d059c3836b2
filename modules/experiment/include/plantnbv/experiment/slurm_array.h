#pragma once
/// \file slurm_array.h
/// \brief A campaign as a Slurm job array: the trials still to run split into array
/// tasks, the task file that lists them, the sbatch script that runs one task per array
/// index, and the parsing of what sbatch and squeue answer. Pure text in, text out: the
/// tool writes the files and runs sbatch and squeue (docs/campaigns.md, "Slurm").

#include <cstddef>
#include <string>
#include <vector>

namespace plantnbv {

/// \brief Trial ids of each array task: task i holds the ids [i], [i + T], [i + 2T], ...
/// of `trial_ids` (T tasks, T = ceil(n / trials_per_task)), so every task holds at most
/// `trials_per_task` ids, task sizes differ by at most one and every task gets a share of
/// every study (as campaignChunk). Empty `trial_ids`: no task.
/// \param[in] trial_ids the trials to run, in campaign order
/// \param[in] trials_per_task at most this many trials per task, >= 1
/// \throws InvalidArgumentError if trials_per_task < 1.
std::vector<std::vector<std::string>>
splitIntoArrayTasks(const std::vector<std::string>& trial_ids, int trials_per_task);

/// \brief The task file: a comment line, then one line per trial, "<task index> TAB
/// <trial id>", task by task. Trial ids may hold any character but tab and newline.
/// \throws InvalidArgumentError if an id is empty or holds a tab or a newline.
std::string renderTaskFile(const std::vector<std::vector<std::string>>& tasks);

/// \brief Reads a task file back (the inverse of renderTaskFile). Lines starting with
/// '#' and empty lines are skipped.
/// \param[in] name_for_messages names the file in errors
/// \throws FormatError naming the file and line for a malformed line, task indices that
/// are not 0, 1, 2, ... in order, or an id listed twice.
std::vector<std::vector<std::string>> parseTaskFile(const std::string& text,
                                                    const std::string& name_for_messages);

/// \brief What the sbatch script of a campaign's array job says. Paths must be absolute
/// (the tasks run on other nodes, from another working directory).
struct SlurmArrayConfig {
  std::string job_name;      ///< --job-name; see slurmJobName()
  std::size_t tasks = 0;     ///< array indices 0 .. tasks-1; >= 1
  int max_parallel = 0;      ///< tasks running at once (--array=..%M); 0: no limit
  std::string partition;     ///< --partition; empty: the cluster's default
  std::string time_limit;    ///< --time per task, e.g. "02:00:00"; empty: the default
  std::string executable;    ///< the plantnbv binary the tasks run
  std::string campaign_file; ///< the campaign definition: DIR/campaign.yaml
  std::string campaign_dir;  ///< DIR
  std::string base_dir;      ///< where relative paths of the campaign file are read from
  std::string task_file;     ///< renderTaskFile's text on disk
  std::string log_dir;       ///< task-%A_%a.out and .err go here

  /// \throws InvalidArgumentError naming the field and value: tasks 0, max_parallel < 0,
  /// a relative path, a partition or time limit that is not Slurm's syntax, a job name
  /// or log directory with characters an `#SBATCH` line cannot hold (white space, quotes,
  /// '\\', '%').
  void validate() const;
};

/// \brief The sbatch script: `#SBATCH` lines (--job-name, --array=0-(T-1)[%M],
/// --partition, --time, --ntasks=1, --cpus-per-task=1, --output and --error one pair
/// per task) and a body that runs `EXE campaign run-chunk FILE -o DIR --base-dir B
/// --task-file F --task $SLURM_ARRAY_TASK_ID -j 1`, every path single-quoted.
/// \throws InvalidArgumentError if `config` does not validate.
std::string renderSbatchScript(const SlurmArrayConfig& config);

/// \brief "plantnbv-<campaign name>", with every character but letters, digits, '-',
/// '_' and '.' replaced by '_'.
std::string slurmJobName(const std::string& campaign_name);

/// \brief `text` quoted for a POSIX shell: 'text', with each ' written as '\''.
std::string shellQuote(const std::string& text);

/// \brief True for Slurm's time formats: M, M:S, H:M:S, D-H, D-H:M, D-H:M:S (digits).
bool isSlurmTimeLimit(const std::string& text);

/// \brief The job id in the answer of `sbatch --parsable` ("<id>" or "<id>;<cluster>",
/// then a newline), as digits.
/// \throws FormatError with the answer if it holds no job id.
std::string parseSbatchJobId(const std::string& parsable_output);

/// \brief Array tasks of a job by state, counted from `squeue -h -r -o %T` (one state a
/// line).
struct SlurmQueueCounts {
  std::size_t pending = 0; ///< PENDING lines
  std::size_t running = 0; ///< RUNNING lines
  std::size_t other = 0;   ///< completing, configuring, suspended, ...
  /// \brief All tasks still in the queue: pending + running + other.
  std::size_t queued() const { return pending + running + other; }
};

/// \brief Counts the state lines of `squeue -h -r -o %T`; empty lines are skipped.
SlurmQueueCounts countQueueStates(const std::string& squeue_states);

} // namespace plantnbv
