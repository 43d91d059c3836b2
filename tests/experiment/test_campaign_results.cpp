// The result store (atomic files, status), the local runner (skips done trials, records
// failures, stops on request) and the report's curves for hand-made results.

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

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
                {{"nbv-leaf-nodes", PlannerKind::nbv, "leaf-nodes", {}, {}},
                 {"predefined", PlannerKind::predefined, "", {1, 2}, {}}},
                {},
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
  store.create("name: small\n", "f1");
  EXPECT_EQ(slurp(dir_ / "campaign.yaml"), "name: small\n");
  store.create("name: small\n", "f1"); // the same campaign again: fine
  EXPECT_THROW(store.create("name: other\n", "f2"), InvalidArgumentError);

  TrialResult r;
  fakeTrial(specs[0], r);
  store.writeResult(specs[0], r);
  store.writeFailure(specs[1], "cannot read 'gone.dae'");
  EXPECT_EQ(store.resultPath(specs[0].id).filename().string(),
            "main+nbv-leaf-nodes+plant00+yaw000+rep0.json");
  EXPECT_EQ(store.state(specs[0]), TrialState::done);
  EXPECT_EQ(store.state(specs[1]), TrialState::failed);
  EXPECT_EQ(store.state(specs[2]), TrialState::missing);
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
  // The done trial's own time, for `campaign status`'s ETA; the failed one has none.
  EXPECT_EQ(s.timed, 1u);
  EXPECT_DOUBLE_EQ(s.timed_s, r.total_ms / 1000.0);

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
  store.create("x", "f");
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
  EXPECT_EQ(store.state(specs[4]), TrialState::failed);
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
  EXPECT_EQ(store.state(specs[0]), TrialState::missing);
}

TEST_F(CampaignResultsTest, ResultsAreTheSameBytesOnOneAndTwoWorkers)
{
  const std::vector<TrialSpec> specs = expandCampaign(smallCampaign());
  const ResultStore a(dir_ / "a"), b(dir_ / "b");
  a.create("x", "f");
  b.create("x", "f");
  LocalRunner(a, fakeTrial, 1).run(specs);
  LocalRunner(b, fakeTrial, 2).run(specs);
  for (const TrialSpec& t : specs)
    EXPECT_EQ(slurp(a.resultPath(t.id)), slurp(b.resultPath(t.id))) << t.id;
}

TEST_F(CampaignResultsTest, TheRecordTellsCampaignsApartByContentNotByText)
{
  const ResultStore store(dir_);
  store.create("name: small # first\n", "aaaa");
  EXPECT_EQ(slurp(dir_ / "campaign.json"), "{\"fingerprint\": \"aaaa\"}\n");
  // The same content written otherwise (a comment added): the same campaign, and the
  // copy of the definition the trials were expanded from is kept.
  store.create("name: small # second\n", "aaaa");
  EXPECT_EQ(slurp(dir_ / "campaign.yaml"), "name: small # first\n");
  try {
    store.create("name: small # first\n", "bbbb");
    FAIL() << "another fingerprint was accepted";
  } catch (const InvalidArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("holds another campaign"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("bbbb"), std::string::npos);
  }
  // A directory from before records: its text decides once, then the record.
  const ResultStore old(dir_ / "old");
  fs::create_directories(dir_ / "old" / "trials");
  std::ofstream(dir_ / "old" / "campaign.yaml") << "name: old\n";
  EXPECT_THROW(old.create("name: other\n", "cccc"), InvalidArgumentError);
  EXPECT_FALSE(fs::exists(dir_ / "old" / "campaign.json"));
  old.create("name: old\n", "cccc");
  EXPECT_EQ(slurp(dir_ / "old" / "campaign.json"),
            "{\"fingerprint\": \"cccc\", \"legacy_trials\": true}\n");
}

