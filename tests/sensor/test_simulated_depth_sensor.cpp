#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/experiment/plant_scene.h>
#include <plantnbv/plant/tomato_plant_generator.h>
#include <plantnbv/sensor/simulated_depth_sensor.h>

#include "sensor_test_util.h"

using namespace plantnbv;
using test::makeQuad;
using test::pixelRay;

namespace {

const Eigen::Vector3d kX = Eigen::Vector3d::UnitX();
const Eigen::Vector3d kY = Eigen::Vector3d::UnitY();
const Eigen::Vector3d kZ = Eigen::Vector3d::UnitZ();

/// The paper's v0 (Table 1).
const Pose kV0 = Pose::fromXyzQuat(0.646, 0.353, 1.383, 0.0, 0.0, -0.383, 0.924);

SensorScene::Ptr sceneOf(const std::vector<TriangleMesh>& meshes)
{
  auto scene = std::make_shared<SensorScene>();
  for (const TriangleMesh& m : meshes)
    scene->addMesh(m);
  scene->commit();
  return scene;
}

bool isNaN(const pcl::PointXYZL& p)
{
  return std::isnan(p.x) && std::isnan(p.y) && std::isnan(p.z) && p.label == 0;
}

/// Bit-wise equality of two clouds' coordinates and labels (NaN == NaN; the padding of
/// pcl::PointXYZL is not compared).
bool samePoints(const CloudXYZL& a, const CloudXYZL& b)
{
  if (a.width != b.width || a.height != b.height || a.size() != b.size())
    return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(a.points[i].data, b.points[i].data, 3 * sizeof(float)) != 0 ||
        a.points[i].label != b.points[i].label)
      return false;
  return true;
}

std::size_t countReturns(const CloudXYZL& cloud)
{
  std::size_t n = 0;
  for (const auto& p : cloud.points)
    n += std::isfinite(p.x);
  return n;
}

} // namespace

TEST(SimulatedDepthSensor, OpticalFrameFollowsTheBodyFrame)
{
  const Pose T_W_O = opticalFrame(kV0);
  EXPECT_TRUE((T_W_O.orientation * kZ).isApprox(kV0.forward(), 1e-12));
  EXPECT_TRUE((T_W_O.orientation * kX).isApprox(-(kV0.orientation * kY), 1e-12));
  EXPECT_TRUE((T_W_O.orientation * kY).isApprox(-(kV0.orientation * kZ), 1e-12));
  EXPECT_TRUE(T_W_O.position.isApprox(kV0.position));
}

TEST(SimulatedDepthSensor, DepthOfAPlaneIsExact)
{
  // Facing the camera at 1.3 m: every pixel's depth is 1.3.
  const CameraIntrinsics K = CameraIntrinsics::l515(L515Mode::vga_640x480);
  SimulatedDepthSensor sensor(K);
  sensor.setScene(sceneOf({makeQuad(Eigen::Vector3d(1.3, 0, 0), kY, kZ, 2.0)}));
  CloudXYZL cloud;
  DepthImage depth;
  sensor.capture(Pose(), cloud, &depth);
  ASSERT_EQ(cloud.width, 640u);
  ASSERT_EQ(cloud.height, 480u);
  ASSERT_EQ(cloud.size(), 640u * 480u);
  EXPECT_TRUE(cloud.is_dense);
  ASSERT_EQ(depth.depth_m.size(), cloud.size());
  double worst = 0.0;
  for (std::uint32_t v = 0; v < K.height; ++v)
    for (std::uint32_t u = 0; u < K.width; ++u) {
      const pcl::PointXYZL& p = cloud.at(u, v);
      worst = std::max(worst, std::abs(depth.at(u, v) - 1.3));
      worst = std::max(worst, std::abs(p.x - 1.3));
      const Eigen::Vector3d expected =
          1.3 / pixelRay(K, Pose(), u, v).x() * pixelRay(K, Pose(), u, v);
      worst = std::max(worst, (p.getVector3fMap().cast<double>() - expected).norm());
      EXPECT_EQ(p.label, std::uint32_t(PartLabel::leaflet));
    }
  EXPECT_LT(worst, 1e-5);
}

