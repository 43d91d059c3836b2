#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <string>
#include <tuple>
#include <utility>
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

TEST(SceneSnapshot, LegendEntriesAreSquaresOfTheirColourInABandAtTheBottom)
{
  SceneSnapshot::Config config;
  config.width = 400;
  config.height = 400;
  config.label_size_px = 40; // squares of 30 px
  config.multisamples = 0;
  SceneSnapshot snapshot(config);
  const plantnbv::viz::Rgb red{1, 0, 0}, blue{0, 0, 1}, green{0, 1, 0};
  snapshot.addLegendEntry("red", red);
  EXPECT_TRUE(snapshot.empty()); // a legend alone is not a scene
  snapshot.addLegendEntry("a long blue entry that needs its own row", blue);
  // A cloud that fills the picture as far as the automatic camera lets it.
  std::vector<Eigen::Vector3f> cloud;
  for (int i = 0; i <= 40; ++i)
    for (int k = 0; k <= 40; ++k)
      cloud.emplace_back(0.0f, 0.01f * i, 0.01f * k);
  snapshot.addPoints(cloud, green, 6.0f);
  const RgbImage image = snapshot.renderImage();
  // Rows where a colour is exactly there, and how many pixels.
  const auto rows = [&](const plantnbv::viz::Rgb& c, int& top, int& bottom) {
    std::size_t n = 0;
    top = image.height;
    bottom = -1;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) {
        const std::uint8_t* p = image.at(x, y);
        if (p[0] == 255 * c.r && p[1] == 255 * c.g && p[2] == 255 * c.b) {
          ++n;
          top = std::min(top, y);
          bottom = std::max(bottom, y);
        }
      }
    return n;
  };
  int red_top, red_bottom, blue_top, blue_bottom;
  EXPECT_NEAR(double(rows(red, red_top, red_bottom)), 900.0, 100.0);
  EXPECT_NEAR(double(rows(blue, blue_top, blue_bottom)), 900.0, 100.0);
  EXPECT_LT(red_bottom, blue_top); // two rows, the first entry on top
  EXPECT_GT(red_top, image.height / 2);
  // The cloud is lit (not exactly green): any pixel that is not white is the scene's or
  // the legend's; the scene keeps above the band.
  int scene_bottom = -1;
  for (int y = 0; y < red_top - 5; ++y)
    for (int x = 0; x < image.width; ++x)
      if (!isWhite(image.at(x, y)))
        scene_bottom = y;
  EXPECT_GT(scene_bottom, image.height / 3); // it is drawn
  for (int y = red_top - 5; y < blue_top - 5; ++y)
    for (int x = image.width / 2; x < image.width; ++x) { // right of the red entry
      EXPECT_TRUE(isWhite(image.at(x, y))) << x << ", " << y;
    }

  EXPECT_THROW(snapshot.addLegendEntry("", red), plantnbv::InvalidArgumentError);
  EXPECT_THROW(snapshot.addLegendEntry("x", plantnbv::viz::Rgb{2, 0, 0}),
               plantnbv::InvalidArgumentError);
  snapshot.clear(); // the legend too
  snapshot.addPoints(cloud, green, 6.0f);
  const RgbImage cleared = snapshot.renderImage();
  for (int y = 0; y < cleared.height; ++y)
    for (int x = 0; x < cleared.width; ++x)
      ASSERT_FALSE(cleared.at(x, y)[0] == 255 && cleared.at(x, y)[1] == 0)
          << x << ", " << y;
}

TEST(SceneSnapshot, PartLegendListsThePartsThatOccur)
{
  SceneSnapshot::Config config;
  config.width = 600;
  config.height = 300;
  config.label_size_px = 40;
  config.multisamples = 0;
  SceneSnapshot snapshot(config);
  snapshot.addPoints({Eigen::Vector3f(0, 0, 0)}, plantnbv::viz::Rgb{0, 0, 0});
  plantnbv::viz::addPartLegend({PartLabel::fruit, PartLabel::stem, PartLabel::fruit},
                               snapshot);
  const RgbImage image = snapshot.renderImage();
  std::size_t per_part[7] = {};
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int l = 0; l < 7; ++l) {
        const auto c = plantnbv::viz::partLabelColor(static_cast<PartLabel>(l));
        const std::uint8_t* p = image.at(x, y);
        per_part[l] += p[0] == std::lround(255 * c.r) && p[1] == std::lround(255 * c.g) &&
                       p[2] == std::lround(255 * c.b);
      }
  for (int l = 0; l < 7; ++l) {
    SCOPED_TRACE(l);
    if (l == int(PartLabel::stem) || l == int(PartLabel::fruit))
      EXPECT_NEAR(double(per_part[l]), 900.0, 100.0);
    else
      EXPECT_LT(per_part[l], 50u);
  }
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

