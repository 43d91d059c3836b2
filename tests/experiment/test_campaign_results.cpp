// The result store (atomic files, status), the local runner (skips done trials, records
// failures, stops on request) and the report's curves for hand-made results.

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/campaign.h>
#include <plantnbv/experiment/campaign_report.h>
#include <plantnbv/experiment/campaign_runner.h>
#include <plantnbv/experiment/result_store.h>

#include "read_csv.h"

using namespace plantnbv;
namespace fs = std::filesystem;

using plantnbv::test::readCsv;

namespace {

class CampaignResultsTest : public ::testing::Test {
protected:
  void SetUp() override
  {
    dir_ = fs::temp_directory_path() /
           ("plantnbv_campaign_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

std::string slurp(const fs::path& p)
{
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

CampaignDefinition smallCampaign()
{
  CampaignDefinition d;
  d.name = "small";
  d.seed = 5;
  for (int s = 0; s < 2; ++s) {
    CampaignPlant p;
    p.seed = s;
    p.name = "plant0" + std::to_string(s);
    d.plants.push_back(p);
  }
  d.yaws_deg = {0, 180};
  d.views = 3;
  d.studies = {{"main",
                {{"nbv-leaf-nodes", PlannerKind::nbv, "leaf-nodes", {}},
                 {"predefined", PlannerKind::predefined, "", {1, 2}}},
                {},
                {},
                {}}};
  return d;
}

/// A made-up result: F1 after view v is (v + 1) / 10 + seed % 7 / 100, one level.
void fakeTrial(const TrialSpec& t, TrialResult& r)
{
  r.level_names = {"whole_plant"};
  for (int v = 0; v < t.views; ++v) {
    TrialStep s;
    s.index = v;
    s.gain = v ? 1.5 * v : std::nan("");
    s.plan_ms = 1.0;
    LevelScore score;
    score.f1 = (v + 1) / 10.0 + double(t.seed % 7) / 100.0;
    score.precision = 1.0;
    score.recall = score.f1;
    score.chamfer = v == 0 ? std::nan("") : 0.01;
    s.scores = {score};
    r.steps.push_back(s);
  }
  r.total_ms = 3.0;
}

} // namespace

TEST_F(CampaignResultsTest, StoreWritesOneFilePerTrialAndCountsThem)
{
  const std::vector<TrialSpec> specs = expandCampaign(smallCampaign());
  ASSERT_EQ(specs.size(), 2u * 2u * 3u);
  const ResultStore store(dir_);
  store.create("name: small\n");
  EXPECT_EQ(slurp(dir_ / "campaign.yaml"), "name: small\n");
  store.create("name: small\n"); // the same campaign again: fine
  EXPECT_THROW(store.create("name: other\n"), InvalidArgumentError);

  TrialResult r;
  fakeTrial(specs[0], r);
  store.writeResult(specs[0], r);
  store.writeFailure(specs[1], "cannot read 'gone.dae'");
  EXPECT_EQ(store.resultPath(specs[0].id).filename().string(),
            "main+nbv-leaf-nodes+plant00+yaw000+rep0.json");
  EXPECT_EQ(store.state(specs[0].id), TrialState::done);
  EXPECT_EQ(store.state(specs[1].id), TrialState::failed);
  EXPECT_EQ(store.state(specs[2].id), TrialState::missing);
  // A half-written temporary file of a killed run is not a result.
  std::ofstream(dir_ / "trials" / (".x.json.tmp.1.2")) << "{\"id\":";
  std::ofstream(store.resultPath(specs[3].id))
      << "{\"id\": \"" << specs[3].id << "\", \"sta";
  const StoreStatus s = store.status(specs);
  EXPECT_EQ(s.total, specs.size());
  EXPECT_EQ(s.done, 1u);
  EXPECT_EQ(s.failed, 1u);
  EXPECT_EQ(s.missing, specs.size() - 2);
  ASSERT_EQ(s.failed_ids.size(), 1u);
  EXPECT_EQ(s.failed_ids[0], specs[1].id);
  EXPECT_EQ(s.failed_errors[0], "cannot read 'gone.dae'");

  const StoredTrial t = ResultStore::loadFile(store.resultPath(specs[0].id));
  EXPECT_EQ(t.id, specs[0].id);
  EXPECT_EQ(t.planner, "nbv-leaf-nodes");
  ASSERT_EQ(t.views.size(), 3u);
  EXPECT_DOUBLE_EQ(t.views[2][0].f1, r.steps[2].scores[0].f1);
  EXPECT_TRUE(std::isnan(t.views[0][0].chamfer)); // written as null
  const std::string text = slurp(store.resultPath(specs[0].id));
  EXPECT_NE(text.find("\"chamfer\": null"), std::string::npos);
  EXPECT_NE(text.find("\"gain\": null"), std::string::npos);
  EXPECT_NE(text.find("\"recall\": 0.1"), std::string::npos)
      << "shortest round-trip form";
  EXPECT_NE(text.find("\"seed\": " + std::to_string(specs[0].seed)), std::string::npos);
}

TEST_F(CampaignResultsTest, RunnerSkipsDoneTrialsAndRecordsFailures)
{
  const std::vector<TrialSpec> specs = expandCampaign(smallCampaign());
  const ResultStore store(dir_);
  store.create("x");
  std::atomic<int> calls{0};
  auto run = [&](const TrialSpec& t, TrialResult& r) {
    ++calls;
    if (t.id == specs[4].id)
      throw IoError("cannot read 'gone.dae'");
    fakeTrial(t, r);
  };
  LocalRunner runner(store, run, 2);
  std::vector<CampaignProgress> events;
  runner.setProgressCallback([&](const CampaignProgress& p) { events.push_back(p); });
  CampaignProgress p = runner.run(specs);
  EXPECT_EQ(calls.load(), static_cast<int>(specs.size()));
  EXPECT_EQ(p.ran, specs.size());
  EXPECT_EQ(p.failed, 1u);
  EXPECT_EQ(store.status(specs).done, specs.size() - 1);
  EXPECT_EQ(store.state(specs[4].id), TrialState::failed);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.front().event, CampaignProgress::Event::started);
  int finished = 0;
  for (const CampaignProgress& e : events)
    if (e.event == CampaignProgress::Event::finished) {
      ++finished;
      if (e.id == specs[4].id) {
        EXPECT_TRUE(e.trial_failed);
        EXPECT_NE(e.error.find("gone.dae"), std::string::npos);
      }
    }
  EXPECT_EQ(finished, static_cast<int>(specs.size()));

  // Again: only the failed trial runs.
  const std::string before = slurp(store.resultPath(specs[0].id));
  calls = 0;
  p = runner.run(specs);
  EXPECT_EQ(calls.load(), 1);
  EXPECT_EQ(p.skipped, specs.size() - 1);
  EXPECT_EQ(slurp(store.resultPath(specs[0].id)), before);

  // A stop request before the run: nothing starts.
  fs::remove(store.resultPath(specs[0].id));
  std::atomic<bool> stop{true};
  runner.setStopFlag(&stop);
  calls = 0;
  p = runner.run(specs);
  EXPECT_EQ(calls.load(), 0);
  EXPECT_EQ(store.state(specs[0].id), TrialState::missing);
}

TEST_F(CampaignResultsTest, ResultsAreTheSameBytesOnOneAndTwoWorkers)
{
  const std::vector<TrialSpec> specs = expandCampaign(smallCampaign());
  const ResultStore a(dir_ / "a"), b(dir_ / "b");
  a.create("x");
  b.create("x");
  LocalRunner(a, fakeTrial, 1).run(specs);
  LocalRunner(b, fakeTrial, 2).run(specs);
  for (const TrialSpec& t : specs)
    EXPECT_EQ(slurp(a.resultPath(t.id)), slurp(b.resultPath(t.id))) << t.id;
}

TEST(CampaignChunks, ChunksPartitionTheTrials)
{
  const std::vector<TrialSpec> specs = expandCampaign(smallCampaign());
  std::multiset<std::string> ids;
  for (int c = 0; c < 5; ++c)
    for (const TrialSpec& t : campaignChunk(specs, c, 5))
      ids.insert(t.id);
  EXPECT_EQ(ids.size(), specs.size());
  for (const TrialSpec& t : specs)
    EXPECT_EQ(ids.count(t.id), 1u);
  EXPECT_THROW(campaignChunk(specs, 5, 5), InvalidArgumentError);
}

namespace {

/// A trial file as a person would write it: F1 and Chamfer per view for one level.
void writeTrial(const fs::path& dir, const std::string& planner, int pattern,
                const std::string& plant, const std::vector<double>& f1,
                const std::vector<std::string>& chamfer)
{
  const std::string id = "main/" + planner +
                         (pattern ? "-p" + std::to_string(pattern) : "") + "/" + plant +
                         "/yaw000/rep0";
  std::string name = id;
  std::replace(name.begin(), name.end(), '/', '+');
  std::ofstream out(dir / "trials" / (name + ".json"));
  out << "{\"id\": \"" << id << "\", \"spec\": {\"study\": \"main\", \"variant\": \"\", "
      << "\"planner\": \"" << planner
      << "\", \"pattern\": " << (pattern ? std::to_string(pattern) : "null")
      << ", \"plant\": \"" << plant << "\", \"yaw_deg\": 0, \"repetition\": 0}, "
      << "\"status\": \"done\", \"levels\": [\"whole_plant\"], \"views\": [";
  for (std::size_t v = 0; v < f1.size(); ++v)
    out << (v ? ", " : "")
        << "{\"levels\": {\"whole_plant\": {\"precision\": 1, \"recall\": " << f1[v]
        << ", \"f1\": " << f1[v] << ", \"chamfer\": " << chamfer[v] << "}}}";
  out << "]}\n";
}

} // namespace

TEST_F(CampaignResultsTest, ReportCurvesOfAHandMadeResultsDirectory)
{
  fs::create_directories(dir_ / "trials");
  // nbv-a: three plants, F1 after view 1 = 0.2, 0.4, 0.6; after view 2 = 0.5 each.
  writeTrial(dir_, "nbv-a", 0, "p1", {0.2, 0.5}, {"null", "0.01"});
  writeTrial(dir_, "nbv-a", 0, "p2", {0.4, 0.5}, {"0.02", "0.03"});
  writeTrial(dir_, "nbv-a", 0, "p3", {0.6, 0.5}, {"0.04", "0.05"});
  // predefined: two patterns on each of two plants, averaged per plant first:
  // p1 (0.1 + 0.3) / 2 = 0.2, p2 (0.5 + 0.7) / 2 = 0.6.
  writeTrial(dir_, "predefined", 1, "p1", {0.1}, {"0.01"});
  writeTrial(dir_, "predefined", 2, "p1", {0.3}, {"0.01"});
  writeTrial(dir_, "predefined", 1, "p2", {0.5}, {"0.01"});
  writeTrial(dir_, "predefined", 2, "p2", {0.7}, {"0.01"});
  // A failed trial counts nowhere.
  std::ofstream(dir_ / "trials" / "main+nbv-a+p4+yaw000+rep0.json")
      << "{\"id\": \"main/nbv-a/p4/yaw000/rep0\", \"spec\": {\"study\": \"main\", "
         "\"planner\": \"nbv-a\", \"plant\": \"p4\", \"yaw_deg\": 0}, \"status\": "
         "\"failed\", \"error\": \"boom\"}\n";

  const std::vector<StoredTrial> trials = ResultStore(dir_).load();
  ASSERT_EQ(trials.size(), 8u);
  writeCampaignReport(trials, dir_ / "report", "hand-made");
  const auto rows = readCsv(slurp(dir_ / "report" / "curves.csv"));
  ASSERT_EQ(rows.size(), 1u + 2u + 1u) << slurp(dir_ / "report" / "curves.csv");
  const std::vector<std::string>& h = rows[0];
  auto col = [&h](const std::string& name) {
    return static_cast<std::size_t>(std::find(h.begin(), h.end(), name) - h.begin());
  };
  ASSERT_LT(col("f1_ci_high"), h.size());
  ASSERT_LT(col("chamfer_n"), h.size());
  // nbv-a, view 1: mean 0.4, sd 0.2, n 3, CI 0.4 -+ 4.302652729749464 * 0.2 / sqrt(3).
  const auto& a1 = rows[1];
  EXPECT_EQ(a1[col("study")], "main");
  EXPECT_EQ(a1[col("planner")], "nbv-a");
  EXPECT_EQ(a1[col("level")], "whole_plant");
  EXPECT_EQ(a1[col("view")], "1");
  EXPECT_NEAR(std::stod(a1[col("f1_mean")]), 0.4, 1e-12);
  EXPECT_NEAR(std::stod(a1[col("f1_sd")]), 0.2, 1e-12);
  EXPECT_EQ(a1[col("f1_n")], "3");
  const double half = 4.302652729749464 * 0.2 / std::sqrt(3.0);
  EXPECT_NEAR(std::stod(a1[col("f1_ci_low")]), 0.4 - half, 1e-9);
  EXPECT_NEAR(std::stod(a1[col("f1_ci_high")]), 0.4 + half, 1e-9);
  // Chamfer: the null is left out: 0.02, 0.04 -> mean 0.03, n 2.
  EXPECT_NEAR(std::stod(a1[col("chamfer_mean")]), 0.03, 1e-12);
  EXPECT_EQ(a1[col("chamfer_n")], "2");
  // View 2: no spread.
  const auto& a2 = rows[2];
  EXPECT_EQ(a2[col("view")], "2");
  EXPECT_NEAR(std::stod(a2[col("f1_mean")]), 0.5, 1e-12);
  EXPECT_NEAR(std::stod(a2[col("f1_sd")]), 0.0, 1e-12);
  // predefined: two samples (plants), not four trials: 0.2 and 0.6.
  const auto& p1 = rows[3];
  EXPECT_EQ(p1[col("planner")], "predefined");
  EXPECT_EQ(p1[col("f1_n")], "2");
  EXPECT_NEAR(std::stod(p1[col("f1_mean")]), 0.4, 1e-12);
  EXPECT_NEAR(std::stod(p1[col("f1_sd")]), std::sqrt(0.08), 1e-12);

  const std::string summary = slurp(dir_ / "report" / "summary.md");
  EXPECT_NE(summary.find("7 trials done, 1 failed"), std::string::npos) << summary;
  // nbv-a's mean curve 0.4, 0.5 never reaches 0.8; its gain over predefined after 3 views
  // is undefined (2 views): shown as "-".
  EXPECT_NE(summary.find("| nbv-a | 3 | - / - (median >2 / >2) |"), std::string::npos)
      << summary;
}
