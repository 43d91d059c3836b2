#include <algorithm>
#include <cmath>
#include <thread>
#include <tuple>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/trial.h>
#include <plantnbv/scenario/campaign_file.h>

#include "scenario_test_util.h"

using namespace plantnbv;
using namespace plantnbv::scenario;
using plantnbv::test::errorOf;
using plantnbv::test::ScenarioFiles;

namespace {

const std::string kHead = "name: t\nplants: [{seed: 0}]\nyaws_deg: [0]\nviews: 2\n";

} // namespace

TEST(CampaignFile, EverySpellingOfAKindIsOnePlanner)
{
  const CampaignFile f =
      parseCampaignFile(kHead + "levels: [whole-plant, fruits, leaf_nodes]\n"
                                "studies:\n  - name: a\n    planners:\n"
                                "      - {type: nbv, attention: leaf-nodes}\n"
                                "  - name: b\n    planners:\n"
                                "      - {type: nbv, attention: leaf_nodes}\n",
                        "dir/t.yaml");
  const CampaignDefinition& d = f.definition;
  EXPECT_EQ(d.levels, (std::vector<std::string>{"whole_plant", "fruit", "leaf_nodes"}));
  ASSERT_EQ(d.studies.size(), 2u);
  EXPECT_EQ(d.studies[0].planners[0].name, "nbv-leaf-nodes");
  EXPECT_EQ(d.studies[1].planners[0].name, "nbv-leaf-nodes");
  // Kept as written: trial files record the attention so.
  EXPECT_EQ(d.studies[0].planners[0].attention, "leaf-nodes");
  EXPECT_EQ(f.base_dir, "dir");
}

TEST(CampaignFile, TrialConfigsComeFromTheSpec)
{
  const CampaignFile f = parseCampaignFile(
      kHead +
          "candidates: 45\nresolution: 0.005\ntrial: {gain: {rays_x: 32}}\n"
          "studies:\n  - name: main\n    planners: [{type: predefined, patterns: [3]}]\n",
      "t.yaml");
  const std::vector<TrialSpec> specs = expandCampaign(f.definition);
  ASSERT_EQ(specs.size(), 1u);
  const TrialConfig c = campaignTrialConfig(f, specs[0]);
  EXPECT_EQ(c.planner, PlannerKind::predefined);
  EXPECT_EQ(c.pattern, 3);
  EXPECT_EQ(c.views, 2);
  EXPECT_EQ(c.samples_per_cell, 5);
  EXPECT_EQ(c.map.resolution_m, 0.005);
  EXPECT_EQ(c.gain.rays_x, 32);
  EXPECT_EQ(c.seed, specs[0].seed);
  EXPECT_EQ(c.threads, 1);
}

