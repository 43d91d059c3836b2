#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/plant/plant_rois.h>
#include <plantnbv/viz/snapshot.h>

#include "viz_test_util.h"

using plantnbv::PartLabel;
using plantnbv::Roi;
using plantnbv::test::countNear;
using plantnbv::test::paperPlant;
using plantnbv::test::readPng;
using plantnbv::test::ScopedEnv;
using plantnbv::viz::CameraPose;
using plantnbv::viz::distinctColor;
using plantnbv::viz::RgbImage;
using plantnbv::viz::SceneSnapshot;

namespace {

std::string outputPath(const std::string& name)
{
  return std::string(PLANTNBV_BINARY_DIR) + "/tests/" + name;
}

/// The paper's plant with its whole-plant, main-stem and leaf-node ROIs.
SceneSnapshot plantScene(const SceneSnapshot::Config& config = {})
{
  SceneSnapshot snapshot(config);
  const plantnbv::Plant& plant = paperPlant();
  snapshot.addMesh(plant.mesh);
  snapshot.addRoi(plantnbv::wholePlantRoi(plant), distinctColor(0));
  snapshot.addRoi(plantnbv::mainStemRoi(plant), distinctColor(1));
  snapshot.addRoi(plantnbv::leafNodeRoi(plant), distinctColor(2));
  return snapshot;
}

bool isWhite(const std::uint8_t* p)
{
  return p[0] == 255 && p[1] == 255 && p[2] == 255;
}

} // namespace

TEST(SceneSnapshot, PlantWithRoisGivesAFilledPngOfTheConfiguredSize)
{
  // Portrait, as the plant is tall: the background share below is then meaningful.
  SceneSnapshot::Config config;
  config.width = 800;
  config.height = 1000;
  const std::string path = outputPath("viz_plant_snapshot.png");
  std::remove(path.c_str());
  plantScene(config).render(path);

  const RgbImage image = readPng(path);
  ASSERT_EQ(image.width, 800);
  ASSERT_EQ(image.height, 1000);

  std::set<int> colors;
  std::size_t white = 0, green = 0;
  int top = image.height, bottom = -1;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.at(x, y);
      colors.insert((p[0] << 16) | (p[1] << 8) | p[2]);
      if (isWhite(p)) {
        ++white;
        continue;
      }
      top = std::min(top, y);
      bottom = std::max(bottom, y);
      green += p[1] > p[0] + 20 && p[1] > p[2] + 20;
    }
  const double pixels = double(image.width) * image.height;
  EXPECT_GT(colors.size(), 1000u); // shaded surfaces, not flat fills
  EXPECT_LT(white / pixels, 0.95);
  EXPECT_GT(green / pixels, 0.01); // the foliage
  // Unlit ROI lines keep their colours exactly, but for anti-aliased edges.
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_GT(countNear(image, distinctColor(i), 8), 200u) << "ROI colour " << i;
  // The automatic camera fits the scene (the 0.7 m tall whole-plant box) to the height.
  EXPECT_LT(top, 0.1 * image.height);
  EXPECT_GT(bottom, 0.9 * image.height);
}

TEST(SceneSnapshot, AutomaticCameraLooksAtTheCentreFromFrontLeftAbove)
{
  const SceneSnapshot snapshot = plantScene();
  Eigen::Vector3d min, max;
  snapshot.bounds(min, max);
  const Eigen::Vector3d center = 0.5 * (min + max);
  const CameraPose camera = snapshot.camera();
  const Eigen::Vector3d to_camera = camera.position - camera.focal_point;
  EXPECT_LT(to_camera.x(), 0.0); // on the robot's side (world x points away from it)
  EXPECT_GT(to_camera.y(), 0.0); // to the left
  EXPECT_GT(to_camera.z(), 0.0); // above
  // Default azimuth 35 deg and elevation 15 deg.
  EXPECT_NEAR(std::atan2(to_camera.y(), -to_camera.x()), 35.0 * M_PI / 180.0, 1e-9);
  EXPECT_NEAR(std::asin(to_camera.z() / to_camera.norm()), 15.0 * M_PI / 180.0, 1e-9);
  // It looks at the centre, up to the sideways shift that centres the picture.
  const Eigen::Vector3d axis = -to_camera.normalized();
  const Eigen::Vector3d off_axis =
      (center - camera.position) - (center - camera.position).dot(axis) * axis;
  EXPECT_LT(off_axis.norm(), 0.05);
  EXPECT_NEAR(camera.view_up.dot(axis), 0.0, 1e-9);
}