TEST(SimulatedDepthSensor, TiltedPlaneFromAnyPoseIsExact)
{
  // A plane through c with normal n, seen from v0: each pixel's point is the exact
  // ray-plane intersection (so pixels map to rays as the intrinsics say).
  const CameraIntrinsics K = CameraIntrinsics::l515(L515Mode::qvga_320x240);
  const Eigen::Vector3d c(1.0, 0.0, 1.2);
  const Eigen::Vector3d n = Eigen::Vector3d(-0.8, 0.3, 0.5).normalized();
  const Eigen::Vector3d a = n.unitOrthogonal(), b = n.cross(a);
  SimulatedDepthSensor sensor(K);
  sensor.setScene(sceneOf({makeQuad(c, a, b, 3.0)}));
  CloudXYZL cloud;
  DepthImage depth;
  sensor.capture(kV0, cloud, &depth);
  const Eigen::Vector3d o = kV0.position;
  const Eigen::Vector3d z_O = kV0.forward();
  double worst = 0.0;
  std::size_t hits = 0;
  for (std::uint32_t v = 0; v < K.height; ++v)
    for (std::uint32_t u = 0; u < K.width; ++u) {
      const Eigen::Vector3d d = pixelRay(K, kV0, u, v);
      const double t = (c - o).dot(n) / d.dot(n);
      const pcl::PointXYZL& p = cloud.at(u, v);
      if (!(t > 0.25 && t < 9.0)) {
        EXPECT_TRUE(isNaN(p));
        continue;
      }
      ++hits;
      const Eigen::Vector3d expected = o + t * d;
      worst = std::max(worst, (p.getVector3fMap().cast<double>() - expected).norm());
      worst = std::max(worst, std::abs(depth.at(u, v) - (expected - o).dot(z_O)));
    }
  EXPECT_GT(hits, K.pixelCount() / 2);
  EXPECT_LT(worst, 1e-5);
}

TEST(SimulatedDepthSensor, ImageAxesPointRightAndDown)
{
  // Identity pose: optical z = world x, x right = world -y, y down = world -z.
  const CameraIntrinsics K = test::smallCamera();
  SimulatedDepthSensor sensor(K);
  // One quad to the right (world y < 0), one above (world z > 0).
  sensor.setScene(
      sceneOf({makeQuad(Eigen::Vector3d(1.0, -0.3, 0.0), kY, kZ, 0.1, PartLabel::fruit),
               makeQuad(Eigen::Vector3d(1.0, 0.0, 0.3), kY, kZ, 0.1, PartLabel::stem)}));
  CloudXYZL cloud;
  sensor.capture(Pose(), cloud);
  std::size_t fruit = 0, stem = 0;
  for (std::uint32_t v = 0; v < K.height; ++v)
    for (std::uint32_t u = 0; u < K.width; ++u) {
      const std::uint32_t label = cloud.at(u, v).label;
      if (label == std::uint32_t(PartLabel::fruit)) {
        ++fruit;
        EXPECT_GT(u, K.cx);
      } else if (label == std::uint32_t(PartLabel::stem)) {
        ++stem;
        EXPECT_LT(v, K.cy);
      }
    }
  EXPECT_GT(fruit, 50u);
  EXPECT_GT(stem, 50u);
}

TEST(SimulatedDepthSensor, DepthOfASphereIsExact)
{
  // A UV sphere of radius 0.2 centred 1 m ahead, a pole facing the camera: the centre
  // pixel hits that pole vertex at depth 0.8 exactly; every pixel matches a double
  // precision ray-triangle reference, and lies between the sphere and its chords.
  const double radius = 0.2, distance = 1.0;
  const int rings = 32, segments = 64; // 4,096 triangles: the reference is brute force
  const Eigen::Vector3d centre(distance, 0.0, 0.0);
  const TriangleMesh sphere = test::makeUvSphere(centre, radius, kX, rings, segments);
  const CameraIntrinsics K = test::smallCamera(101, 81, 200.0);
  SimulatedDepthSensor sensor(K);
  sensor.setScene(sceneOf({sphere}));
  CloudXYZL cloud;
  DepthImage depth;
  sensor.capture(Pose(), cloud, &depth);

  const std::uint32_t uc = std::uint32_t(K.cx), vc = std::uint32_t(K.cy);
  EXPECT_NEAR(depth.at(uc, vc), distance - radius, 1e-5);
  EXPECT_EQ(cloud.at(uc, vc).label, std::uint32_t(PartLabel::fruit));

  // Largest radial gap between the sphere and the mesh: 3 times the sagitta of an edge
  // (the triangles of a cell span its diagonal); along a ray, divided by the cosine of
  // the incidence angle.
  const double sag = 3.0 * radius * (1.0 - std::cos(0.5 * M_PI / rings));
  double worst = 0.0;
  std::size_t hits = 0;
  for (std::uint32_t v = 0; v < K.height; ++v)
    for (std::uint32_t u = 0; u < K.width; ++u) {
      const Eigen::Vector3d d = pixelRay(K, Pose(), u, v);
      const double reference = test::referenceRange(sphere, Eigen::Vector3d::Zero(), d);
      const float z = depth.at(u, v);
      if (!std::isfinite(reference)) {
        EXPECT_TRUE(std::isnan(z)) << u << " " << v;
        continue;
      }
      ++hits;
      ASSERT_TRUE(std::isfinite(z)) << u << " " << v;
      worst = std::max(worst, std::abs(z - reference * d.x()));
      // The analytic sphere: nearest root of |t d - c| = r.
      const double b = d.dot(centre);
      const double disc = b * b - (centre.squaredNorm() - radius * radius);
      ASSERT_GE(disc, 0.0);
      const double t_sphere = b - std::sqrt(disc);
      EXPECT_GE(z, t_sphere * d.x() - 1e-5);
      const double cos_incidence = std::sqrt(disc) / radius;
      if (cos_incidence > 0.1) { // away from the silhouette
        EXPECT_LE(z, t_sphere * d.x() + sag / cos_incidence) << u << " " << v;
      }
    }
  EXPECT_GT(hits, 1000u);
  EXPECT_LT(worst, 1e-5);
}