TEST(CampaignFile, AnNbvPlannerCanHaveANoisyRoiSourceThatNamesItAndReachesItsTrials)
{
  const CampaignFile f = parseCampaignFile(
      kHead +
          "trial: {roi_source: noisy, roi_sigma: 0.002}\n"
          "studies:\n  - name: main\n    planners:\n"
          "      - {type: nbv, attention: leaf-nodes, roi_source: noisy, roi_sigma: "
          "0.01}\n"
          "      - {type: nbv, attention: leaf-nodes, roi_source: noisy, roi_scale: 2}\n"
          "      - {type: nbv, attention: main-stem}\n"
          "      - {type: nbv, attention: main-stem, roi_source: oracle, name: truth}\n"
          "      - {type: nbv, attention: leaf-nodes, roi_source: detections, "
          "detector_recall: 0.8, detector_false_positives: 1}\n"
          "      - {type: random}\n"
          "      - {type: nbv, attention: leaf-nodes, roi_source: detections, "
          "detector_box_jitter: 2, detector_mask_dilation: -1, detector_masks: false, "
          "detections_explore_views: 0}\n",
      "t.yaml");
  const std::vector<TrialSpec> specs = expandCampaign(f.definition);
  ASSERT_EQ(specs.size(), 7u);
  EXPECT_EQ(specs[6].planner,
            "nbv-leaf-nodes-detections-jitter2px-dilation-1px-boxes-explore0");
  const TrialConfig c6 = campaignTrialConfig(f, specs[6]);
  EXPECT_EQ(c6.roi_source.detector_box_jitter_px, 2.0);
  EXPECT_EQ(c6.roi_source.detector_mask_dilation_px, -1);
  EXPECT_FALSE(c6.roi_source.detector_masks);
  EXPECT_EQ(c6.roi_source.detections_explore_views, 0);
  EXPECT_EQ(campaignTrialConfig(f, specs[4]).roi_source.detections_explore_views, 1);
  EXPECT_EQ(specs[4].planner, "nbv-leaf-nodes-detections-recall0.8-fp1");
  const TrialConfig c4 = campaignTrialConfig(f, specs[4]);
  EXPECT_EQ(c4.roi_source.kind, RoiSourceKind::detections);
  EXPECT_EQ(c4.roi_source.detector_recall, 0.8);
  EXPECT_EQ(c4.roi_source.detector_false_positives, 1.0);
  EXPECT_EQ(specs[0].planner, "nbv-leaf-nodes-noisy10mm");
  EXPECT_EQ(specs[1].planner, "nbv-leaf-nodes-noisy0mm-x2");
  EXPECT_EQ(specs[2].planner, "nbv-main-stem");
  const TrialConfig c0 = campaignTrialConfig(f, specs[0]);
  EXPECT_EQ(c0.roi_source.kind, RoiSourceKind::noisy);
  EXPECT_EQ(c0.roi_source.sigma_m, 0.01);
  const TrialConfig c1 = campaignTrialConfig(f, specs[1]);
  EXPECT_EQ(c1.roi_source.sigma_m, 0.0);
  EXPECT_EQ(c1.roi_source.scale, 2.0);
  // Without keys of its own, a planner keeps the trial section's source.
  EXPECT_EQ(campaignTrialConfig(f, specs[2]).roi_source.sigma_m, 0.002);
  EXPECT_EQ(campaignTrialConfig(f, specs[3]).roi_source.kind, RoiSourceKind::oracle);

  const std::string head = kHead + "studies:\n  - name: main\n    planners: ";
  EXPECT_EQ(errorOf([&] {
              parseCampaignFile(head + "[{type: random, roi_source: noisy}]\n", "t.yaml");
            }),
            "'t.yaml' studies[0].planners[0].roi_source: only an NBV planner has an ROI "
            "source");
  EXPECT_EQ(errorOf([&] {
              parseCampaignFile(
                  head + "[{type: nbv, attention: leaf-nodes, roi_sigma: 0.01}]\n",
                  "t.yaml");
            }),
            "'t.yaml' studies[0].planners[0]: roi_sigma 0.01: only the noisy ROI source "
            "uses it (roi_source is oracle)");
  EXPECT_EQ(errorOf([&] {
              parseCampaignFile(head + "[{type: nbv, attention: leaf-nodes, roi_source: "
                                       "noisy, roi_sigma: -1}]\n",
                                "t.yaml");
            }),
            "'t.yaml' studies[0].planners[0]: roi_sigma -1: expected a finite value >= 0 "
            "(metres)");
}

TEST(CampaignFile, ErrorsNameTheKeyPath)
{
  const std::string studies =
      "studies:\n  - name: main\n    planners: [{type: random}]\n";
  EXPECT_EQ(
      errorOf([&] { parseCampaignFile(kHead + "candidates: 10\n" + studies, "t.yaml"); }),
      "'t.yaml' candidates 10: expected a multiple of the 9 grid cells (9, 27, 45, "
      "...)");
  EXPECT_EQ(
      errorOf(
          [&] { parseCampaignFile(kHead + "levels: [leaves]\n" + studies, "t.yaml"); }),
      "'t.yaml' levels[0]: unknown level 'leaves' (expected whole_plant, main_stem, "
      "leaf_nodes, fruit or model_rois)");
  EXPECT_EQ(errorOf([&] {
              parseCampaignFile(
                  "name: t\nplants: [{model: m.dae, stage: 0.5}]\n" + studies, "t.yaml");
            }),
            "'t.yaml' plants[0].stage: only a generated plant has a growth stage");
  EXPECT_EQ(errorOf([&] {
              parseCampaignFile(kHead + "studies:\n  - name: main\n    planners: "
                                        "[{type: nbv, attention: stems}]\n",
                                "t.yaml");
            }),
            "'t.yaml' studies[0].planners[0].attention: unknown ROI 'stems' (expected "
            "whole_plant, main_stem, leaf_nodes, fruit or an ROI file, .yaml)");
  EXPECT_THROW(loadCampaignFile("/nonexistent/campaign.yaml"), IoError);
}

