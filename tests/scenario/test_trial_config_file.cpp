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
