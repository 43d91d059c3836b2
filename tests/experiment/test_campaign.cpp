// Campaign expansion: counts, stable readable ids, seeds independent of order, and
// invalid definitions named by their field path.

#include <algorithm>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/experiment/campaign.h>

using namespace plantnbv;

namespace {

CampaignPlanner nbv(const std::string& attention)
{
  return {"nbv-" + attention, PlannerKind::nbv, attention, {}, {}};
}

/// The paper's study: 10 plants x 12 yaws; main with 5 planners (predefined: 4 patterns),
/// three sensitivity studies of the 3 NBV planners.
CampaignDefinition paperLike()
{
  CampaignDefinition d;
  d.name = "paper";
  d.seed = 2023;
  for (int s = 0; s < 10; ++s) {
    CampaignPlant p;
    p.seed = s;
    p.name = "plant0" + std::to_string(s);
    d.plants.push_back(p);
  }
  d.yaws_deg.clear();
  for (int y = 0; y < 360; y += 30)
    d.yaws_deg.push_back(y);
  const std::vector<CampaignPlanner> nbvs{nbv("whole-plant"), nbv("main-stem"),
                                          nbv("leaf-nodes")};
  CampaignStudy main{"main", nbvs, {}, {}, {}, {}};
  main.planners.push_back({"predefined", PlannerKind::predefined, "", {1, 2, 3, 4}, {}});
  main.planners.push_back({"random", PlannerKind::random, "", {}, {}});
  d.studies = {main,
               {"occlusion", nbvs, {true}, {}, {}, {}},
               {"candidates", nbvs, {}, {9, 45}, {}, {}},
               {"resolution", nbvs, {}, {}, {0.005, 0.007}, {}}};
  return d;
}

} // namespace

TEST(Campaign, PaperStudyExpandsToTheExpectedTrials)
{
  const std::vector<TrialSpec> specs = expandCampaign(paperLike());
  std::map<std::string, int> per_study;
  for (const TrialSpec& t : specs)
    ++per_study[t.study];
  EXPECT_EQ(per_study["main"], 10 * 12 * (3 + 4 + 1));
  EXPECT_EQ(per_study["occlusion"], 10 * 12 * 3);
  EXPECT_EQ(per_study["candidates"], 10 * 12 * 3 * 2);
  EXPECT_EQ(per_study["resolution"], 10 * 12 * 3 * 2);
  EXPECT_EQ(specs.size(), 2760u);

  std::set<std::string> ids;
  for (const TrialSpec& t : specs)
    EXPECT_TRUE(ids.insert(t.id).second) << t.id;

  auto find = [&](const std::string& id) {
    const auto it = std::find_if(specs.begin(), specs.end(),
                                 [&](const TrialSpec& t) { return t.id == id; });
    EXPECT_NE(it, specs.end()) << id;
    return it == specs.end() ? TrialSpec{} : *it;
  };
  const TrialSpec leaf = find("main/nbv-leaf-nodes/plant03/yaw090/rep0");
  EXPECT_EQ(leaf.kind, PlannerKind::nbv);
  EXPECT_EQ(leaf.attention, "leaf-nodes");
  EXPECT_EQ(leaf.plant_index, 3u);
  EXPECT_EQ(leaf.yaw_deg, 90.0);
  EXPECT_EQ(leaf.candidates, 27);
  EXPECT_EQ(leaf.resolution_m, 0.003);
  EXPECT_EQ(leaf.seed, deriveSeed(2023, trialIdHash(leaf.id)));
  const TrialSpec pre = find("main/predefined-p2/plant00/yaw330/rep0");
  EXPECT_EQ(pre.kind, PlannerKind::predefined);
  EXPECT_EQ(pre.pattern, 2);
  EXPECT_EQ(pre.planner, "predefined"); // the report averages the patterns as one planner
  const TrialSpec c45 = find("candidates/nbv-main-stem/c45/plant09/yaw000/rep0");
  EXPECT_EQ(c45.candidates, 45);
  EXPECT_EQ(c45.variant, "c45");
  EXPECT_EQ(find("resolution/nbv-whole-plant/res7mm/plant01/yaw060/rep0").resolution_m,
            0.007);
  EXPECT_TRUE(find("occlusion/nbv-leaf-nodes/simplified/plant01/yaw060/rep0").simplified);
}