TEST(SimulatedDepthSensor, HitsCarryTheirTriangleLabels)
{
  // Left half leaflet, right half fruit, in one mesh with per-triangle labels; a second
  // mesh without labels gets the default label.
  TriangleMesh mesh =
      makeQuad(Eigen::Vector3d(1.0, 0.25, 0.0), kY, kZ, 0.25, PartLabel::leaflet);
  mesh.append(makeQuad(Eigen::Vector3d(1.0, -0.25, 0.0), kY, kZ, 0.25, PartLabel::fruit));
  TriangleMesh unlabelled = makeQuad(Eigen::Vector3d(2.0, 0.0, 0.0), kY, kZ, 5.0);
  unlabelled.labels.clear();
  auto scene = std::make_shared<SensorScene>();
  scene->addMesh(mesh);
  scene->addMesh(unlabelled, PartLabel::background);
  scene->commit();
  const CameraIntrinsics K = test::smallCamera();
  SimulatedDepthSensor sensor(K);
  sensor.setScene(scene);
  CloudXYZL cloud;
  sensor.capture(Pose(), cloud);
  std::size_t counts[7] = {};
  for (std::uint32_t v = 0; v < K.height; ++v)
    for (std::uint32_t u = 0; u < K.width; ++u) {
      const pcl::PointXYZL& p = cloud.at(u, v);
      ASSERT_TRUE(std::isfinite(p.x));
      ASSERT_LT(p.label, 7u);
      ++counts[p.label];
      if (std::abs(p.y) < 1e-6f)
        continue; // the edge both halves share
      if (std::abs(p.x - 1.0f) < 1e-4f)
        EXPECT_EQ(p.label, p.y > 0 ? std::uint32_t(PartLabel::leaflet)
                                   : std::uint32_t(PartLabel::fruit));
      else
        EXPECT_EQ(p.label, std::uint32_t(PartLabel::background));
    }
  EXPECT_GT(counts[std::uint32_t(PartLabel::leaflet)], 100u);
  EXPECT_GT(counts[std::uint32_t(PartLabel::fruit)], 100u);
  EXPECT_GT(counts[std::uint32_t(PartLabel::background)], 100u);
}

TEST(SimulatedDepthSensor, BackFacesAreHit)
{
  const TriangleMesh front = makeQuad(Eigen::Vector3d(1.0, 0, 0), kY, kZ, 2.0);
  const TriangleMesh back = test::flipped(front);
  const CameraIntrinsics K = test::smallCamera();
  SimulatedDepthSensor sensor(K);
  CloudXYZL a, b;
  sensor.setScene(sceneOf({front}));
  sensor.capture(Pose(), a);
  sensor.setScene(sceneOf({back}));
  sensor.capture(Pose(), b);
  EXPECT_EQ(countReturns(a), K.pixelCount());
  ASSERT_EQ(countReturns(b), K.pixelCount());
  for (std::size_t i = 0; i < a.size(); ++i) // same depths (the triangles' vertex order
    EXPECT_NEAR(a.points[i].x, b.points[i].x, 1e-6f); // differs: not bit-identical)
  // Seen from behind (camera at x = 2 looking back along -x).
  const Pose behind(Eigen::Vector3d(2.0, 0, 0), Eigen::Quaterniond(0, 0, 0, 1));
  sensor.capture(behind, b);
  EXPECT_EQ(countReturns(b), K.pixelCount());
  EXPECT_NEAR(b.at(32, 24).x, 1.0f, 1e-6f);
}

