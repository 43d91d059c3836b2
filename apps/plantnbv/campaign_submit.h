#pragma once
// plantnbv campaign submit: a campaign's missing trials as a Slurm job array, and what
// `campaign run-chunk` and `campaign status` need of it (docs/campaigns.md, "Slurm").

#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include <plantnbv/experiment/campaign.h>

namespace CLI {
class App;
}

namespace plantnbv {
namespace app {

/// Adds `submit` to the `campaign` command.
void addCampaignSubmitCommand(CLI::App& campaign);

/// The trials of one array task of a task file written by `submit`.
struct ArrayTaskTrials {
  std::vector<TrialSpec> trials; ///< in the task file's order
  std::size_t tasks = 0;         ///< tasks in the file
};

/// The specs of task `task` of `task_file`, looked up in `specs` (the campaign's).
/// \throws IoError if the file cannot be read; FormatError if it is not a task file;
/// InvalidArgumentError if there is no such task or it lists a trial `specs` lacks.
ArrayTaskTrials arrayTaskTrials(const std::vector<TrialSpec>& specs,
                                const std::string& task_file, int task);

/// Prints one line per submission recorded in DIR/slurm (job id, tasks, trials and,
/// when squeue is on the PATH, how many of its tasks are pending or running).
void printSlurmSubmissions(const std::string& campaign_dir, std::ostream& out);

} // namespace app
} // namespace plantnbv