TEST_F(CampaignResultsTest, ResultsOfAnotherCampaignAreRunAgainAndNotReported)
{
  CampaignDefinition ours = smallCampaign(), theirs = smallCampaign();
  ours.content_fingerprint = "ours";
  theirs.content_fingerprint = "theirs";
  const std::vector<TrialSpec> specs = expandCampaign(ours);
  const std::vector<TrialSpec> other = expandCampaign(theirs);
  ASSERT_EQ(specs[0].id, other[0].id);
  ASSERT_NE(specs[0].fingerprint, other[0].fingerprint);
  // Another seed with the same content changes every trial's fingerprint too.
  CampaignDefinition reseeded = ours;
  reseeded.seed = 6;
  EXPECT_NE(expandCampaign(reseeded)[0].fingerprint, specs[0].fingerprint);

  const ResultStore store(dir_ / "ours"), foreign(dir_ / "theirs");
  store.create("x", "ours");
  foreign.create("y", "theirs");
  LocalRunner(store, fakeTrial, 1).run(specs);
  LocalRunner(foreign, fakeTrial, 1).run(other);
  // Their files copied over some of ours, and one without any fingerprint.
  for (std::size_t i : {0, 3})
    fs::copy_file(foreign.resultPath(other[i].id), store.resultPath(specs[i].id),
                  fs::copy_options::overwrite_existing);
  std::string text = slurp(store.resultPath(specs[5].id));
  const std::size_t at = text.find("  \"fingerprint\"");
  ASSERT_NE(at, std::string::npos);
  text.erase(at, text.find('\n', at) + 1 - at);
  std::ofstream(store.resultPath(specs[5].id)) << text;

  EXPECT_EQ(store.state(specs[0]), TrialState::foreign);
  EXPECT_EQ(store.state(specs[5]), TrialState::foreign);
  EXPECT_EQ(store.state(specs[1]), TrialState::done);
  const StoreStatus s = store.status(specs);
  EXPECT_EQ(s.foreign, 3u);
  EXPECT_EQ(s.missing, 3u);
  EXPECT_EQ(s.done, specs.size() - 3);
  try {
    store.load(specs);
    FAIL() << "another campaign's result was loaded";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("another campaign's result"), std::string::npos)
        << e.what();
  }
  // Not one of the campaign's trials at all.
  std::vector<TrialSpec> fewer(specs.begin() + 1, specs.end());
  EXPECT_THROW(store.load(fewer), FormatError);

  std::atomic<int> calls{0};
  LocalRunner(
      store,
      [&](const TrialSpec& t, TrialResult& r) {
        ++calls;
        fakeTrial(t, r);
      },
      1)
      .run(specs);
  EXPECT_EQ(calls.load(), 3);
  EXPECT_EQ(store.status(specs).done, specs.size());
  EXPECT_EQ(store.load(specs).size(), specs.size());
}