TEST(SimulatedDepthSensor, PixelsOutsideTheRangeLimitsAreNaN)
{
  // A small near quad at 0.2 m (inside min range 0.25) hides part of a wall at 1 m.
  const CameraIntrinsics K0 = test::smallCamera();
  auto scene = sceneOf({makeQuad(Eigen::Vector3d(1.0, 0, 0), kY, kZ, 2.0),
                        makeQuad(Eigen::Vector3d(0.2, 0, 0), kY, kZ, 0.02)});
  SimulatedDepthSensor sensor(K0);
  sensor.setScene(scene);
  CloudXYZL cloud;
  CloudXYZ far;
  DepthImage depth;
  sensor.capture(Pose(), cloud, &depth, &far);
  EXPECT_FALSE(cloud.is_dense);
  EXPECT_TRUE(isNaN(cloud.at(32, 24))); // the near quad: no return, and it occludes
  EXPECT_TRUE(std::isnan(depth.at(32, 24)));
  EXPECT_NEAR(cloud.at(0, 0).x, 1.0f, 1e-6f);
  EXPECT_EQ(far.size(), 0u);
  const std::size_t near_pixels = K0.pixelCount() - countReturns(cloud);
  EXPECT_GT(near_pixels, 10u);

  // Far limit 0.9 m: the wall is beyond it, so every pixel but the near ones is NaN and
  // becomes a far point at exactly 0.9 m along its ray.
  CameraIntrinsics K = K0;
  K.max_range_m = 0.9;
  sensor.setIntrinsics(K);
  sensor.capture(Pose(), cloud, &depth, &far);
  EXPECT_EQ(countReturns(cloud), 0u);
  for (const pcl::PointXYZL& p : cloud.points)
    EXPECT_TRUE(isNaN(p));
  for (float z : depth.depth_m)
    EXPECT_TRUE(std::isnan(z));
  ASSERT_EQ(far.size(), K.pixelCount() - near_pixels);
  EXPECT_EQ(far.width, far.size());
  EXPECT_EQ(far.height, 1u);
  for (const pcl::PointXYZ& q : far.points)
    EXPECT_NEAR(q.getVector3fMap().norm(), 0.9f, 1e-6f);
  // The first far point is pixel (0, 0)'s.
  EXPECT_LT(
      (far.points[0].getVector3fMap().cast<double>() - 0.9 * pixelRay(K, Pose(), 0, 0))
          .norm(),
      1e-6);

  // A ray that meets nothing gives neither a point nor a far point.
  sensor.setScene(sceneOf({makeQuad(Eigen::Vector3d(-1.0, 0, 0), kY, kZ, 1.0)}));
  sensor.capture(Pose(), cloud, &depth, &far);
  EXPECT_EQ(countReturns(cloud), 0u);
  EXPECT_EQ(far.size(), 0u);
}

TEST(SimulatedDepthSensor, SurfelsRenderADensePlane)
{
  // 40k random points on the plane x = 1 within |y|, |z| < 0.2 (spacing about 2 mm).
  Rng rng(7);
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < 40000; ++i)
    points.emplace_back(1.0f, float(rng.uniform(-0.2, 0.2)),
                        float(rng.uniform(-0.2, 0.2)));
  const std::vector<float> radii = surfelRadii(points);
  const float max_radius = *std::max_element(radii.begin(), radii.end());
  EXPECT_LT(max_radius, 0.02f);

  const CameraIntrinsics K = test::smallCamera(101, 81, 150.0);
  SimulatedDepthSensor sensor(K);
  CloudXYZL cloud;
  DepthImage depth;
  for (bool oriented : {false, true}) {
    auto scene = std::make_shared<SensorScene>();
    if (oriented)
      scene->addSurfels(
          points, std::vector<PartLabel>(points.size(), PartLabel::leaflet),
          std::vector<Eigen::Vector3f>(points.size(), -Eigen::Vector3f::UnitX()));
    else
      scene->addSurfels(points,
                        std::vector<PartLabel>(points.size(), PartLabel::leaflet));
    scene->commit();
    sensor.setScene(scene);
    sensor.capture(Pose(), cloud, &depth);
    std::size_t inside = 0, covered = 0;
    double worst = 0.0;
    for (std::uint32_t v = 0; v < K.height; ++v)
      for (std::uint32_t u = 0; u < K.width; ++u) {
        const Eigen::Vector3d d = pixelRay(K, Pose(), u, v);
        const Eigen::Vector3d on_plane = d / d.x();
        if (std::abs(on_plane.y()) > 0.18 || std::abs(on_plane.z()) > 0.18)
          continue; // near the cloud's border discs may be missing
        ++inside;
        const pcl::PointXYZL& p = cloud.at(u, v);
        if (!std::isfinite(p.x))
          continue;
        ++covered;
        EXPECT_EQ(p.label, std::uint32_t(PartLabel::leaflet));
        worst = std::max(worst, std::abs(depth.at(u, v) - 1.0));
      }
    EXPECT_GT(inside, 2000u);
    EXPECT_GE(covered, inside * 998 / 1000) << (oriented ? "oriented" : "ray-facing");
    if (oriented)
      EXPECT_LT(worst, 1e-5); // discs in the plane give its exact depth
    else
      EXPECT_LE(worst, max_radius);
  }
}

