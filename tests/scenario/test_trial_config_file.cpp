#include <cmath>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/scenario/trial_config_file.h>

#include "scenario_test_util.h"

using namespace plantnbv;
using plantnbv::test::errorOf;
using plantnbv::test::ScenarioFiles;

using TrialConfigFile = ScenarioFiles;

TEST_F(TrialConfigFile, ThePapersConfigIsTheBuiltInDefault)
{
  TrialConfig c;
  c.views = 3; // overwritten by the file
  scenario::loadTrialConfig(std::string(PLANTNBV_DATA_DIR) + "/paper.yaml", c);
  const TrialConfig d;
  EXPECT_EQ(c.views, d.views);
  EXPECT_EQ(c.map.resolution_m, d.map.resolution_m);
  EXPECT_EQ(c.map.prob_hit, d.map.prob_hit);
  EXPECT_EQ(c.map.clamp_min, d.map.clamp_min);
  EXPECT_EQ(c.sector.radius_m, d.sector.radius_m);
  EXPECT_EQ(c.sector.angle_rad, d.sector.angle_rad);
  EXPECT_EQ(c.samples_per_cell, d.samples_per_cell);
  EXPECT_EQ(c.gain.rays_x, d.gain.rays_x);
  EXPECT_EQ(c.initial_view.position, d.initial_view.position);
  EXPECT_EQ(c.initial_view.orientation.coeffs(), d.initial_view.orientation.coeffs());
  EXPECT_EQ(c.camera.toString(), d.camera.toString());
}

TEST_F(TrialConfigFile, OnlyTheKeysGivenChange)
{
  TrialConfig c;
  scenario::loadTrialConfig(write("t.yaml", "views: 4\nmap: {resolution: 0.005}\n"
                                            "scene: {floor: false}\n"),
                            c);
  EXPECT_EQ(c.views, 4);
  EXPECT_EQ(c.map.resolution_m, 0.005);
  EXPECT_FALSE(c.scene.floor);
  EXPECT_TRUE(c.scene.support);
  EXPECT_EQ(c.map.max_range_m, TrialConfig().map.max_range_m);
  TrialConfig noisy;
  scenario::loadTrialConfig(
      write("noisy.yaml", "roi_source: noisy\nroi_sigma: 0.01\nroi_scale: 2\n"), noisy);
  EXPECT_EQ(noisy.roi_source.kind, RoiSourceKind::noisy);
  EXPECT_EQ(noisy.roi_source.sigma_m, 0.01);
  EXPECT_EQ(noisy.roi_source.scale, 2.0);
  EXPECT_EQ(TrialConfig().roi_source.kind, RoiSourceKind::oracle);
  TrialConfig empty;
  scenario::loadTrialConfig(write("empty.yaml", ""), empty);
  EXPECT_EQ(empty.views, TrialConfig().views);
}

