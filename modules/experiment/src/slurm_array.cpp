#include <algorithm>
#include <cctype>
#include <set>
#include <sstream>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/slurm_array.h>

namespace plantnbv {

namespace {

bool allDigits(const std::string& s)
{
  return !s.empty() && std::all_of(s.begin(), s.end(),
                                   [](unsigned char c) { return std::isdigit(c) != 0; });
}

/// A field of the sbatch script that must be an absolute path.
void checkAbsolute(const std::string& field, const std::string& path)
{
  if (path.empty() || path[0] != '/')
    throw InvalidArgumentError("slurm array " + field + " '" + path +
                               "': expected an absolute path (the tasks run on other "
                               "nodes, from another directory)");
}

/// A value written bare into an #SBATCH line: sbatch splits these lines at white space
/// and quotes, and expands '%' in --output and --error.
void checkSbatchWord(const std::string& field, const std::string& value)
{
  if (value.find_first_of(" \t\n\r'\"\\%") != std::string::npos)
    throw InvalidArgumentError("slurm array " + field + " '" + value +
                               "': white space, quotes, '\\' and '%' cannot be written "
                               "into an #SBATCH line; choose a path without them");
}

} // namespace

std::vector<std::vector<std::string>>
splitIntoArrayTasks(const std::vector<std::string>& trial_ids, int trials_per_task)
{
  if (trials_per_task < 1)
    throw InvalidArgumentError(
        "trials per array task: " + std::to_string(trials_per_task) + ", expected >= 1");
  const std::size_t per_task = static_cast<std::size_t>(trials_per_task);
  const std::size_t tasks = (trial_ids.size() + per_task - 1) / per_task;
  std::vector<std::vector<std::string>> out(tasks);
  // Striding, not blocks: trials of one study or planner take similar times, so every
  // task gets a share of each and the tasks end at about the same time.
  for (std::size_t i = 0; i < trial_ids.size(); ++i)
    out[i % tasks].push_back(trial_ids[i]);
  return out;
}

std::string renderTaskFile(const std::vector<std::vector<std::string>>& tasks)
{
  std::string text = "# plantnbv campaign array tasks: <task index> TAB <trial id>\n";
  for (std::size_t t = 0; t < tasks.size(); ++t)
    for (const std::string& id : tasks[t]) {
      if (id.empty() || id.find_first_of("\t\n\r") != std::string::npos)
        throw InvalidArgumentError("trial id '" + id +
                                   "' cannot be written to a task file (empty, or "
                                   "holds a tab or a line break)");
      text += std::to_string(t) + "\t" + id + "\n";
    }
  return text;
}

std::vector<std::vector<std::string>> parseTaskFile(const std::string& text,
                                                    const std::string& name_for_messages)
{
  std::vector<std::vector<std::string>> tasks;
  std::set<std::string> seen;
  std::istringstream lines(text);
  std::string line;
  for (std::size_t number = 1; std::getline(lines, line); ++number) {
    if (!line.empty() && line.back() == '\r')
      line.pop_back();
    if (line.empty() || line[0] == '#')
      continue;
    const std::string where =
        "'" + name_for_messages + "' line " + std::to_string(number) + ": ";
    const std::size_t tab = line.find('\t');
    const std::string index = line.substr(0, tab);
    if (tab == std::string::npos || !allDigits(index) || index.size() > 9 ||
        tab + 1 == line.size())
      throw FormatError(where + "'" + line + "', expected <task index> TAB <trial id>");
    const std::size_t task = std::stoul(index);
    if (task == tasks.size())
      tasks.emplace_back();
    else if (task + 1 != tasks.size())
      throw FormatError(where + "task " + index + ", expected task " +
                        (tasks.empty() ? std::string("0")
                                       : std::to_string(tasks.size() - 1) + " or " +
                                             std::to_string(tasks.size())) +
                        " (tasks in order from 0)");
    const std::string id = line.substr(tab + 1);
    if (!seen.insert(id).second)
      throw FormatError(where + "trial '" + id + "' is listed twice");
    tasks.back().push_back(id);
  }
  return tasks;
}

void SlurmArrayConfig::validate() const
{
  if (tasks < 1)
    throw InvalidArgumentError("slurm array: 0 tasks, expected >= 1");
  if (max_parallel < 0)
    throw InvalidArgumentError(
        "slurm array max_parallel: " + std::to_string(max_parallel) + ", expected >= 0");
  if (job_name.empty())
    throw InvalidArgumentError("slurm array job_name: empty");
  checkSbatchWord("job_name", job_name);
  if (!partition.empty() &&
      !std::all_of(partition.begin(), partition.end(), [](unsigned char c) {
        return std::isalnum(c) || c == '_' || c == '-' || c == '.' || c == ',';
      }))
    throw InvalidArgumentError("slurm partition '" + partition +
                               "': expected letters, digits, '_', '-', '.' or ','");
  if (!time_limit.empty() && !isSlurmTimeLimit(time_limit))
    throw InvalidArgumentError("slurm time limit '" + time_limit +
                               "': expected [D-]HH:MM:SS, e.g. 02:00:00");
  checkAbsolute("executable", executable);
  checkAbsolute("campaign_file", campaign_file);
  checkAbsolute("campaign_dir", campaign_dir);
  checkAbsolute("base_dir", base_dir);
  checkAbsolute("task_file", task_file);
  checkAbsolute("log_dir", log_dir);
  checkSbatchWord("log_dir", log_dir);
}

std::string renderSbatchScript(const SlurmArrayConfig& c)
{
  c.validate();
  std::ostringstream s;
  s << "#!/bin/bash\n";
  s << "#SBATCH --job-name=" << c.job_name << "\n";
  s << "#SBATCH --array=0-" << c.tasks - 1;
  if (c.max_parallel > 0)
    s << "%" << c.max_parallel;
  s << "\n";
  if (!c.partition.empty())
    s << "#SBATCH --partition=" << c.partition << "\n";
  if (!c.time_limit.empty())
    s << "#SBATCH --time=" << c.time_limit << "\n";
  // One trial at a time on one core: the same as `campaign run -j 1`.
  s << "#SBATCH --ntasks=1\n";
  s << "#SBATCH --cpus-per-task=1\n";
  s << "#SBATCH --output=" << c.log_dir << "/task-%A_%a.out\n";
  s << "#SBATCH --error=" << c.log_dir << "/task-%A_%a.err\n";
  s << "# Written by `plantnbv campaign submit`: array task I runs the trials listed\n"
       "# under I in the task file; trials already done are skipped.\n";
  s << "set -eu\n";
  s << "exec " << shellQuote(c.executable) << " campaign run-chunk "
    << shellQuote(c.campaign_file) << " -o " << shellQuote(c.campaign_dir)
    << " --base-dir " << shellQuote(c.base_dir) << " --task-file "
    << shellQuote(c.task_file) << " --task \"$SLURM_ARRAY_TASK_ID\" -j 1\n";
  return s.str();
}

std::string slurmJobName(const std::string& campaign_name)
{
  std::string name = "plantnbv-" + campaign_name;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.')
      c = '_';
  return name;
}

std::string shellQuote(const std::string& text)
{
  std::string out = "'";
  for (char c : text)
    out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

bool isSlurmTimeLimit(const std::string& text)
{
  std::string rest = text;
  std::size_t max_fields = 3; // M, M:S, H:M:S
  const std::size_t dash = text.find('-');
  if (dash != std::string::npos) {
    if (!allDigits(text.substr(0, dash)))
      return false;
    rest = text.substr(dash + 1); // D-H, D-H:M, D-H:M:S
  }
  std::size_t fields = 0;
  std::istringstream parts(rest);
  std::string part;
  while (std::getline(parts, part, ':')) {
    if (!allDigits(part) || ++fields > max_fields)
      return false;
  }
  return fields >= 1 && !rest.empty() && rest.back() != ':';
}

std::string parseSbatchJobId(const std::string& parsable_output)
{
  std::string text = parsable_output;
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back())))
    text.pop_back();
  // --parsable prints "<id>" or "<id>;<cluster>" as its last line.
  const std::size_t line_start = text.find_last_of('\n');
  std::string last = line_start == std::string::npos ? text : text.substr(line_start + 1);
  const std::string id = last.substr(0, last.find(';'));
  if (!allDigits(id))
    throw FormatError("sbatch answered '" + text + "', expected a job id");
  return id;
}

SlurmQueueCounts countQueueStates(const std::string& squeue_states)
{
  SlurmQueueCounts counts;
  std::istringstream lines(squeue_states);
  std::string line;
  while (std::getline(lines, line)) {
    line.erase(0, line.find_first_not_of(" \t\r"));
    line.erase(line.find_last_not_of(" \t\r") + 1);
    if (line.empty())
      continue;
    if (line == "PENDING")
      ++counts.pending;
    else if (line == "RUNNING")
      ++counts.running;
    else
      ++counts.other;
  }
  return counts;
}

} // namespace plantnbv