TEST_F(CampaignResultsTest, TrialFilesWithWrongTypesOrImpossibleValuesAreRefusedByName)
{
  const std::vector<TrialSpec> specs = expandCampaign(smallCampaign());
  const ResultStore store(dir_);
  store.create("x", "f");
  TrialResult r;
  fakeTrial(specs[0], r);
  store.writeResult(specs[0], r);
  const fs::path file = store.resultPath(specs[0].id);
  const std::string good = slurp(file);
  ASSERT_NO_THROW(ResultStore::loadFile(file));
  // Each edit replaces the first occurrence of a field's text; what the message names.
  const std::vector<std::tuple<std::string, std::string, std::string>> edits = {
      {"\"f1\": ", "\"f1\": \"high\", \"was\": ", "f1"},
      {"\"f1\": ", "\"f1\": 1.5, \"was\": ", "f1"},
      {"\"f1\": ", "\"f1\": -0.25, \"was\": ", "f1"},
      {"\"precision\": ", "\"precision\": true, \"was\": ", "precision"},
      {"\"recall\": ", "\"recall\": [0.5], \"was\": ", "recall"},
      {"\"chamfer\": ", "\"chamfer\": 1e308, \"was\": ", "chamfer"},
      {"\"chamfer\": ", "\"chamfer\": -1, \"was\": ", "chamfer"},
      {"\"status\": \"done\"", "\"status\": 3", "status"},
      {"\"status\": \"done\"", "\"status\": \"maybe\"", "status"},
      {"\"id\": ", "\"id\": 7, \"was\": ", "id"},
      {"\"yaw_deg\": ", "\"yaw_deg\": \"north\", \"was\": ", "yaw_deg"},
      {"\"planner\": ", "\"planner\": null, \"was\": ", "planner"},
      {"\"levels\": [", "\"levels\": [], \"was\": [", "levels"},
      {"\"fingerprint\": ", "\"fingerprint\": 12, \"was\": ", "fingerprint"},
  };
  for (const auto& [from, to, field] : edits) {
    std::string text = good;
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    std::ofstream(file) << text;
    try {
      ResultStore::loadFile(file);
      ADD_FAILURE() << "accepted: " << to;
    } catch (const FormatError& e) {
      EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  }
  // A done trial without views.
  std::string text = good;
  const std::size_t views = text.find("\"views\": [");
  const std::size_t end = text.find("\n  ],", views);
  ASSERT_NE(end, std::string::npos);
  text.replace(views, end + 4 - views, "\"views\": [],");
  std::ofstream(file) << text;
  EXPECT_THROW(ResultStore::loadFile(file), FormatError);
  // And the report reads no directory that holds such a file.
  EXPECT_THROW(store.load(), FormatError);
  // A directory named like a trial file, or a FIFO: refused by name, without blocking.
  fs::remove(file);
  fs::create_directories(file);
  EXPECT_THROW(store.state(specs[0]), IoError);
  EXPECT_THROW(store.load(), IoError);
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
/// A trial file by hand; `organs`, if given, holds per view the text of its "organs"
/// object.
void writeTrial(const fs::path& dir, const std::string& planner, int pattern,
                const std::string& plant, const std::vector<double>& f1,
                const std::vector<std::string>& chamfer,
                const std::vector<std::string>& organs = {})
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
        << ", \"f1\": " << f1[v] << ", \"chamfer\": " << chamfer[v] << "}}"
        << (organs.empty() ? "" : ", \"organs\": " + organs[v]) << "}";
  out << "]}\n";
}

} // namespace