TEST(SimulatedDepthSensor, SeesThePlantFromTheInitialView)
{
  // v0 of Table 1 looks at the stem of a default plant standing at (1.0, 0, 0.8).
  Plant plant = TomatoPlantGenerator(defaultPlantConfig(3)).generate();
  posePlant(plant, Eigen::Vector3d(1.0, 0.0, 0.8), 0.0);
  SimulatedDepthSensor sensor(CameraIntrinsics::l515(L515Mode::xga_1024x768));
  sensor.setScene(makePlantScene(plant));
  CloudXYZL cloud;
  sensor.capture(kV0, cloud);
  std::size_t counts[7] = {};
  for (const auto& p : cloud.points)
    if (std::isfinite(p.x))
      ++counts[std::min<std::uint32_t>(p.label, 6)];
  EXPECT_GT(counts[std::uint32_t(PartLabel::stem)], 2000u);
  EXPECT_GT(counts[std::uint32_t(PartLabel::leaflet)], 10000u);
  EXPECT_GT(counts[std::uint32_t(PartLabel::background)], 10000u); // floor and support
  EXPECT_EQ(counts[std::uint32_t(PartLabel::unknown)], 0u);
  // The stem is straight ahead: the centre column has stem pixels.
  std::size_t centre_stem = 0;
  for (std::uint32_t v = 0; v < cloud.height; ++v)
    for (std::uint32_t u = 500; u < 524; ++u)
      centre_stem += cloud.at(u, v).label == std::uint32_t(PartLabel::stem);
  EXPECT_GT(centre_stem, 100u);

  // Without floor and support nothing is background.
  PlantSceneConfig bare;
  bare.floor = bare.support = false;
  sensor.setScene(makePlantScene(plant, bare));
  sensor.capture(kV0, cloud);
  for (const auto& p : cloud.points)
    ASSERT_NE(p.label, std::uint32_t(PartLabel::background));
}

namespace {

/// A plant scene shared by the determinism tests.
SensorScene::ConstPtr plantScene()
{
  static SensorScene::ConstPtr scene = [] {
    Plant plant = TomatoPlantGenerator(defaultPlantConfig(3)).generate();
    posePlant(plant, Eigen::Vector3d(1.0, 0.0, 0.8), 0.0);
    return makePlantScene(plant);
  }();
  return scene;
}

struct Frame {
  CloudXYZL cloud;
  DepthImage depth;
  CloudXYZ far;
};

Frame captureFrame(SimulatedDepthSensor& sensor, const Pose& pose)
{
  Frame f;
  sensor.capture(pose, f.cloud, &f.depth, &f.far);
  return f;
}

bool sameFrame(const Frame& a, const Frame& b)
{
  return samePoints(a.cloud, b.cloud) &&
         a.depth.depth_m.size() == b.depth.depth_m.size() &&
         std::memcmp(a.depth.depth_m.data(), b.depth.depth_m.data(),
                     a.depth.depth_m.size() * sizeof(float)) == 0 &&
         a.far.size() == b.far.size() &&
         std::equal(a.far.begin(), a.far.end(), b.far.begin(),
                    [](const pcl::PointXYZ& p, const pcl::PointXYZ& q) {
                      return std::memcmp(p.data, q.data, 3 * sizeof(float)) == 0;
                    });
}

/// Noise with only the named part on.
NoiseConfig onlyNoise(double axial_sigma_m, double lateral_sigma_px,
                      double grazing_start_rad, double edge_dropout_probability)
{
  NoiseConfig n;
  n.enabled = true;
  n.seed = 11;
  n.axial_sigma_m = axial_sigma_m;
  n.axial_sigma_per_m = 0.0;
  n.lateral_sigma_px = lateral_sigma_px;
  n.grazing_start_rad = grazing_start_rad;
  n.grazing_end_rad =
      std::max(grazing_start_rad, std::min(M_PI / 2, 85.0 * M_PI / 180.0));
  n.edge_dropout_probability = edge_dropout_probability;
  return n;
}

} // namespace