TEST(SceneSnapshot, ExplicitCameraIsUsedAndTheImageIsUpright)
{
  // Looking along +x with z up: a red cloud above the focal point must appear in the
  // upper half, a grey one below it in the lower half.
  SceneSnapshot::Config config;
  config.width = 160;
  config.height = 120;
  config.camera = CameraPose{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                             Eigen::Vector3d(0, 0, 1)};
  SceneSnapshot snapshot(config);
  std::vector<Eigen::Vector3f> high, low;
  for (int i = -5; i <= 5; ++i) {
    high.emplace_back(1.0f, 0.01f * i, 0.15f);
    low.emplace_back(1.0f, 0.01f * i, -0.15f);
  }
  snapshot.addPoints(high, std::vector<PartLabel>(high.size(), PartLabel::fruit), 6.0f);
  snapshot.addPoints(low, plantnbv::viz::Rgb{0.0f, 0.0f, 0.0f}, 6.0f);
  EXPECT_TRUE(snapshot.camera().position.isZero());

  const RgbImage image = snapshot.renderImage();
  ASSERT_EQ(image.width, 160);
  ASSERT_EQ(image.height, 120);
  std::size_t red_top = 0, red_bottom = 0, dark_top = 0, dark_bottom = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.at(x, y);
      const bool red = p[0] > 120 && p[1] < 60 && p[2] < 60;
      const bool dark = p[0] < 60 && p[1] < 60 && p[2] < 60;
      (y < image.height / 2 ? red_top : red_bottom) += red;
      (y < image.height / 2 ? dark_top : dark_bottom) += dark;
    }
  EXPECT_GT(red_top, 20u);
  EXPECT_EQ(red_bottom, 0u);
  EXPECT_GT(dark_bottom, 20u);
  EXPECT_EQ(dark_top, 0u);
}

TEST(SceneSnapshot, TitleIsDrawn)
{
  SceneSnapshot::Config config;
  config.width = 200;
  config.height = 100;
  config.camera = CameraPose{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                             Eigen::Vector3d(0, 0, 1)};
  SceneSnapshot snapshot(config);
  // A point behind the camera: nothing of the scene is drawn.
  snapshot.addPoints({Eigen::Vector3f(-1, 0, 0)}, plantnbv::viz::Rgb{0, 0, 0});
  const auto dark_in_top_left = [](const RgbImage& image) {
    std::size_t n = 0;
    for (int y = 0; y < image.height / 3; ++y)
      for (int x = 0; x < image.width / 2; ++x)
        n += image.at(x, y)[0] < 100;
    return n;
  };
  EXPECT_EQ(dark_in_top_left(snapshot.renderImage()), 0u);
  config.title = "seed 7";
  config.title_size_px = 30;
  snapshot.setConfig(config);
  EXPECT_GT(dark_in_top_left(snapshot.renderImage()), 10u);
}

TEST(SceneSnapshot, EmptySceneIsAnError)
{
  SceneSnapshot snapshot;
  EXPECT_TRUE(snapshot.empty());
  // Empty inputs add nothing.
  snapshot.addMesh(plantnbv::TriangleMesh());
  snapshot.addRoi(Roi(), distinctColor(0));
  snapshot.addPoints({}, distinctColor(0));
  EXPECT_TRUE(snapshot.empty());
  EXPECT_THROW(snapshot.renderImage(), plantnbv::InvalidArgumentError);
  EXPECT_THROW(snapshot.render(outputPath("viz_empty.png")),
               plantnbv::InvalidArgumentError);
  EXPECT_THROW(snapshot.camera(), plantnbv::InvalidArgumentError);

  snapshot.addRoi(plantnbv::mainStemRoi(paperPlant()), distinctColor(0));
  EXPECT_FALSE(snapshot.empty());
  snapshot.clear();
  EXPECT_TRUE(snapshot.empty());
}

