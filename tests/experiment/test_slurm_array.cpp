// A campaign as a Slurm job array: splitting trials into tasks, the task file, the
// sbatch script, and reading what sbatch and squeue answer.

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/slurm_array.h>

using namespace plantnbv;

namespace {

std::vector<std::string> ids(int n)
{
  std::vector<std::string> out;
  for (int i = 0; i < n; ++i)
    out.push_back("main/random/plant00/yaw" + std::to_string(i) + "/rep0");
  return out;
}

SlurmArrayConfig config()
{
  SlurmArrayConfig c;
  c.job_name = "plantnbv-tiny";
  c.tasks = 3;
  c.executable = "/opt/plantnbv/bin/plantnbv";
  c.campaign_file = "/shared/c/campaign.yaml";
  c.campaign_dir = "/shared/c";
  c.base_dir = "/home/me/campaigns";
  c.task_file = "/shared/c/slurm/submit-1/tasks.txt";
  c.log_dir = "/shared/c/slurm/submit-1";
  return c;
}

bool contains(const std::string& text, const std::string& part)
{
  return text.find(part) != std::string::npos;
}

} // namespace

TEST(SlurmArray, SplitGivesAtMostKTrialsPerTaskStridedAndBalanced)
{
  const std::vector<std::string> all = ids(10);
  const auto tasks = splitIntoArrayTasks(all, 3); // ceil(10 / 3) = 4 tasks
  ASSERT_EQ(tasks.size(), 4u);
  EXPECT_EQ(tasks[0], (std::vector<std::string>{all[0], all[4], all[8]}));
  EXPECT_EQ(tasks[1], (std::vector<std::string>{all[1], all[5], all[9]}));
  EXPECT_EQ(tasks[2], (std::vector<std::string>{all[2], all[6]}));
  EXPECT_EQ(tasks[3], (std::vector<std::string>{all[3], all[7]}));

  EXPECT_EQ(splitIntoArrayTasks(all, 10).size(), 1u);
  EXPECT_EQ(splitIntoArrayTasks(all, 100).size(), 1u);
  EXPECT_EQ(splitIntoArrayTasks(all, 1).size(), 10u);
  EXPECT_EQ(splitIntoArrayTasks(all, 5).size(), 2u);
  EXPECT_TRUE(splitIntoArrayTasks({}, 5).empty());
}

TEST(SlurmArray, SplitCoversEveryTrialOnce)
{
  for (int n : {1, 2, 7, 24, 101})
    for (int k : {1, 2, 3, 10, 200}) {
      const auto tasks = splitIntoArrayTasks(ids(n), k);
      std::vector<std::string> seen;
      std::size_t smallest = SIZE_MAX, largest = 0;
      for (const auto& t : tasks) {
        seen.insert(seen.end(), t.begin(), t.end());
        smallest = std::min(smallest, t.size());
        largest = std::max(largest, t.size());
      }
      std::sort(seen.begin(), seen.end());
      std::vector<std::string> expected = ids(n);
      std::sort(expected.begin(), expected.end());
      EXPECT_EQ(seen, expected) << n << " trials, " << k << " per task";
      EXPECT_LE(largest, std::size_t(k));
      EXPECT_LE(largest - smallest, 1u);
    }
}

TEST(SlurmArray, SplitRefusesANonPositiveTaskSize)
{
  EXPECT_THROW(splitIntoArrayTasks(ids(3), 0), InvalidArgumentError);
  EXPECT_THROW(splitIntoArrayTasks(ids(3), -2), InvalidArgumentError);
}