TEST(SimulatedDepthSensor, FramesAreIdenticalAcrossRunsAndThreadCounts)
{
  const Pose pose = kV0;
  for (bool noisy : {false, true}) {
    NoiseConfig noise;
    noise.enabled = noisy;
    noise.seed = 42;
    // Far limit inside the scene, so that far points are produced too.
    CameraIntrinsics K = CameraIntrinsics::l515(L515Mode::vga_640x480);
    K.max_range_m = 1.5;
    std::vector<Frame> frames;
    for (unsigned int threads : {1u, 2u, 3u, 1u}) {
      SimulatedDepthSensor sensor(K);
      sensor.setScene(plantScene());
      sensor.setNoise(noise);
      sensor.setNumberOfThreads(threads);
      frames.push_back(captureFrame(sensor, pose));
    }
    EXPECT_GT(countReturns(frames[0].cloud), 10000u);
    EXPECT_GT(frames[0].far.size(), 1000u);
    for (std::size_t i = 1; i < frames.size(); ++i)
      EXPECT_TRUE(sameFrame(frames[0], frames[i])) << "noise " << noisy << " run " << i;
  }
}

TEST(SimulatedDepthSensor, NoiseDependsOnSeedAndFrame)
{
  NoiseConfig noise;
  noise.enabled = true;
  noise.seed = 1;
  SimulatedDepthSensor sensor(CameraIntrinsics::l515(L515Mode::qvga_320x240));
  sensor.setScene(plantScene());
  SimulatedDepthSensor clean(CameraIntrinsics::l515(L515Mode::qvga_320x240));
  clean.setScene(plantScene());
  sensor.setNoise(noise);
  EXPECT_EQ(sensor.getFrameIndex(), 0u);
  const Frame first = captureFrame(sensor, kV0);
  EXPECT_EQ(sensor.getFrameIndex(), 1u);
  EXPECT_EQ(first.cloud.header.seq, 0u);
  const Frame second = captureFrame(sensor, kV0);
  EXPECT_FALSE(sameFrame(first, second)); // every frame draws new noise
  sensor.setFrameIndex(0);
  EXPECT_TRUE(sameFrame(first, captureFrame(sensor, kV0)));
  noise.seed = 2;
  sensor.setNoise(noise); // restarts at frame 0
  EXPECT_FALSE(sameFrame(first, captureFrame(sensor, kV0)));
  EXPECT_FALSE(sameFrame(first, captureFrame(clean, kV0)));
}

TEST(SimulatedDepthSensor, AxialNoiseHasTheConfiguredSigma)
{
  // A wall 1-1.3 m away filling the image: (noisy - true range) / sigma(true range)
  // must be standard normal.
  const CameraIntrinsics K = CameraIntrinsics::l515(L515Mode::vga_640x480);
  SimulatedDepthSensor sensor(K);
  sensor.setScene(sceneOf({makeQuad(Eigen::Vector3d(1.0, 0, 0), kY, kZ, 2.0)}));
  NoiseConfig noise = onlyNoise(0.0, 0.0, M_PI / 2, 0.0);
  noise.axial_sigma_m = 0.001;
  noise.axial_sigma_per_m = 0.004;
  sensor.setNoise(noise);
  CloudXYZL cloud;
  DepthImage depth;
  sensor.capture(Pose(), cloud, &depth);
  ASSERT_EQ(countReturns(cloud), K.pixelCount());
  double sum = 0.0, sum_sq = 0.0;
  for (std::uint32_t v = 0; v < K.height; ++v)
    for (std::uint32_t u = 0; u < K.width; ++u) {
      const Eigen::Vector3d d = pixelRay(K, Pose(), u, v);
      const double true_range = 1.0 / d.x();
      const Eigen::Vector3d p = cloud.at(u, v).getVector3fMap().cast<double>();
      // Still on the pixel's ray, and the depth image agrees with the point.
      ASSERT_LT((p - p.norm() * d).norm(), 1e-5);
      ASSERT_NEAR(depth.at(u, v), p.x(), 1e-5);
      const double z = (p.norm() - true_range) / noise.axialSigma(true_range);
      sum += z;
      sum_sq += z * z;
    }
  const double n = double(K.pixelCount());
  const double mean = sum / n, sd = std::sqrt(sum_sq / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.01);
  EXPECT_NEAR(sd, 1.0, 0.01);
}