// Every key trialConfigText writes loads back to the value it was written from: configs
// that between them set every key away from its default, written, loaded over the
// defaults and written again, give the same text (the orientation of v0 is normalized
// again when read: the same to rounding).
TEST_F(TrialConfigFile, ItsTextLoadsBackToTheSameValues)
{
  const auto withoutV0 = [](const std::string& text) {
    std::istringstream in(text);
    std::string line, out;
    while (std::getline(in, line))
      if (line.rfind("initial_view:", 0) != 0)
        out += line + "\n";
    return out;
  };
  const auto roundTrip = [&](const TrialConfig& c, const std::string& name) {
    const std::string text = scenario::trialConfigText(c);
    TrialConfig back;
    scenario::loadTrialConfig(write(name, text), back);
    EXPECT_EQ(withoutV0(scenario::trialConfigText(back)), withoutV0(text));
    EXPECT_TRUE(back.initial_view.position == c.initial_view.position);
    EXPECT_TRUE(back.initial_view.orientation.coeffs().isApprox(
        c.initial_view.orientation.coeffs(), 1e-15));
    return back;
  };
  TrialConfig c;
  c.camera = parseCameraIntrinsics("320x240:200.5,201,159.5,119.25");
  c.noise.enabled = true;
  c.views = 7;
  c.depth_scale = 1000;
  c.roi_source.kind = RoiSourceKind::noisy;
  c.roi_source.sigma_m = 0.0125;
  c.roi_source.scale = 1.5;
  c.stop_gain_bits = 12.5;
  c.explore_share = 0.3;
  c.view_spacing_m = 0.1;
  c.seed = 123456789012345ull;
  c.time_limit_s = 60;
  c.memory_cap_bytes = 2.5 * 1024 * 1024 * 1024;
  c.initial_view = Pose::fromXyzQuat(0.5, 0.25, 1.125, 0.0, 0.0, 0.6, 0.8);
  c.sector.radius_m = 0.45;
  c.sector.height_m = 0.8;
  c.sector.bottom_m = 0.05;
  c.sector.angle_rad = 120.0 * M_PI / 180.0;
  c.grid_rows = 2;
  c.grid_cols = 4;
  c.samples_per_cell = 5;
  c.map.resolution_m = 0.004;
  c.map.prob_hit = 0.75;
  c.map.prob_miss = 0.35;
  c.map.clamp_min = 0.1;
  c.map.clamp_max = 0.98;
  c.map.occupancy_threshold = 0.55;
  c.map.max_range_m = 0.8;
  c.gain.rays_x = 40;
  c.gain.rays_y = 30;
  c.gain.raycast_range_m = 0.7;
  c.gain.visibility_weighted = true;
  c.gain.unknown_only = !TrialConfig().gain.unknown_only;
  c.gain.unknown_depth = 5;
  c.scene.floor = false;
  c.scene.support = false;
  const TrialConfig back = roundTrip(c, "noisy.yaml");
  EXPECT_EQ(back.camera.toString(), c.camera.toString());
  EXPECT_EQ(back.seed, c.seed);
  EXPECT_EQ(back.memory_cap_bytes, c.memory_cap_bytes);
  EXPECT_DOUBLE_EQ(back.sector.angle_rad, c.sector.angle_rad);
  EXPECT_EQ(back.gain.unknown_only, c.gain.unknown_only);

  // The keys of the other ROI sources and of the predefined planner.
  TrialConfig detections;
  detections.roi_source.kind = RoiSourceKind::detections_prior;
  detections.roi_source.detector_recall = 0.8;
  detections.roi_source.detector_false_positives = 1.5;
  detections.roi_source.detector_box_jitter_px = 2.5;
  detections.roi_source.detector_mask_dilation_px = -2;
  detections.roi_source.detector_masks = false;
  detections.roi_source.prior_internode_m = 0.05;
  const TrialConfig detections_back = roundTrip(detections, "detections.yaml");
  EXPECT_EQ(detections_back.roi_source.kind, RoiSourceKind::detections_prior);
  EXPECT_EQ(detections_back.roi_source.detector_false_positives, 1.5);
  EXPECT_EQ(detections_back.roi_source.prior_internode_m, 0.05);
  EXPECT_EQ(detections_back.roi_source.detector_box_jitter_px, 2.5);
  EXPECT_EQ(detections_back.roi_source.detector_mask_dilation_px, -2);
  EXPECT_FALSE(detections_back.roi_source.detector_masks);
  TrialConfig predefined;
  predefined.planner = PlannerKind::predefined;
  predefined.pattern = 3;
  const TrialConfig predefined_back = roundTrip(predefined, "predefined.yaml");
  TrialConfig attending;
  attending.roi_source.kind = RoiSourceKind::detections;
  attending.roi_source.detections_explore_views = 0;
  EXPECT_EQ(roundTrip(attending, "attending.yaml").roi_source.detections_explore_views,
            0);
  EXPECT_EQ(predefined_back.planner, PlannerKind::predefined);
  EXPECT_EQ(predefined_back.pattern, 3);

  // Between them the four set every line away from the defaults': every key is written.
  const auto lines = [](const TrialConfig& config) {
    std::istringstream in(scenario::trialConfigText(config));
    std::vector<std::string> out;
    for (std::string line; std::getline(in, line);)
      out.push_back(line);
    return out;
  };
  const std::vector<std::string> defaults = lines(TrialConfig());
  const std::vector<std::vector<std::string>> set = {lines(c), lines(detections),
                                                     lines(predefined), lines(attending)};
  ASSERT_EQ(defaults.size(), 27u);
  for (std::size_t i = 0; i < defaults.size(); ++i)
    EXPECT_TRUE(set[0][i] != defaults[i] || set[1][i] != defaults[i] ||
                set[2][i] != defaults[i] || set[3][i] != defaults[i])
        << "no config sets " << defaults[i];
  // A preset camera is written by its name.
  EXPECT_EQ(defaults[0], "camera: l515-640");
}

TEST_F(TrialConfigFile, ErrorsNameTheFileAndTheKeyPath)
{
  TrialConfig c;
  const std::string f = write("bad.yaml", "sector: {radius: 0.4, hieght: 0.7}\n");
  EXPECT_EQ(errorOf([&] { scenario::loadTrialConfig(f, c); }),
            "'" + f +
                "' sector.hieght: unknown key (expected one of angle_deg, bottom, "
                "cols, height, radius, rows, samples_per_cell)");
  const std::string g = write("words.yaml", "views: ten\n");
  EXPECT_EQ(errorOf([&] { scenario::loadTrialConfig(g, c); }),
            "'" + g + "' views: 'ten' is not an integer");
  const std::string h = write("list.yaml", "gain: {rays_x: [1, 2]}\n");
  EXPECT_EQ(errorOf([&] { scenario::loadTrialConfig(h, c); }),
            "'" + h + "' gain.rays_x: expected an integer, got [1, 2]");
  const std::string v =
      write("view.yaml", "initial_view: {position: [.nan, 0.3, 1.4]}\n");
  EXPECT_EQ(errorOf([&] { scenario::loadTrialConfig(v, c); }),
            "'" + v +
                "' initial_view.position: expected 3 numbers, got [.nan, 0.3, 1.4]");
  const std::string k = write("key.yaml", "? [views]\n: 3\n");
  EXPECT_EQ(errorOf([&] { scenario::loadTrialConfig(k, c); }),
            "'" + k + "' (top level): a key must be a name, not [views]");
  const std::string cam = write("cam.yaml", "camera: l516\n");
  EXPECT_NE(errorOf([&] { scenario::loadTrialConfig(cam, c); }).find("camera: "),
            std::string::npos);
  EXPECT_THROW(scenario::loadTrialConfig((dir_ / "none.yaml").string(), c), IoError);
  const std::string source = write("source.yaml", "roi_source: detector\n");
  EXPECT_EQ(errorOf([&] { scenario::loadTrialConfig(source, c); }),
            "'" + source +
                "' roi_source: unknown ROI source 'detector' (expected oracle, noisy, "
                "detections, prior or detections+prior)");
  const std::string sigma = write("sigma.yaml", "roi_sigma: 0.01\n");
  EXPECT_EQ(errorOf([&] { scenario::loadTrialConfig(sigma, c); }),
            "trial config: roi_sigma 0.01: only the noisy ROI source uses it (roi_source "
            "is oracle)");
  const std::string range = write("range.yaml", "map: {prob_hit: 1.5}\n");
  EXPECT_THROW(scenario::loadTrialConfig(range, c), InvalidArgumentError);
}