TEST_F(CampaignResultsTest, TimingGivesEachPlannersMeanTimesAndShareOfItsDoneTrials)
{
  const std::vector<TrialSpec> specs = expandCampaign(smallCampaign());
  ASSERT_EQ(specs.size(), 12u);
  const ResultStore store(dir_);
  store.create("name: small\n", "f1");
  // Trial i: setup i, each of its 3 views plan 1, capture 2, insert 10 + i, eval 4,
  // total 100 + i.
  auto timed = [](std::size_t i) {
    TrialResult r;
    r.level_names = {"whole_plant"};
    for (int v = 0; v < 3; ++v) {
      TrialStep s;
      s.index = v;
      s.plan_ms = 1.0;
      s.capture_ms = 2.0;
      s.insert_ms = 10.0 + double(i);
      s.eval_ms = 4.0;
      LevelScore score;
      score.f1 = score.precision = score.recall = 0.5;
      s.scores = {score};
      r.steps.push_back(s);
    }
    r.setup_ms = double(i);
    r.total_ms = 100.0 + double(i);
    return r;
  };
  for (std::size_t i = 0; i < 6; ++i)
    store.writeResult(specs[i], timed(i));
  store.writeFailure(specs[6], "boom"); // failed, missing and foreign trials: left out
  const std::string foreign = store.resultPath(specs[7].id).string();
  store.writeResult(specs[7], timed(7));
  std::string text = slurp(foreign);
  text.replace(text.find(specs[7].fingerprint), specs[7].fingerprint.size(), "other");
  std::ofstream(foreign) << text;
  // A view's time that is not one: the trial's times are incomplete (its scores stay).
  store.writeResult(specs[8], timed(8));
  text = slurp(store.resultPath(specs[8].id));
  const std::string insert_ms = "\"insert_ms\": 18";
  const std::size_t at = text.find(insert_ms);
  ASSERT_NE(at, std::string::npos) << text;
  text.replace(at, insert_ms.size(), "\"insert_ms\": -18");
  std::ofstream(store.resultPath(specs[8].id)) << text;

  const std::vector<StoredTrial> trials = store.loadDone(specs);
  ASSERT_EQ(trials.size(), 7u); // 0-5 and 8
  EXPECT_EQ(trials[6].id, specs[8].id);
  EXPECT_EQ(trials[0].times.setup_ms, 0.0);
  EXPECT_EQ(trials[0].times.plan_ms, 3.0);
  EXPECT_EQ(trials[0].times.capture_ms, 6.0);
  EXPECT_EQ(trials[1].times.insert_ms, 33.0);
  EXPECT_EQ(trials[0].times.eval_ms, 12.0);
  EXPECT_EQ(trials[1].times.total_ms, 101.0);
  EXPECT_TRUE(trials[0].times.complete());
  EXPECT_TRUE(std::isnan(trials[6].times.insert_ms));
  EXPECT_FALSE(trials[6].times.complete());
  EXPECT_DOUBLE_EQ(trials[6].views[0][0].f1, 0.5);

  // Trials 0-3 are nbv-leaf-nodes' (totals 100-103: 406), 4 and 5 predefined's (104,
  // 105: 209), of 615 ms in all.
  for (std::size_t i = 0; i < 6; ++i)
    ASSERT_EQ(specs[i].planner, i < 4 ? "nbv-leaf-nodes" : "predefined") << i;
  const std::vector<TimingRow> rows = campaignTiming(trials);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].planner, "nbv-leaf-nodes");
  EXPECT_EQ(rows[0].study, "main");
  EXPECT_EQ(rows[0].trials, 4u);
  EXPECT_DOUBLE_EQ(rows[0].mean.setup_ms, 1.5);
  EXPECT_DOUBLE_EQ(rows[0].mean.plan_ms, 3.0);
  EXPECT_DOUBLE_EQ(rows[0].mean.insert_ms, 3.0 * (10.0 + 1.5));
  EXPECT_DOUBLE_EQ(rows[0].mean.total_ms, 101.5);
  EXPECT_DOUBLE_EQ(rows[0].share, 406.0 / 615.0);
  EXPECT_EQ(rows[1].planner, "predefined");
  EXPECT_EQ(rows[1].trials, 2u);
  EXPECT_DOUBLE_EQ(rows[1].mean.setup_ms, 4.5);
  EXPECT_DOUBLE_EQ(rows[1].mean.capture_ms, 6.0);
  EXPECT_DOUBLE_EQ(rows[1].mean.eval_ms, 12.0);
  EXPECT_DOUBLE_EQ(rows[1].mean.total_ms, 104.5);
  EXPECT_DOUBLE_EQ(rows[1].share, 209.0 / 615.0);
  EXPECT_TRUE(campaignTiming({}).empty());
}

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

TEST_F(CampaignResultsTest, ReportTablesTheRecallPerOrganOfTheOrgansThePlantsHave)
{
  fs::create_directories(dir_ / "trials");
  // Files as the first release with organs wrote them, without flower: not measured.
  auto organs = [](double stem, double leaflet) {
    std::ostringstream s;
    s << "{\"stem\": " << stem << ", \"petiole\": null, \"leaflet\": " << leaflet
      << ", \"peduncle\": null, \"fruit\": null}";
    return s.str();
  };
  const std::vector<double> f1 = {0.1, 0.2, 0.3, 0.4};
  const std::vector<std::string> chamfer(4, "0.01");
  writeTrial(dir_, "nbv-a", 0, "p1", f1, chamfer,
             {organs(0.1, 0.1), organs(0.3, 0.1), organs(0.5, 0.2), organs(0.7, 0.4)});
  writeTrial(dir_, "nbv-a", 0, "p2", f1, chamfer,
             {organs(0.1, 0.1), organs(0.3, 0.1), organs(0.7, 0.2), organs(0.9, 0.2)});
  writeTrial(dir_, "random", 0, "p1", f1, chamfer); // a file without organ recall
  const std::vector<StoredTrial> trials = ResultStore(dir_).load();
  for (const StoredTrial& t : trials)
    ASSERT_EQ(t.organ_recall.size(), t.planner == "random" ? 0u : 4u) << t.id;
  writeCampaignReport(trials, dir_ / "report", "organs");
  const std::string summary = slurp(dir_ / "report" / "summary.md");
  // After 3 views: stem (0.5 + 0.7) / 2, leaflet 0.2; after the last: 0.8 and 0.3. The
  // organs no plant has get no column.
  EXPECT_NE(summary.find("| planner | stem | leaflet |\n"), std::string::npos) << summary;
  EXPECT_NE(summary.find("| nbv-a | 0.600 / 0.800 | 0.200 / 0.300 |"), std::string::npos)
      << summary;
  EXPECT_NE(summary.find("| random | - / - | - / - |"), std::string::npos) << summary;
}