TEST(SimulatedDepthSensor, LateralJitterMovesPointsAlongTheSurface)
{
  const CameraIntrinsics K = CameraIntrinsics::l515(L515Mode::qvga_320x240);
  SimulatedDepthSensor sensor(K);
  sensor.setScene(sceneOf({makeQuad(Eigen::Vector3d(1.0, 0, 0), kY, kZ, 2.0)}));
  sensor.setNoise(onlyNoise(0.0, 0.5, M_PI / 2, 0.0));
  CloudXYZL cloud;
  sensor.capture(Pose(), cloud);
  ASSERT_EQ(countReturns(cloud), K.pixelCount());
  double sum = 0.0, sum_sq = 0.0;
  for (std::uint32_t v = 0; v < K.height; ++v)
    for (std::uint32_t u = 0; u < K.width; ++u) {
      const pcl::PointXYZL& p = cloud.at(u, v);
      ASSERT_NEAR(p.x, 1.0f, 1e-5f); // on the wall
      // Reprojection: optical x = -world y.
      const double du = K.cx + K.fx * (-p.y / p.x) - u;
      sum += du;
      sum_sq += du * du;
    }
  const double n = double(K.pixelCount());
  const double mean = sum / n, sd = std::sqrt(sum_sq / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.01);
  EXPECT_NEAR(sd, 0.5, 0.01);
}

TEST(SimulatedDepthSensor, GrazingAnglesDropReturns)
{
  // A narrow camera (about 1 deg) and a wall turned so that rays meet it at 80 deg:
  // the default ramp (70-85 deg) drops 2/3 of the pixels; at 60 deg none.
  const CameraIntrinsics K = test::smallCamera(65, 49, 3000.0);
  NoiseConfig noise = onlyNoise(0.0, 0.0, 70.0 * M_PI / 180.0, 0.0);
  for (double incidence_deg : {80.0, 60.0}) {
    const double a = incidence_deg * M_PI / 180.0;
    const Eigen::Vector3d normal(-std::cos(a), std::sin(a), 0.0);
    SimulatedDepthSensor sensor(K);
    sensor.setScene(sceneOf(
        {makeQuad(Eigen::Vector3d(1.0, 0, 0), kZ, normal.cross(kZ).normalized(), 1.0)}));
    sensor.setNoise(noise);
    CloudXYZL cloud;
    sensor.capture(Pose(), cloud);
    const double kept = double(countReturns(cloud)) / double(K.pixelCount());
    if (incidence_deg > 70.0)
      EXPECT_NEAR(1.0 - kept, noise.grazingDropoutProbability(a), 0.03);
    else
      EXPECT_EQ(kept, 1.0);
  }
}

TEST(SimulatedDepthSensor, DepthEdgesDropReturns)
{
  // A square 1 m away in front of a wall at 2 m: only pixels next to the square's
  // outline (range jump > 1 cm) may drop, about half of them.
  const CameraIntrinsics K = test::smallCamera(101, 81, 100.0);
  SimulatedDepthSensor sensor(K);
  sensor.setScene(sceneOf({makeQuad(Eigen::Vector3d(2.0, 0, 0), kY, kZ, 3.0),
                           makeQuad(Eigen::Vector3d(1.0, 0, 0), kY, kZ, 0.15)}));
  DepthImage clean;
  CloudXYZL cloud;
  sensor.capture(Pose(), cloud, &clean);
  ASSERT_EQ(countReturns(cloud), K.pixelCount());
  sensor.setNoise(onlyNoise(0.0, 0.0, M_PI / 2, 0.5));
  sensor.capture(Pose(), cloud);
  std::size_t edge = 0, edge_dropped = 0;
  for (std::uint32_t v = 0; v < K.height; ++v)
    for (std::uint32_t u = 0; u < K.width; ++u) {
      const float z = clean.at(u, v);
      bool on_edge = false;
      if (u > 0)
        on_edge |= std::abs(clean.at(u - 1, v) - z) > 0.5f;
      if (u + 1 < K.width)
        on_edge |= std::abs(clean.at(u + 1, v) - z) > 0.5f;
      if (v > 0)
        on_edge |= std::abs(clean.at(u, v - 1) - z) > 0.5f;
      if (v + 1 < K.height)
        on_edge |= std::abs(clean.at(u, v + 1) - z) > 0.5f;
      const bool dropped = !std::isfinite(cloud.at(u, v).x);
      if (on_edge) {
        ++edge;
        edge_dropped += dropped;
      } else {
        EXPECT_FALSE(dropped) << u << " " << v;
      }
    }
  EXPECT_GT(edge, 100u);
  EXPECT_NEAR(double(edge_dropped) / double(edge), 0.5, 0.1);
}