// --- Translucent meshes, camera frustums and polylines -------------------------------

namespace {

using plantnbv::Pose;
using plantnbv::viz::Rgb;

/// A square facing -x (towards a camera at the origin looking along +x), `half_m` on
/// each side of (x, 0, 0).
plantnbv::TriangleMesh square(double x, double half_m)
{
  plantnbv::TriangleMesh mesh;
  const float h = static_cast<float>(half_m), xf = static_cast<float>(x);
  mesh.vertices = {{xf, -h, -h}, {xf, h, -h}, {xf, h, h}, {xf, -h, h}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

/// A small scene seen by a camera at the origin looking along +x, z up.
SceneSnapshot::Config frontCamera(int width = 160, int height = 120)
{
  SceneSnapshot::Config config;
  config.width = width;
  config.height = height;
  config.camera = CameraPose{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                             Eigen::Vector3d(0, 0, 1)};
  return config;
}

struct Pixel {
  int r, g, b;
};

Pixel centrePixel(const RgbImage& image)
{
  const std::uint8_t* p = image.at(image.width / 2, image.height / 2);
  return {p[0], p[1], p[2]};
}

double distanceToWhite(const Pixel& p)
{
  return std::sqrt(double((255 - p.r) * (255 - p.r) + (255 - p.g) * (255 - p.g) +
                          (255 - p.b) * (255 - p.b)));
}

/// A camera body frame (x forward, y left, z up) at `position` looking at `target`.
Pose lookAt(const Eigen::Vector3d& position, const Eigen::Vector3d& target)
{
  const Eigen::Vector3d forward = (target - position).normalized();
  const Eigen::Vector3d left = Eigen::Vector3d::UnitZ().cross(forward).normalized();
  Eigen::Matrix3d R;
  R << forward, left, forward.cross(left);
  return Pose(position, Eigen::Quaterniond(R));
}

const Rgb kBlue{0.0f, 0.0f, 1.0f};
const Rgb kRed{1.0f, 0.0f, 0.0f};

} // namespace

TEST(SceneSnapshot, FadedMeshIsBlendedWithWhatIsBehindIt)
{
  const auto render = [](const std::vector<std::pair<double, Rgb>>& squares,
                         double first_opacity) {
    SceneSnapshot snapshot(frontCamera());
    bool first = true;
    for (const auto& [x, color] : squares) {
      snapshot.addMesh(square(x, 0.1 * x), color, first ? first_opacity : 1.0);
      first = false;
    }
    return centrePixel(snapshot.renderImage());
  };
  const Pixel opaque = render({{1.0, kBlue}}, 1.0);
  const Pixel faded = render({{1.0, kBlue}}, 0.3);
  // Faded over the white background: lighter, yet still blue.
  EXPECT_GT(distanceToWhite(opaque), 250.0);
  EXPECT_LT(distanceToWhite(faded), 0.5 * distanceToWhite(opaque));
  EXPECT_GT(distanceToWhite(faded), 50.0);
  EXPECT_GT(faded.b, faded.r + 20);
  EXPECT_GT(faded.r, opaque.r + 100);

  // Faded over an opaque red square behind it, added before or after: both colours
  // show, whatever the order.
  const Pixel red = render({{1.5, kRed}}, 1.0);
  const Pixel over_red = render({{1.0, kBlue}, {1.5, kRed}}, 0.3);
  const Pixel red_first = [] {
    SceneSnapshot snapshot(frontCamera());
    snapshot.addMesh(square(1.5, 0.15), kRed);
    snapshot.addMesh(square(1.0, 0.1), kBlue, 0.3);
    return centrePixel(snapshot.renderImage());
  }();
  EXPECT_GT(over_red.r, 100);
  EXPECT_GT(over_red.b, red.b + 30);
  EXPECT_LT(over_red.g, faded.g - 80); // red, not white, behind the blue
  EXPECT_NEAR(red_first.r, over_red.r, 4);
  EXPECT_NEAR(red_first.g, over_red.g, 4);
  EXPECT_NEAR(red_first.b, over_red.b, 4);
}

TEST(SceneSnapshot, TranslucentMeshesAreSortedByDepthNotByOrder)
{
  // Two half-transparent squares: the nearer one's colour dominates, whichever was
  // added first.
  const auto render = [](double blue_x, double red_x, bool blue_first) {
    SceneSnapshot snapshot(frontCamera());
    const auto add_blue = [&] {
      snapshot.addMesh(square(blue_x, 0.1 * blue_x), kBlue, 0.5);
    };
    const auto add_red = [&] { snapshot.addMesh(square(red_x, 0.1 * red_x), kRed, 0.5); };
    if (blue_first) {
      add_blue();
      add_red();
    } else {
      add_red();
      add_blue();
    }
    return centrePixel(snapshot.renderImage());
  };
  for (bool blue_first : {true, false}) {
    const Pixel blue_near = render(1.0, 1.5, blue_first);
    EXPECT_GT(blue_near.b, blue_near.r + 30) << blue_first;
    const Pixel red_near = render(1.5, 1.0, blue_first);
    EXPECT_GT(red_near.r, red_near.b + 30) << blue_first;
  }
}

TEST(SceneSnapshot, FrustumBoundsFollowTheCameraBodyFrame)
{
  // Turned 90 deg about z: the camera looks along world +y, its left (body y) is world
  // -x. The horizontal field of view spans body y, the vertical one body z.
  const Pose T_W_C(
      Eigen::Vector3d(1.0, 2.0, 3.0),
      Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ())));
  SceneSnapshot snapshot;
  snapshot.addCameraFrustum(T_W_C, M_PI / 2, M_PI / 3, 2.0, distinctColor(0), "1");
  EXPECT_FALSE(snapshot.empty());
  Eigen::Vector3d min, max;
  snapshot.bounds(min, max);
  const double half_h = 2.0, half_v = 2.0 * std::tan(M_PI / 6);
  EXPECT_TRUE(min.isApprox(Eigen::Vector3d(1.0 - half_h, 2.0, 3.0 - half_v), 1e-6))
      << min.transpose();
  EXPECT_TRUE(max.isApprox(Eigen::Vector3d(1.0 + half_h, 4.0, 3.0 + half_v), 1e-6))
      << max.transpose();

