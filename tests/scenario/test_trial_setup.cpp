#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/scenario/trial_setup.h>

#include "scenario_test_util.h"

using namespace plantnbv;
using namespace plantnbv::scenario;
using plantnbv::test::errorOf;

namespace {

const PlacedPlant& generatedPlant()
{
  static const PlacedPlant placed = [] {
    PlantSource source;
    source.seed = 8; // a plant with fruit
    return makePlacedPlant(source);
  }();
  return placed;
}

} // namespace

TEST(Attention, KindsInAnySpellingAndRoiFiles)
{
  EXPECT_EQ(Attention::parse("leaf-nodes").kind, RoiKind::leaf_nodes);
  EXPECT_EQ(Attention::parse("leaf_nodes").kind, RoiKind::leaf_nodes);
  EXPECT_EQ(Attention::parse("fruits").kind, RoiKind::fruit);
  EXPECT_EQ(Attention::parse("whole-plant").name(), "whole_plant");
  const Attention file = Attention::parse("my/rois.yaml");
  EXPECT_FALSE(file.kind);
  EXPECT_EQ(file.file, "my/rois.yaml");
  EXPECT_EQ(file.name(), "my/rois.yaml");
  const std::string msg = errorOf([] { Attention::parse("stems"); });
  EXPECT_EQ(msg,
            "unknown ROI 'stems' (expected whole_plant, main_stem, leaf_nodes, fruit "
            "or an ROI file, .yaml)");
}

TEST(Attention, PlannerNamesKeepThePapersSpelling)
{
  // Trial ids hold these names: every spelling of a kind gives the same one.
  EXPECT_EQ(nbvPlannerName(Attention::parse("leaf_nodes")), "nbv-leaf-nodes");
  EXPECT_EQ(nbvPlannerName(Attention::parse("leaf-nodes")), "nbv-leaf-nodes");
  EXPECT_EQ(nbvPlannerName(Attention::parse("whole_plant")), "nbv-whole-plant");
  EXPECT_EQ(nbvPlannerName(Attention::parse("fruits")), "nbv-fruit");
  EXPECT_EQ(nbvPlannerName(Attention::parse("boxes/my_rois.yaml")), "nbv-my_rois");
  // A noisy ROI source is part of the name: its sigma in mm, a scale other than 1.
  RoiSource noisy;
  noisy.kind = RoiSourceKind::noisy;
  EXPECT_EQ(nbvPlannerName(Attention::parse("leaf_nodes"), noisy),
            "nbv-leaf-nodes-noisy0mm");
  noisy.sigma_m = 0.005;
  EXPECT_EQ(nbvPlannerName(Attention::parse("main-stem"), noisy),
            "nbv-main-stem-noisy5mm");
  noisy.sigma_m = 0.0025;
  noisy.scale = 1.5;
  EXPECT_EQ(nbvPlannerName(Attention::parse("leaf_nodes"), noisy),
            "nbv-leaf-nodes-noisy2.5mm-x1.5");
  EXPECT_EQ(nbvPlannerName(Attention::parse("leaf_nodes"), RoiSource()),
            "nbv-leaf-nodes");
  RoiSource detections;
  detections.kind = RoiSourceKind::detections;
  EXPECT_EQ(nbvPlannerName(Attention::parse("leaf_nodes"), detections),
            "nbv-leaf-nodes-detections");
  detections.detector_recall = 0.8;
  detections.detector_false_positives = 2;
  EXPECT_EQ(nbvPlannerName(Attention::parse("leaf_nodes"), detections),
            "nbv-leaf-nodes-detections-recall0.8-fp2");
  detections.detections_explore_views = 0;
  EXPECT_EQ(nbvPlannerName(Attention::parse("leaf_nodes"), detections),
            "nbv-leaf-nodes-detections-recall0.8-fp2-explore0");
  RoiSource prior;
  prior.kind = RoiSourceKind::prior;
  EXPECT_EQ(nbvPlannerName(Attention::parse("leaf_nodes"), prior),
            "nbv-leaf-nodes-prior");
  prior.kind = RoiSourceKind::detections_prior;
  prior.detector_recall = 0.5;
  prior.prior_internode_m = 0.05;
  EXPECT_EQ(nbvPlannerName(Attention::parse("leaf_nodes"), prior),
            "nbv-leaf-nodes-detections-prior-recall0.5-internode50mm");
}