TEST(SimulatedDepthSensor, ARayMaskCastsOnlyItsPixels)
{
  CameraIntrinsics K = CameraIntrinsics::l515(L515Mode::vga_640x480);
  K.max_range_m = 1.5; // far points too
  SimulatedDepthSensor sensor(K);
  sensor.setScene(plantScene());
  sensor.setNumberOfThreads(2);
  const Frame full = captureFrame(sensor, kV0);

  // Every pixel in the mask: the frame without one.
  auto all = std::make_shared<RayMask>(K, opticalFrame(kV0), K.max_range_m);
  all->addAll();
  sensor.setRayMask(all);
  EXPECT_TRUE(sameFrame(captureFrame(sensor, kV0), full));

  // Part of the plant: its pixels as without a mask, the others no return.
  auto part = std::make_shared<RayMask>(K, opticalFrame(kV0), K.max_range_m);
  const double lo[3] = {0.9, -0.15, 1.0}, hi[3] = {1.1, 0.15, 1.3};
  part->addBox(lo, hi);
  const std::size_t pixels = std::size_t(K.width) * K.height;
  ASSERT_GT(part->pixelCount(), pixels / 20);
  ASSERT_LT(part->pixelCount(), pixels / 2);
  sensor.setRayMask(part);
  const Frame masked = captureFrame(sensor, kV0);
  std::size_t returns = 0;
  for (std::uint32_t v = 0; v < K.height; ++v)
    for (std::uint32_t u = 0; u < K.width; ++u) {
      const std::size_t i = std::size_t(v) * K.width + u;
      const pcl::PointXYZL& p = masked.cloud.points[i];
      if (part->containsPixel(u, v)) {
        ASSERT_EQ(std::memcmp(p.data, full.cloud.points[i].data, 3 * sizeof(float)), 0);
        ASSERT_EQ(p.label, full.cloud.points[i].label);
        ASSERT_EQ(std::memcmp(&masked.depth.depth_m[i], &full.depth.depth_m[i],
                              sizeof(float)),
                  0);
        returns += std::isfinite(p.x);
      } else {
        ASSERT_TRUE(isNaN(p)) << u << ", " << v;
        ASSERT_TRUE(std::isnan(masked.depth.depth_m[i]));
      }
    }
  EXPECT_GT(returns, 1000u);
  EXPECT_LT(countReturns(masked.cloud), countReturns(full.cloud));
  // The far points: those of the masked pixels, in the same (pixel) order.
  EXPECT_GT(masked.far.size(), 0u);
  EXPECT_LT(masked.far.size(), full.far.size());
  std::size_t next = 0;
  for (const pcl::PointXYZ& q : masked.far) {
    while (next < full.far.size() &&
           std::memcmp(full.far[next].data, q.data, 3 * sizeof(float)) != 0)
      ++next;
    ASSERT_LT(next, full.far.size()) << "a far point of no pixel of the full frame";
    ++next;
  }

  // Back to every pixel.
  sensor.setRayMask(nullptr);
  EXPECT_TRUE(sameFrame(captureFrame(sensor, kV0), full));
}

TEST(SimulatedDepthSensor, ARayMaskOfAnotherImageSizeIsRejected)
{
  const CameraIntrinsics vga = CameraIntrinsics::l515(L515Mode::vga_640x480);
  const CameraIntrinsics xga = CameraIntrinsics::l515(L515Mode::xga_1024x768);
  SimulatedDepthSensor sensor(vga);
  sensor.setScene(plantScene());
  EXPECT_THROW(sensor.setRayMask(std::make_shared<RayMask>(xga, Pose(), 1.0)),
               InvalidArgumentError);
  EXPECT_EQ(sensor.getRayMask(), nullptr);
  sensor.setRayMask(std::make_shared<RayMask>(vga, Pose(), 1.0));
  sensor.setIntrinsics(xga);
  CloudXYZL cloud;
  EXPECT_THROW(sensor.capture(kV0, cloud), InvalidArgumentError);
}