  // Polylines count too; a non-finite point breaks the line, lone points add nothing.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  snapshot.addPolyline({Eigen::Vector3d(-5, 0, 0), Eigen::Vector3d(nan, 0, 0),
                        Eigen::Vector3d(0, -6, 0), Eigen::Vector3d(0, -6, 7)},
                       distinctColor(1));
  snapshot.bounds(min, max);
  EXPECT_TRUE(min.isApprox(Eigen::Vector3d(-1.0, -6.0, 0.0), 1e-6)) << min.transpose();
  EXPECT_TRUE(max.isApprox(Eigen::Vector3d(3.0, 4.0, 7.0), 1e-6)) << max.transpose();

  SceneSnapshot lone;
  lone.addPolyline({Eigen::Vector3d(0, 0, 0)}, distinctColor(1));
  lone.addPolyline(
      {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, nan, 0), Eigen::Vector3d(1, 0, 0)},
      distinctColor(1));
  lone.addPolyline({}, distinctColor(1));
  EXPECT_TRUE(lone.empty());
}

TEST(SceneSnapshot, FrustumIsDrawnInItsColourWithTheFieldsOfViewAsGiven)
{
  // Seen from behind: a frustum 2 m ahead looking the same way (+x), 90 deg wide and
  // 20 deg high, appears as a flat wide rectangle with its diagonals.
  SceneSnapshot snapshot(frontCamera(320, 240));
  snapshot.addCameraFrustum(
      Pose(Eigen::Vector3d(2, 0, 0), Eigen::Quaterniond::Identity()), M_PI / 2,
      20.0 * M_PI / 180.0, 0.5, distinctColor(0));
  const RgbImage image = snapshot.renderImage();
  ASSERT_EQ(image.width, 320);
  ASSERT_EQ(image.height, 240);
  int left = image.width, right = -1, top = image.height, bottom = -1;
  std::size_t n = 0;
  const int want[3] = {int(distinctColor(0).r * 255 + 0.5f),
                       int(distinctColor(0).g * 255 + 0.5f),
                       int(distinctColor(0).b * 255 + 0.5f)};
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.at(x, y);
      if (std::abs(p[0] - want[0]) > 8 || std::abs(p[1] - want[1]) > 8 ||
          std::abs(p[2] - want[2]) > 8)
        continue;
      ++n;
      left = std::min(left, x);
      right = std::max(right, x);
      top = std::min(top, y);
      bottom = std::max(bottom, y);
    }
  EXPECT_GT(n, 200u);
  // The far rectangle at 2.5 m: 1 m wide, 0.18 m high, centred.
  const double px_per_m = 120.0 / std::tan(M_PI / 12) / 2.5;
  EXPECT_NEAR(right - left, 1.0 * px_per_m, 6.0);
  EXPECT_NEAR(bottom - top, 2 * 0.5 * std::tan(M_PI / 18) * px_per_m, 6.0);
  EXPECT_NEAR(0.5 * (left + right), 160.0, 3.0);
  EXPECT_NEAR(0.5 * (top + bottom), 120.0, 3.0);
}