TEST(TrialSetup, RoiSourceOverridesNameTheOptionAndAnOracleDropsAConfigsNoise)
{
  RoiSource roi;
  RoiSourceOverrides o;
  o.source = "noisy";
  o.sigma_m = 0.01;
  o.applyTo(roi, "--");
  EXPECT_EQ(roi.kind, RoiSourceKind::noisy);
  EXPECT_EQ(roi.sigma_m, 0.01);
  EXPECT_EQ(roi.scale, 1.0);
  // --roi-source oracle over a config's noisy source: its sigma and scale go with it.
  RoiSourceOverrides oracle;
  oracle.source = "oracle";
  oracle.applyTo(roi, "--");
  EXPECT_EQ(roi.kind, RoiSourceKind::oracle);
  EXPECT_EQ(roi.sigma_m, 0.0);
  EXPECT_EQ(errorOf([] {
              RoiSource r;
              RoiSourceOverrides bad;
              bad.source = "detector";
              bad.applyTo(r, "--");
            }),
            "--roi-source: unknown ROI source 'detector' (expected oracle, noisy, "
            "detections, prior or detections+prior)");
  // --roi-source noisy over a config's detector: its recall goes with it.
  RoiSource detecting;
  detecting.kind = RoiSourceKind::detections;
  detecting.detector_recall = 0.5;
  RoiSourceOverrides noisy;
  noisy.source = "noisy";
  noisy.applyTo(detecting, "--");
  EXPECT_EQ(detecting.detector_recall, 1.0);
  EXPECT_EQ(errorOf([] {
              RoiSource r;
              RoiSourceOverrides bad;
              bad.source = "noisy";
              bad.detector_recall = 0.5;
              bad.applyTo(r, "--");
            }),
            "--detector-recall 0.5: only the detections and detections+prior ROI sources "
            "use it (--roi-source is noisy)");
  EXPECT_EQ(errorOf([] {
              RoiSource r;
              RoiSourceOverrides bad;
              bad.source = "detections";
              bad.detector_false_positives = -1;
              bad.applyTo(r, "");
            }),
            "detector_false_positives -1: expected a value in [0, 1000] per frame");
  EXPECT_EQ(
      errorOf([] {
        RoiSource r;
        RoiSourceOverrides bad;
        bad.sigma_m = 0.02;
        bad.applyTo(r, "--");
      }),
      "--roi-sigma 0.02: only the noisy ROI source uses it (--roi-source is oracle)");
  EXPECT_EQ(errorOf([] {
              RoiSource r;
              RoiSourceOverrides bad;
              bad.source = "noisy";
              bad.scale = -1.0;
              bad.applyTo(r, "");
            }),
            "roi_scale -1: expected a finite value > 0");
}

TEST(TrialSetup, AGeneratedPlantHasEveryLevelInTheStudysOrder)
{
  const PlacedPlant& placed = generatedPlant();
  const std::vector<EvaluationLevel> levels = evaluationLevels(placed);
  ASSERT_EQ(levels.size(), 4u);
  const char* names[] = {"whole_plant", "main_stem", "leaf_nodes", "fruit"};
  const bool apart[] = {false, false, true, true};
  for (std::size_t i = 0; i < levels.size(); ++i) {
    EXPECT_EQ(levels[i].name, names[i]);
    EXPECT_EQ(levels[i].average_boxes, apart[i]) << names[i];
    EXPECT_EQ(levels[i].roi.size(), placed.roi(kRoiKinds[i])->size());
  }
  EXPECT_EQ(attentionRoi(placed, Attention::parse("leaf-nodes")).size(), 3u);
}

TEST(TrialSetup, CanonicalLevelNames)
{
  EXPECT_EQ(canonicalLevelName("fruits"), "fruit");
  EXPECT_EQ(canonicalLevelName("main-stem"), "main_stem");
  EXPECT_EQ(canonicalLevelName("model_rois"), "model_rois");
  EXPECT_EQ(
      errorOf([] { canonicalLevelName("leaves"); }),
      "unknown level 'leaves' (expected whole_plant, main_stem, leaf_nodes, fruit or "
      "model_rois)");
}

TEST(TrialSetup, CandidatesAreMultiplesOfTheGridCells)
{
  TrialConfig c;
  setCandidateCount(45, "--candidates", c);
  EXPECT_EQ(c.samples_per_cell, 5);
  EXPECT_EQ(errorOf([&] { setCandidateCount(10, "--candidates", c); }),
            "--candidates 10: expected a multiple of the 9 grid cells (9, 27, 45, ...)");
  EXPECT_EQ(c.samples_per_cell, 5); // unchanged
  c.grid_rows = 2;
  c.grid_cols = 4;
  EXPECT_EQ(errorOf([&] { setCandidateCount(27, "candidates", c); }),
            "candidates 27: expected a multiple of the 8 grid cells (8, 24, 40, ...)");
  EXPECT_NE(errorOf([&] { setCandidateCount(0, "candidates", c); }), "");
  EXPECT_NE(errorOf([&] { setCandidateCount(-8, "candidates", c); }), "");
}

TEST(TrialSetup, TheSectorFollowsALoadedModelOnly)
{
  TrialConfig c;
  fitSectorToPlant(generatedPlant(), std::nullopt, c);
  EXPECT_EQ(c.sector.height_m, TrialConfig().sector.height_m); // the paper's 0.7 m
  fitSectorToPlant(generatedPlant(), 0.5, c);
  EXPECT_EQ(c.sector.height_m, 0.5);

  PlantSource source;
  source.model = std::string(PLANTNBV_DATA_DIR) + "/fixtures/plant_cm_zup.dae";
  const PlacedPlant model = makePlacedPlant(source);
  Eigen::Vector3f lo, hi;
  model.plant.bounds(lo, hi);
  TrialConfig m;
  fitSectorToPlant(model, std::nullopt, m);
  EXPECT_EQ(m.sector.height_m, double(hi.z()) - model.plant.base_position.z());
  fitSectorToPlant(model, 0.9, m);
  EXPECT_EQ(m.sector.height_m, 0.9);
}