TEST(CampaignFile, TrialFingerprintsFollowTheContentNotTheText)
{
  const std::string studies =
      "studies:\n  - name: main\n    planners: [{type: random}]\n";
  const auto fingerprint = [](const std::string& text) {
    return expandCampaign(parseCampaignFile(text, "t.yaml").definition)[0].fingerprint;
  };
  const std::string a = fingerprint(kHead + "trial: {gain: {rays_x: 32}}\n" + studies);
  EXPECT_EQ(a.size(), 16u);
  // Comments, key order, quoting and flow or block style change nothing.
  EXPECT_EQ(a, fingerprint("# mine\n" + studies + "trial:\n  gain:\n    rays_x: '32'\n" +
                           kHead));
  // What the trials are run with does: the trial config, the plants, the seed, views.
  EXPECT_NE(a, fingerprint(kHead + "trial: {gain: {rays_x: 48}}\n" + studies));
  EXPECT_NE(a, fingerprint(kHead + "trial: {gain: {rays_x: 32}}\nseed: 9\n" + studies));
  EXPECT_NE(a, fingerprint("name: t\nplants: [{seed: 1}]\nyaws_deg: [0]\nviews: 2\n"
                           "trial: {gain: {rays_x: 32}}\n" +
                           studies));
}

// The same file read over other built-in defaults (as a plantnbv whose defaults
// changed reads it) is another campaign: its trials do not take the old results.
TEST(CampaignFile, FingerprintsFollowTheBuiltInDefaultsToo)
{
  const std::string text =
      kHead +
      "studies:\n  - name: main\n    planners: [{type: nbv, attention: leaf_nodes}]\n";
  const auto fingerprint = [&](const TrialConfig& defaults) {
    const CampaignFile f = parseCampaignFile(text, "t.yaml", defaults);
    return std::make_pair(f.definition.content_fingerprint,
                          expandCampaign(f.definition)[0].fingerprint);
  };
  const auto ours = fingerprint(TrialConfig());
  EXPECT_EQ(ours, fingerprint(TrialConfig()));
  TrialConfig paper_planner;
  paper_planner.view_spacing_m = 0.0;
  const auto other = fingerprint(paper_planner);
  EXPECT_NE(ours.first, other.first);
  EXPECT_NE(ours.second, other.second);
  // A default the file sets itself does not matter.
  const std::string pinned =
      kHead + "trial: {view_spacing: 0}\n" +
      "studies:\n  - name: main\n    planners: [{type: nbv, attention: leaf_nodes}]\n";
  EXPECT_EQ(
      parseCampaignFile(pinned, "t.yaml").definition.content_fingerprint,
      parseCampaignFile(pinned, "t.yaml", paper_planner).definition.content_fingerprint);
}

// A model kept in its file's frame (keep_frame) stands where the file puts it in every
// trial, so that boxes drawn in that frame (the ROI viewpoint planner's) match it.
TEST_F(ScenarioFiles, AModelKeptInItsFilesFrameStaysThereInItsTrials)
{
  // A 0.5 m triangle standing at x = 2 in its file.
  write("far.obj", "o Stem\nv 2 0 0.1\nv 2.05 0 0.1\nv 2 0 0.6\nf 1 2 3\n");
  write("far_rois.yaml", "- {min: [1.9, -0.1, 0.1], max: [2.1, 0.1, 0.6]}\n");
  const std::string studies =
      "views: 2\ncandidates: 9\nstudies:\n  - name: main\n    planners: [{type: "
      "predefined, patterns: [1]}]\n";
  const std::string path =
      write("c.yaml", "name: t\nplants: [{model: far.obj, keep_frame: true, rois: "
                      "far_rois.yaml}]\nyaws_deg: [0]\n" +
                          studies);
  const CampaignFile f = loadCampaignFile(path);
  EXPECT_TRUE(f.definition.plants[0].keep_frame);
  TrialResult result;
  runCampaignTrial(f, expandCampaign(f.definition).at(0), result);
  ASSERT_EQ(result.steps.size(), 2u);
  // The sector is around the model where its file has it (bottom-face centre x = 2.025),
  // not at the default base (1, 0, 0.8); the user's boxes are scored as model_rois.
  const Eigen::Vector3d& p = result.steps[1].view.position;
  EXPECT_NEAR(std::hypot(p.x() - 2.025, p.y()), 0.4, 1e-6) << p.transpose();
  const auto& names = result.level_names;
  EXPECT_NE(std::find(names.begin(), names.end(), "model_rois"), names.end());

  EXPECT_EQ(errorOf([&] {
              parseCampaignFile("name: t\nplants: [{model: far.obj, keep_frame: true}]\n"
                                "yaws_deg: [0, 90]\n" +
                                    studies,
                                path);
            }),
            "'" + path +
                "' plants[0].keep_frame: a plant kept in its file's frame is not turned: "
                "yaws_deg must be [0]");
  EXPECT_EQ(errorOf([] {
              parseCampaignFile("name: t\nplants: [{seed: 0, keep_frame: true}]\n",
                                "t.yaml");
            }),
            "'t.yaml' plants[0].keep_frame: a generated plant has no file frame to keep");
}