TEST(SceneSnapshot, FrustumLabelIsDrawnNextToTheApexInsideThePicture)
{
  // A frustum looking right from near the left edge: the label goes left of the apex,
  // away from the frustum, and is moved back inside the picture.
  const auto render = [](const std::string& label) {
    SceneSnapshot::Config config = frontCamera(320, 240);
    config.label_size_px = 20;
    SceneSnapshot snapshot(config);
    const Pose T_W_C(
        Eigen::Vector3d(2.0, 0.45, 0.0),
        Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitZ())));
    snapshot.addCameraFrustum(T_W_C, 1.0, 0.8, 0.3, distinctColor(2), label);
    return snapshot.renderImage();
  };
  const RgbImage plain = render("");
  const RgbImage labelled = render("3");
  // The apex in the picture (see the previous test for the scale).
  const double px_per_m = 120.0 / std::tan(M_PI / 12) / 2.0;
  const double apex_x = 160.0 - 0.45 * px_per_m;
  ASSERT_GT(apex_x, 0.0);
  std::size_t changed = 0, far_off = 0;
  for (int y = 0; y < plain.height; ++y)
    for (int x = 0; x < plain.width; ++x) {
      bool differs = false;
      for (int c = 0; c < 3; ++c)
        differs = differs || std::abs(plain.at(x, y)[c] - labelled.at(x, y)[c]) > 30;
      if (!differs)
        continue;
      ++changed;
      far_off += std::hypot(x - apex_x, y - 120.0) > 40.0;
    }
  EXPECT_GT(changed, 30u);
  EXPECT_EQ(far_off, 0u);
}