TEST(SceneSnapshot, UnwritablePathIsAnIoError)
{
  SceneSnapshot snapshot;
  snapshot.addRoi(plantnbv::mainStemRoi(paperPlant()), distinctColor(0));
  const std::string path = outputPath("no-such-directory/snapshot.png");
  try {
    snapshot.render(path);
    FAIL() << "no exception";
  } catch (const plantnbv::IoError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(SceneSnapshot, WithoutDisplayRenderThrowsTheDocumentedError)
{
  SceneSnapshot snapshot;
  snapshot.addRoi(plantnbv::mainStemRoi(paperPlant()), distinctColor(0));
  {
    ScopedEnv no_display("DISPLAY", std::nullopt);
    try {
      snapshot.renderImage();
      FAIL() << "no exception";
    } catch (const plantnbv::Error& e) {
      EXPECT_STREQ(e.what(), "rendering needs an X display: run the command under "
                             "`xvfb-run -a`, or set DISPLAY");
    }
  }
  {
    // A display number no server listens on: VTK alone would abort() here.
    ScopedEnv dead_display("DISPLAY", std::string(":4987"));
    try {
      snapshot.render(outputPath("viz_no_display.png"));
      FAIL() << "no exception";
    } catch (const plantnbv::Error& e) {
      EXPECT_NE(std::string(e.what()).find("DISPLAY=:4987"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("xvfb-run -a"), std::string::npos) << e.what();
    }
  }
  // With the display back, the same snapshot renders, at the default size.
  const RgbImage image = snapshot.renderImage();
  EXPECT_EQ(image.width, 1200);
  EXPECT_EQ(image.height, 900);
}

TEST(SceneSnapshot, RejectsInvalidSettings)
{
  using plantnbv::InvalidArgumentError;
  SceneSnapshot::Config config;
  config.width = 0;
  EXPECT_THROW(SceneSnapshot{config}, InvalidArgumentError);
  config = {};
  config.background.g = 1.5f;
  EXPECT_THROW(SceneSnapshot{config}, InvalidArgumentError);
  config = {};
  config.auto_elevation_rad = 1.6;
  EXPECT_THROW(SceneSnapshot{config}, InvalidArgumentError);
  config = {};
  config.camera = CameraPose{Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 0, 0),
                             Eigen::Vector3d(0, 0, 1)};
  EXPECT_THROW(SceneSnapshot{config}, InvalidArgumentError);
  config.camera = CameraPose{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 1),
                             Eigen::Vector3d(0, 0, 1)};
  EXPECT_THROW(SceneSnapshot{config}, InvalidArgumentError);

  config = {};
  EXPECT_NE(config.toString().find("width: 1200 px\nheight: 900 px"), std::string::npos);
  EXPECT_NE(config.toString().find("camera: automatic"), std::string::npos);

  SceneSnapshot snapshot;
  const Roi roi = plantnbv::mainStemRoi(paperPlant());
  EXPECT_THROW(snapshot.addRoi(roi, plantnbv::viz::Rgb{-0.1f, 0, 0}),
               InvalidArgumentError);
  EXPECT_THROW(snapshot.addRoi(roi, distinctColor(0), 0.0f), InvalidArgumentError);
  EXPECT_THROW(snapshot.addPoints({Eigen::Vector3f::Zero()}, std::vector<PartLabel>(2)),
               InvalidArgumentError);
  EXPECT_THROW(snapshot.addPoints({Eigen::Vector3f::Zero()}, distinctColor(0), -1.0f),
               InvalidArgumentError);
  plantnbv::TriangleMesh broken;
  broken.vertices.emplace_back(0, 0, 0);
  broken.triangles.push_back({0, 1, 2});
  EXPECT_THROW(snapshot.addMesh(broken), plantnbv::FormatError);
  EXPECT_TRUE(snapshot.empty());
}

TEST(WritePng, RoundTripsPixelsTopRowFirst)
{
  RgbImage image;
  image.width = 5;
  image.height = 3;
  image.rgb.resize(3 * 5 * 3);
  for (std::size_t i = 0; i < image.rgb.size(); ++i)
    image.rgb[i] = static_cast<std::uint8_t>(17 * i);
  const std::string path = outputPath("viz_roundtrip.png");
  plantnbv::viz::writePng(image, path);
  const RgbImage back = readPng(path);
  ASSERT_EQ(back.width, 5);
  ASSERT_EQ(back.height, 3);
  EXPECT_EQ(back.rgb, image.rgb);

  image.rgb.pop_back();
  EXPECT_THROW(plantnbv::viz::writePng(image, path), plantnbv::InvalidArgumentError);
}