TEST_F(ScenarioFiles, AModelsScaleAndSectorRadiusReachItsTrials)
{
  // A 1 m tall triangle in centimetres, y up; its views 0.55 m from its axis.
  write("tall.obj", "o Stem\nv 0 0 0\nv 5 0 0\nv 0 100 0\nf 1 2 3\n");
  const std::string path =
      write("c.yaml", "name: t\nplants: [{model: tall.obj, scale: 0.01, up_axis: y, "
                      "sector_radius: 0.55}]\nyaws_deg: [0]\nviews: 2\ncandidates: 9\n"
                      "studies:\n  - name: main\n    planners: [{type: predefined, "
                      "patterns: [1]}]\n");
  const CampaignFile f = loadCampaignFile(path);
  EXPECT_EQ(f.definition.plants[0].scale, 0.01);
  EXPECT_EQ(f.definition.plants[0].sector_radius_m, 0.55);
  EXPECT_EQ(f.definition.plants[0].up_axis, "y");
  TrialResult result;
  runCampaignTrial(f, expandCampaign(f.definition).at(0), result);
  ASSERT_EQ(result.steps.size(), 2u);
  // v0 is Table 1's (0.5 m from the axis); the next view is a cell centre of the sector,
  // around the model's bottom-face centre at the default base (1, 0, 0.8).
  const Eigen::Vector3d& p = result.steps[1].view.position;
  EXPECT_NEAR(std::hypot(p.x() - 1.0, p.y()), 0.55, 1e-9) << p.transpose();
  EXPECT_NEAR(p.z(), 0.8 + 1.0 / 6.0,
              1e-7); // the bottom row of a sector 1 m (float) high

  EXPECT_EQ(errorOf([] {
              parseCampaignFile("name: t\nplants: [{seed: 0, scale: 0.01}]\n", "t.yaml");
            }),
            "'t.yaml' plants[0].scale: a scale belongs to a model file");
  EXPECT_EQ(errorOf([] {
              parseCampaignFile("name: t\nplants: [{seed: 0, up_axis: y}]\n", "t.yaml");
            }),
            "'t.yaml' plants[0].up_axis: an up axis belongs to a model file");
  EXPECT_EQ(errorOf([] {
              parseCampaignFile("name: t\nplants: [{model: a.obj, up_axis: Y_UP}]\n",
                                "t.yaml");
            }),
            "'t.yaml' plants[0].up_axis: 'Y_UP' is not file, y or z");
  EXPECT_EQ(errorOf([] {
              parseCampaignFile("name: t\nplants: [{seed: 0, sector_radius: 0}]\n",
                                "t.yaml");
            }),
            "'t.yaml' plants[0].sector_radius: 0 is not a radius in metres > 0");
}

namespace {

/// Everything of two trial results but their timings (NaN equals NaN).
void expectSameResults(const TrialResult& a, const TrialResult& b)
{
  const auto same = [](double x, double y) {
    return x == y || (std::isnan(x) && std::isnan(y));
  };
  ASSERT_EQ(a.steps.size(), b.steps.size());
  for (std::size_t i = 0; i < a.steps.size(); ++i) {
    const TrialStep& s = a.steps[i];
    const TrialStep& t = b.steps[i];
    EXPECT_EQ(s.view.position, t.view.position) << i;
    EXPECT_TRUE(same(s.gain, t.gain)) << i;
    EXPECT_EQ(s.occupied_voxels, t.occupied_voxels) << i;
    ASSERT_EQ(s.organs.size(), t.organs.size());
    for (std::size_t o = 0; o < s.organs.size(); ++o)
      EXPECT_TRUE(same(s.organs[o].recall, t.organs[o].recall)) << i;
    ASSERT_EQ(s.scores.size(), t.scores.size());
    for (std::size_t l = 0; l < s.scores.size(); ++l) {
      EXPECT_EQ(s.scores[l].f1, t.scores[l].f1) << i;
      EXPECT_EQ(s.scores[l].reconstruction_points, t.scores[l].reconstruction_points);
      EXPECT_TRUE(same(s.scores[l].chamfer, t.scores[l].chamfer)) << i;
    }
  }
}

} // namespace