TEST(Campaign, IdsAndSeedsDoNotDependOnOrder)
{
  const CampaignDefinition d = paperLike();
  CampaignDefinition shuffled = d;
  std::reverse(shuffled.plants.begin(), shuffled.plants.end());
  std::reverse(shuffled.yaws_deg.begin(), shuffled.yaws_deg.end());
  std::reverse(shuffled.studies.begin(), shuffled.studies.end());
  for (CampaignStudy& s : shuffled.studies)
    std::reverse(s.planners.begin(), s.planners.end());
  std::map<std::string, std::uint64_t> seeds;
  for (const TrialSpec& t : expandCampaign(d))
    seeds[t.id] = t.seed;
  const std::vector<TrialSpec> other = expandCampaign(shuffled);
  ASSERT_EQ(other.size(), seeds.size());
  std::set<std::uint64_t> distinct;
  for (const TrialSpec& t : other) {
    ASSERT_EQ(seeds.count(t.id), 1u) << t.id;
    EXPECT_EQ(seeds[t.id], t.seed) << t.id;
    distinct.insert(t.seed);
  }
  EXPECT_EQ(distinct.size(), other.size());
  // Same definition, same list in the same order.
  const std::vector<TrialSpec> again = expandCampaign(d);
  const std::vector<TrialSpec> first = expandCampaign(d);
  for (std::size_t i = 0; i < first.size(); ++i)
    EXPECT_EQ(first[i].id, again[i].id);
  // Another campaign seed: other trial seeds.
  CampaignDefinition reseeded = d;
  reseeded.seed = 1;
  EXPECT_NE(expandCampaign(reseeded)[0].seed, expandCampaign(d)[0].seed);
}

TEST(Campaign, RepetitionsAndFractionalYawsHaveTheirOwnIds)
{
  CampaignDefinition d = paperLike();
  d.plants.resize(1);
  d.yaws_deg = {-30, 12.5};
  d.repetitions = 2;
  d.studies.resize(1);
  d.studies[0].planners = {{"random", PlannerKind::random, "", {}, {}}};
  const std::vector<TrialSpec> specs = expandCampaign(d);
  std::vector<std::string> ids;
  for (const TrialSpec& t : specs)
    ids.push_back(t.id);
  EXPECT_EQ(ids, (std::vector<std::string>{"main/random/plant00/yaw-30/rep0",
                                           "main/random/plant00/yaw-30/rep1",
                                           "main/random/plant00/yaw12.5/rep0",
                                           "main/random/plant00/yaw12.5/rep1"}));
  EXPECT_NE(specs[0].seed, specs[1].seed);
}

TEST(Campaign, RowSpacingsAreVariantsOfTheirStudy)
{
  CampaignDefinition d = paperLike();
  d.plants.resize(1);
  d.yaws_deg = {0};
  d.studies.resize(1);
  d.studies[0].name = "row";
  d.studies[0].planners = {{"random", PlannerKind::random, "", {}, {}}};
  d.studies[0].row_spacings_m = {0.0, 0.4, 0.25};
  const std::vector<TrialSpec> specs = expandCampaign(d);
  ASSERT_EQ(specs.size(), 3u);
  EXPECT_EQ(specs[0].id, "row/random/alone/plant00/yaw000/rep0");
  EXPECT_EQ(specs[1].id, "row/random/row40cm/plant00/yaw000/rep0");
  EXPECT_EQ(specs[2].id, "row/random/row25cm/plant00/yaw000/rep0");
  EXPECT_EQ(specs[0].row_spacing_m, 0.0);
  EXPECT_EQ(specs[2].row_spacing_m, 0.25);
  EXPECT_EQ(specs[2].variant, "row25cm");

  d.studies[0].row_spacings_m = {0.4, -0.1};
  EXPECT_THROW(
      {
        try {
          expandCampaign(d);
        } catch (const InvalidArgumentError& e) {
          EXPECT_NE(std::string(e.what()).find("studies[0].row_spacings[1]"),
                    std::string::npos)
              << e.what();
          throw;
        }
      },
      InvalidArgumentError);
  d.studies[0].row_spacings_m = {0.4, 0.4};
  EXPECT_THROW(expandCampaign(d), InvalidArgumentError);
}

TEST(Campaign, InvalidDefinitionsNameTheField)
{
  auto expectError = [](const CampaignDefinition& d, const std::string& needle) {
    try {
      expandCampaign(d);
      ADD_FAILURE() << "no error for " << needle;
    } catch (const InvalidArgumentError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  CampaignDefinition d = paperLike();
  d.views = 0;
  expectError(d, "views");
  d = paperLike();
  d.studies[0].planners[3].patterns = {1, 5};
  expectError(d, "studies[0].planners[3].patterns[1]");
  d = paperLike();
  d.studies[2].candidates = {9, 0};
  expectError(d, "studies[2].candidates[1]");
  d = paperLike();
  d.studies[1].name = "main";
  expectError(d, "studies[1].name");
  d = paperLike();
  d.plants[2].name = "plant01";
  expectError(d, "plants[2].name");
  d = paperLike();
  d.studies[0].planners[0].attention.clear();
  expectError(d, "studies[0].planners[0].attention");
  d = paperLike();
  d.plants[0].model = "tomato.dae";
  expectError(d, "plants[0]");
  d = paperLike();
  d.studies[0].planners[1].name = "a/b";
  expectError(d, "studies[0].planners[1].name");
  d = paperLike();
  d.yaws_deg = {0, 0};
  expectError(d, "yaws_deg[1]");
}