TEST(SceneSnapshot, FadedPlantWithVoxelsPathAndNumberedFrustums)
{
  // What `plantnbv reconstruct --snapshot` draws: the plant faded, occupied voxels
  // (here the 1 cm voxels of the plant's front half), the camera path and its views.
  const plantnbv::Plant& plant = paperPlant();
  std::set<std::tuple<int, int, int>> keys;
  for (const Eigen::Vector3f& v : plant.mesh.vertices)
    if (v.x() < 1.0f)
      keys.emplace(int(std::floor(v.x() / 0.01f)), int(std::floor(v.y() / 0.01f)),
                   int(std::floor(v.z() / 0.01f)));
  std::vector<Eigen::Vector3f> voxels;
  for (const auto& [i, j, k] : keys)
    voxels.emplace_back(0.01f * (i + 0.5f), 0.01f * (j + 0.5f), 0.01f * (k + 0.5f));
  const Eigen::Vector3d target(1.0, 0.0, 1.15);
  std::vector<Eigen::Vector3d> path;
  std::vector<Pose> views;
  for (int i = 0; i < 3; ++i) {
    const double angle = (i - 1) * 45.0 * M_PI / 180.0;
    path.emplace_back(
        target + Eigen::Vector3d(-0.5 * std::cos(angle), 0.5 * std::sin(angle), 0.1 * i));
    views.push_back(lookAt(path.back(), target));
  }

  SceneSnapshot snapshot;
  snapshot.addMesh(plant.mesh, 0.25);
  snapshot.addPoints(voxels, distinctColor(6), 4.0f);
  snapshot.addPolyline(path, distinctColor(7), 2.0f);
  for (std::size_t i = 0; i < views.size(); ++i)
    snapshot.addCameraFrustum(views[i], 69.0 * M_PI / 180.0, 42.0 * M_PI / 180.0, 0.15,
                              distinctColor(0), std::to_string(i + 1));
  // The automatic camera keeps every frustum in the picture.
  Eigen::Vector3d min, max;
  snapshot.bounds(min, max);
  for (const auto& p : path)
    EXPECT_TRUE((p.array() >= min.array() - 1e-6).all() &&
                (p.array() <= max.array() + 1e-6).all());

  const std::string path_png = outputPath("viz_nbv_snapshot.png");
  std::remove(path_png.c_str());
  snapshot.render(path_png);
  const RgbImage image = readPng(path_png);
  ASSERT_EQ(image.width, 1200);
  ASSERT_EQ(image.height, 900);
  std::size_t white = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      white += isWhite(image.at(x, y));
  EXPECT_LT(white / (1200.0 * 900.0), 0.97);
  EXPECT_GT(countNear(image, distinctColor(0), 8), 300u); // frustums
  EXPECT_GT(countNear(image, distinctColor(7), 8), 100u); // path (black)
}

TEST(SceneSnapshot, RejectsInvalidOpacityAndFrustums)
{
  using plantnbv::InvalidArgumentError;
  const plantnbv::TriangleMesh mesh = square(1.0, 0.1);
  SceneSnapshot snapshot;
  for (double opacity : {0.0, -0.5, 1.01, std::numeric_limits<double>::quiet_NaN()}) {
    EXPECT_THROW(snapshot.addMesh(mesh, opacity), InvalidArgumentError) << opacity;
    EXPECT_THROW(snapshot.addMesh(mesh, kBlue, opacity), InvalidArgumentError) << opacity;
  }
  try {
    snapshot.addMesh(mesh, kBlue, 1.5);
    FAIL() << "no exception";
  } catch (const InvalidArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("1.5"), std::string::npos) << e.what();
  }
  const Pose pose;
  EXPECT_THROW(snapshot.addCameraFrustum(pose, 0.0, 1.0, 0.2, kBlue),
               InvalidArgumentError);
  EXPECT_THROW(snapshot.addCameraFrustum(pose, 1.0, M_PI, 0.2, kBlue),
               InvalidArgumentError);
  EXPECT_THROW(snapshot.addCameraFrustum(pose, 1.0, 1.0, 0.0, kBlue),
               InvalidArgumentError);
  EXPECT_THROW(snapshot.addCameraFrustum(pose, 1.0, 1.0, 0.2, Rgb{2, 0, 0}),
               InvalidArgumentError);
  EXPECT_THROW(snapshot.addCameraFrustum(pose, 1.0, 1.0, 0.2, kBlue, "1", 0.0f),
               InvalidArgumentError);
  Pose broken;
  broken.position.x() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(snapshot.addCameraFrustum(broken, 1.0, 1.0, 0.2, kBlue),
               InvalidArgumentError);
  broken = Pose();
  broken.orientation.coeffs().setZero();
  EXPECT_THROW(snapshot.addCameraFrustum(broken, 1.0, 1.0, 0.2, kBlue),
               InvalidArgumentError);
  EXPECT_THROW(snapshot.addPolyline({Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()},
                                    kBlue, 25.0f),
               InvalidArgumentError);
  EXPECT_TRUE(snapshot.empty());

  SceneSnapshot::Config config;
  config.label_size_px = -1;
  EXPECT_THROW(SceneSnapshot{config}, InvalidArgumentError);
  EXPECT_NE(SceneSnapshot::Config().toString().find("label_size_px: 0"),
            std::string::npos);
}