TEST_F(CampaignResultsTest, ReportListsOnlyThePaperRowsThatRanAndNoEmptySection)
{
  // Two of the paper's planners on one level: 3 of its 30 rows ran.
  const fs::path paper = dir_ / "paper";
  fs::create_directories(paper / "trials");
  for (const char* plant : {"p1", "p2"}) {
    writeTrial(paper, "nbv-whole-plant", 0, plant, {0.5, 0.85, 0.95},
               {"0.01", "0.01", "0.01"});
    writeTrial(paper, "random", 0, plant, {0.4, 0.6, 0.85}, {"0.01", "0.01", "0.01"});
  }
  writeCampaignReport(ResultStore(paper).load(), paper / "report", "two planners");
  const std::string summary = slurp(paper / "report" / "summary.md");
  // Gain at 3 views: (0.95 - 0.85) / 0.85 = +11.8%, 10.0 points.
  const std::string paper_section =
      "\n## The paper's numbers beside ours\n\n"
      "Paper: Burusa et al., section 4 (10 plants x 12 yaws). Ours: study main, mean "
      "curve. The paper does not say whether its F1 gains are relative or percentage "
      "points: both of ours are given.\n\n"
      "27 of the paper's 30 rows have no trial in this campaign (the planner, its "
      "baseline or the level is not in study main) and are left out.\n\n"
      "| level | planner | quantity | paper | ours |\n"
      "|---|---|---|---|---|\n"
      "| whole_plant | nbv-whole-plant | views to F1 0.8 | 3 | 2 |\n"
      "| whole_plant | random | views to F1 0.8 | 4 | 3 |\n"
      "| whole_plant | nbv-whole-plant | F1 gain at 3 views vs random | +5.3% | +11.8% "
      "(10.0 points) |\n";
  ASSERT_GE(summary.size(), paper_section.size()) << summary;
  EXPECT_EQ(summary.substr(summary.size() - paper_section.size()), paper_section)
      << summary;
  EXPECT_EQ(summary.find("not run"), std::string::npos) << summary;
  EXPECT_NE(summary.find("## F1 gain of the NBV planners after 3 views (study main)\n\n"
                         "Relative gain of the mean F1, (NBV - baseline) / baseline, and "
                         "in brackets the difference in percentage points.\n\n"
                         "| planner | baseline | whole_plant |\n|---|---|---|\n"
                         "| nbv-whole-plant | random | +11.8% (10.0) |\n"),
            std::string::npos)
      << summary;
  // No sensitivity study: no heading for one.
  EXPECT_EQ(summary.find("## Sensitivity studies"), std::string::npos) << summary;

  // A planner of the user's own only: no gain, no sensitivity study, none of the paper's
  // rows. Only the section with rows is written.
  const fs::path mine = dir_ / "mine";
  fs::create_directories(mine / "trials");
  for (const char* plant : {"p1", "p2"})
    writeTrial(mine, "nbv-mine", 0, plant, {0.5, 0.85, 0.95}, {"0.01", "0.01", "0.01"});
  writeCampaignReport(ResultStore(mine).load(), mine / "report", "mine");
  EXPECT_EQ(slurp(mine / "report" / "summary.md"),
            "# mine\n\n"
            "2 trials done, 0 failed (left out). Samples: one per plant, yaw and "
            "repetition; the patterns of a pre-defined planner are averaged into one "
            "sample. Views count v0.\n\n"
            "## Views to reach F1 0.8 / 0.9\n\n"
            "From the mean F1 curve, and in brackets the median over samples (`-`: the "
            "mean curve never reaches it; `>N`: more than half of the samples never do "
            "within N views).\n\n"
            "### main\n\n"
            "| planner | n | whole_plant |\n"
            "|---|---|---|\n"
            "| nbv-mine | 2 | 2 / 3 (median 2 / 3) |\n");
}