TEST(SlurmArray, TaskFileReadsBackWhatWasWritten)
{
  std::vector<std::string> all = ids(7);
  all[3] = "main/nbv-leaf-nodes/my plant/yaw090/rep0"; // a model name with a space
  const auto tasks = splitIntoArrayTasks(all, 2);
  const std::string text = renderTaskFile(tasks);
  EXPECT_EQ(text.rfind("# ", 0), 0u);
  EXPECT_TRUE(contains(text, "\n0\t" + all[0] + "\n"));
  EXPECT_TRUE(contains(text, "\n3\t" + all[3] + "\n"));
  EXPECT_EQ(parseTaskFile(text, "tasks.txt"), tasks);
  EXPECT_TRUE(parseTaskFile(renderTaskFile({}), "tasks.txt").empty());
  EXPECT_THROW(renderTaskFile({{"a\tb"}}), InvalidArgumentError);
  EXPECT_THROW(renderTaskFile({{""}}), InvalidArgumentError);
}

TEST(SlurmArray, MalformedTaskFilesNameFileAndLine)
{
  auto error = [](const std::string& text) {
    try {
      parseTaskFile(text, "t.txt");
    } catch (const FormatError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_TRUE(contains(error("# c\n0 a\n"), "'t.txt' line 2"));         // no tab
  EXPECT_TRUE(contains(error("x\ta\n"), "line 1"));                     // not an index
  EXPECT_TRUE(contains(error("0\t\n"), "line 1"));                      // no id
  EXPECT_TRUE(contains(error("1\ta\n"), "expected task 0"));            // not from 0
  EXPECT_TRUE(contains(error("0\ta\n2\tb\n"), "expected task 0 or 1")); // a gap
  EXPECT_TRUE(contains(error("0\ta\n1\tb\n0\tc\n"), "line 3"));         // back to 0
  EXPECT_TRUE(contains(error("0\ta\n1\ta\n"), "'a' is listed twice"));
  EXPECT_EQ(parseTaskFile("0\ta\r\n0\tb\r\n\n1\tc\n", "t.txt"),
            (std::vector<std::vector<std::string>>{{"a", "b"}, {"c"}}));
}

TEST(SlurmArray, ScriptHasTheArrayLogsAndTheRunChunkLine)
{
  const std::string script = renderSbatchScript(config());
  EXPECT_EQ(script.rfind("#!/bin/bash\n", 0), 0u);
  EXPECT_TRUE(contains(script, "\n#SBATCH --job-name=plantnbv-tiny\n"));
  EXPECT_TRUE(contains(script, "\n#SBATCH --array=0-2\n"));
  EXPECT_TRUE(contains(script, "\n#SBATCH --cpus-per-task=1\n"));
  EXPECT_TRUE(
      contains(script, "\n#SBATCH --output=/shared/c/slurm/submit-1/task-%A_%a.out\n"));
  EXPECT_TRUE(
      contains(script, "\n#SBATCH --error=/shared/c/slurm/submit-1/task-%A_%a.err\n"));
  EXPECT_FALSE(contains(script, "--partition"));
  EXPECT_FALSE(contains(script, "--time"));
  EXPECT_TRUE(contains(script, "\nexec '/opt/plantnbv/bin/plantnbv' campaign run-chunk "
                               "'/shared/c/campaign.yaml' -o '/shared/c' --base-dir "
                               "'/home/me/campaigns' --task-file "
                               "'/shared/c/slurm/submit-1/tasks.txt' --task "
                               "\"$SLURM_ARRAY_TASK_ID\" -j 1\n"));
  // Every #SBATCH line comes before the first command (sbatch stops reading there).
  const std::size_t last_directive = script.rfind("#SBATCH");
  EXPECT_LT(last_directive, script.find("\nset -eu"));

  SlurmArrayConfig c = config();
  c.max_parallel = 4;
  c.partition = "gpu,cpu";
  c.time_limit = "1-02:00:00";
  const std::string limited = renderSbatchScript(c);
  EXPECT_TRUE(contains(limited, "\n#SBATCH --array=0-2%4\n"));
  EXPECT_TRUE(contains(limited, "\n#SBATCH --partition=gpu,cpu\n"));
  EXPECT_TRUE(contains(limited, "\n#SBATCH --time=1-02:00:00\n"));
  c.tasks = 1;
  EXPECT_TRUE(contains(renderSbatchScript(c), "\n#SBATCH --array=0-0%4\n"));
}

TEST(SlurmArray, ScriptQuotesPathsForTheShell)
{
  SlurmArrayConfig c = config();
  c.base_dir = "/home/me/my campaigns/it's here";
  EXPECT_TRUE(contains(renderSbatchScript(c),
                       "--base-dir '/home/me/my campaigns/it'\\''s here' "));
  EXPECT_EQ(shellQuote(""), "''");
  EXPECT_EQ(shellQuote("a$b`c"), "'a$b`c'");
}

TEST(SlurmArray, InvalidScriptConfigsAreRefusedNamingTheField)
{
  auto error = [](const SlurmArrayConfig& c) {
    try {
      renderSbatchScript(c);
    } catch (const InvalidArgumentError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  SlurmArrayConfig c = config();
  c.tasks = 0;
  EXPECT_TRUE(contains(error(c), "0 tasks"));
  c = config();
  c.max_parallel = -1;
  EXPECT_TRUE(contains(error(c), "max_parallel"));
  c = config();
  c.campaign_dir = "relative/dir";
  EXPECT_TRUE(contains(error(c), "campaign_dir 'relative/dir'"));
  c = config();
  c.executable = "";
  EXPECT_TRUE(contains(error(c), "executable"));
  c = config();
  c.log_dir = "/shared/my logs";
  EXPECT_TRUE(contains(error(c), "log_dir '/shared/my logs'"));
  c = config();
  c.log_dir = "/shared/100%";
  EXPECT_TRUE(contains(error(c), "log_dir"));
  c = config();
  c.partition = "a b";
  EXPECT_TRUE(contains(error(c), "partition 'a b'"));
  c = config();
  c.time_limit = "2h";
  EXPECT_TRUE(contains(error(c), "time limit '2h'"));
  c = config();
  c.job_name = "x y";
  EXPECT_TRUE(contains(error(c), "job_name"));
}

TEST(SlurmArray, TimeLimitsInSlurmsFormats)
{
  for (const char* ok : {"30", "30:00", "02:00:00", "1-0", "1-02:00", "1-02:00:00"})
    EXPECT_TRUE(isSlurmTimeLimit(ok)) << ok;
  for (const char* bad : {"", "2h", "1:2:3:4", "1-2:3:4:5", "-1", "1-", ":30",
                          "30:", "1--2", "01:0a:00", "1-2-3"})
    EXPECT_FALSE(isSlurmTimeLimit(bad)) << bad;
}

TEST(SlurmArray, JobNamesKeepOnlySafeCharacters)
{
  EXPECT_EQ(slurmJobName("paper"), "plantnbv-paper");
  EXPECT_EQ(slurmJobName("my study/v2 (final)"), "plantnbv-my_study_v2__final_");
  EXPECT_EQ(slurmJobName("a.b_c-d"), "plantnbv-a.b_c-d");
}

TEST(SlurmArray, SbatchJobIdAndQueueStates)
{
  EXPECT_EQ(parseSbatchJobId("1234\n"), "1234");
  EXPECT_EQ(parseSbatchJobId("1234;cluster\n"), "1234");
  EXPECT_EQ(parseSbatchJobId("sbatch: warning: x\n77\n"), "77");
  EXPECT_THROW(parseSbatchJobId(""), FormatError);
  EXPECT_THROW(parseSbatchJobId("Submitted batch job\n"), FormatError);

  const SlurmQueueCounts q =
      countQueueStates("PENDING\nRUNNING\n  RUNNING \nCOMPLETING\n\nPENDING\nPENDING\n");
  EXPECT_EQ(q.pending, 3u);
  EXPECT_EQ(q.running, 2u);
  EXPECT_EQ(q.other, 1u);
  EXPECT_EQ(q.queued(), 6u);
  EXPECT_EQ(countQueueStates("").queued(), 0u);
}