TEST(CampaignFile, TrialsOfOnePlantAndPoseShareTheirSceneWithTheSameResults)
{
  const CampaignFile f = parseCampaignFile(
      "name: t\nplants: [{seed: 0}]\nyaws_deg: [0, 90]\nviews: 2\ncandidates: 9\n"
      "levels: [whole_plant, leaf_nodes]\n"
      "trial: {camera: '160x120:114.25,114.25,79.5,59.5', gain: {rays_x: 16, rays_y: "
      "12}}\n"
      "studies:\n"
      "  - name: main\n    planners: [{type: nbv, attention: leaf-nodes}, {type: "
      "random}, {type: predefined, patterns: [2]}]\n"
      "  - name: row\n    row_spacings: [0.3]\n    planners: [{type: random}]\n",
      "t.yaml");
  std::vector<TrialSpec> specs = expandCampaign(f.definition);
  ASSERT_EQ(specs.size(), 8u);
  // Grouped by plant, variant, yaw and row, in their order otherwise.
  std::vector<std::string> ids;
  for (const TrialSpec& t : specs)
    ids.push_back(t.id);
  groupTrialsByScene(specs);
  for (std::size_t i = 1; i < specs.size(); ++i)
    EXPECT_FALSE(std::tie(specs[i].yaw_deg, specs[i].row_spacing_m) <
                 std::tie(specs[i - 1].yaw_deg, specs[i - 1].row_spacing_m))
        << specs[i].id;
  for (std::size_t i = 1; i < specs.size(); ++i) {
    if (specs[i].yaw_deg == specs[i - 1].yaw_deg &&
        specs[i].row_spacing_m == specs[i - 1].row_spacing_m) {
      EXPECT_LT(std::find(ids.begin(), ids.end(), specs[i - 1].id),
                std::find(ids.begin(), ids.end(), specs[i].id));
    }
  }

  // Four scenes (two yaws, alone and in a row), each made once; every trial as without.
  // The baselines of a yaw attend to the whole plant: the second starts from the
  // first's v0 (no capture).
  CampaignSceneCache cache(2);
  std::size_t v0_shared = 0;
  for (const TrialSpec& t : specs) {
    TrialResult own, shared;
    runCampaignTrial(f, t, own);
    runCampaignTrial(f, t, shared, &cache);
    SCOPED_TRACE(t.id);
    expectSameResults(own, shared);
    EXPECT_GT(own.steps.at(0).capture_ms, 0.0);
    v0_shared += shared.steps.at(0).capture_ms == 0.0;
  }
  EXPECT_EQ(cache.builds(), 4u);
  EXPECT_EQ(v0_shared, 2u);
  // Ungrouped, with room for one scene, each change of scene makes it again.
  CampaignSceneCache one(1);
  const std::vector<TrialSpec> in_file_order = expandCampaign(f.definition);
  std::size_t changes = 1;
  for (std::size_t i = 0; i < in_file_order.size(); ++i) {
    TrialResult result;
    runCampaignTrial(f, in_file_order[i], result, &one);
    if (i > 0 && (in_file_order[i].yaw_deg != in_file_order[i - 1].yaw_deg ||
                  in_file_order[i].row_spacing_m != in_file_order[i - 1].row_spacing_m))
      ++changes;
  }
  EXPECT_GT(changes, 4u);
  EXPECT_EQ(one.builds(), changes);
  EXPECT_THROW(CampaignSceneCache(0), InvalidArgumentError);
}

TEST(CampaignFile, WorkersAskingForOneSceneTogetherWaitForOneBuild)
{
  const CampaignFile f = parseCampaignFile(
      kHead + "studies:\n  - name: main\n    planners: [{type: random}]\n", "t.yaml");
  const TrialSpec t = expandCampaign(f.definition).at(0);
  const TrialConfig config = campaignTrialConfig(f, t);
  CampaignSceneCache cache(1);
  std::vector<std::shared_ptr<const CampaignSceneCache::Entry>> got(4);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < got.size(); ++i)
    threads.emplace_back([&, i] { got[i] = cache.get(f, t, config); });
  for (std::thread& thread : threads)
    thread.join();
  EXPECT_EQ(cache.builds(), 1u);
  for (const auto& entry : got) {
    ASSERT_NE(entry, nullptr);
    EXPECT_EQ(entry, got[0]);
    EXPECT_NE(entry->scene, nullptr);
    EXPECT_FALSE(entry->placed.plant.mesh.empty());
  }
}
