/// \file bench_sensor.cpp
/// \brief Rendering a depth frame of a plant, ours (Embree 3 packets,
/// SimulatedDepthSensor) side by side with what users of PCL / VTK would write instead:
/// one vtkCellLocator::IntersectWithLine per pixel; the cost of building the BVH; and a
/// trial's ten frames with every pixel cast or only those whose rays can reach the map's
/// update region (BM_EmbreeCaptureInRegion, as a campaign trial casts them).
///
/// Data: the oldest default tomato plant (defaultPlantConfig(9)) at mesh_detail 1.1,
/// about 300k triangles, posed at the paper's (1.0, 0, 0.8), seen from the paper's v0
/// (Table 1) with the L515 at 640 x 480 and 1024 x 768. Two scenes: the plant alone
/// (10% of the pixels hit it) and the default scene of the experiments (plant, floor
/// and support: 32% of the pixels have a return within the L515's 9 m; the rest look
/// above the horizon or hit the floor farther away). Counters: hits = fraction of pixels
/// with a return, triangles = scene size.
///
/// VTK's locator is not thread-safe for IntersectWithLine and takes seconds per frame,
/// so it casts the rays of every 8th pixel in each direction (1/64 of the frame, on one
/// thread) and the time reported is that, times 64: an extrapolation to a full frame.
/// Only the plant-alone scene by default (see the registration below).
/// Counter vtk_mismatch counts the sampled pixels where VTK's first hit and ours differ
/// by more than 0.1 mm (or one hits and the other not). Run:
///   bench_sensor --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <benchmark/benchmark.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/camera/optical_frame.h>
#include <plantnbv/camera/ray_mask.h>
#include <plantnbv/experiment/plant_scene.h>
#include <plantnbv/experiment/region_ray_mask.h>
#include <plantnbv/octree/update_region.h>
#include <plantnbv/planning/cylindrical_sector_sampler.h>
#include <plantnbv/plant/tomato_plant_generator.h>
#include <plantnbv/sensor/simulated_depth_sensor.h>

#ifdef PLANTNBV_BENCH_VTK
#include <vtkCellArray.h>
#include <vtkCellLocator.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#endif

#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

namespace {

using namespace plantnbv;

const Pose kV0 = Pose::fromXyzQuat(0.646, 0.353, 1.383, 0.0, 0.0, -0.383, 0.924);
constexpr double kResolutionM = 0.003; ///< the paper's map (Table 1)
constexpr double kMapRangeM = 0.75;

const Plant& benchPlant()
{
  static const Plant plant = [] {
    TomatoPlantGenerator::Config config = defaultPlantConfig(9);
    config.mesh_detail = 1.1;
    Plant p = TomatoPlantGenerator(config).generate();
    posePlant(p, Eigen::Vector3d(1.0, 0.0, 0.8), 0.0);
    return p;
  }();
  return plant;
}

/// The scene: the plant alone, or with floor and support (makePlantScene's default).
SensorScene::Ptr benchScene(bool background)
{
  static SensorScene::Ptr scenes[2];
  SensorScene::Ptr& scene = scenes[background ? 1 : 0];
  if (!scene) {
    PlantSceneConfig config;
    config.floor = config.support = background;
    scene = makePlantScene(benchPlant(), config);
  }
  return scene;
}

CameraIntrinsics camera(int width)
{
  return CameraIntrinsics::l515(width == 640 ? L515Mode::vga_640x480
                                             : L515Mode::xga_1024x768);
}

std::size_t returns(const CloudXYZL& cloud)
{
  std::size_t n = 0;
  for (const auto& p : cloud.points)
    n += std::isfinite(p.x);
  return n;
}

/// Args: width (640 or 1024), threads, background (0 or 1).
void BM_EmbreeCapture(benchmark::State& state)
{
  const int width = int(state.range(0));
  const unsigned int threads = unsigned(state.range(1));
  const bool background = state.range(2) != 0;
  SimulatedDepthSensor sensor(camera(width));
  sensor.setScene(benchScene(background));
  sensor.setNumberOfThreads(threads);
  CloudXYZL cloud;
  sensor.capture(kV0, cloud); // warm-up: buffers allocated
  for (auto _ : state) {
    sensor.capture(kV0, cloud);
    benchmark::DoNotOptimize(cloud.points.data());
  }
  state.counters["threads"] = threads;
  state.counters["hits"] = double(returns(cloud)) / double(cloud.size());
  state.counters["triangles"] = double(benchScene(background)->triangleCount());
}

/// The views of a trial on the bench plant: v0 and the centres of the paper's sector's
/// 3 x 3 grid cells.
std::vector<Pose> trialViews()
{
  std::vector<Pose> views = CylindricalSectorSampler().gridCellCentres();
  views.insert(views.begin(), kV0);
  return views;
}

/// The region a campaign trial of the bench plant updates, less its ROI boxes: the
/// bricks around every triangle of the scene at the paper's 3 mm, over the views' reach
/// (Trial's surface region).
const UpdateRegion& trialRegion(bool background)
{
  static std::unique_ptr<UpdateRegion> regions[2];
  std::unique_ptr<UpdateRegion>& region = regions[background ? 1 : 0];
  if (!region) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(HUGE_VAL), hi = -lo;
    for (const Pose& view : trialViews()) {
      lo = lo.cwiseMin(view.position);
      hi = hi.cwiseMax(view.position);
    }
    const double reach = kMapRangeM + kResolutionM;
    region = std::make_unique<UpdateRegion>(
        kResolutionM, Box::fromMinMax(lo.array() - reach, hi.array() + reach));
    region->addMesh(benchPlant().mesh, kResolutionM);
    if (background) {
      PlantSceneConfig config;
      for (const TriangleMesh& mesh : plantSceneBackground(benchPlant(), config))
        region->addMesh(mesh, kResolutionM);
    }
  }
  return *region;
}

/// Args: mask (0 or 1), threads, background. The ten views of a trial at 640 x 480, each
/// casting every pixel (mask 0) or only those whose rays may reach the trial's region
/// within the map's range (mask 1: the region's RayMask made for each view, its time
/// included, as Trial does). Time: the ten frames; counters: mask = fraction of the
/// pixels cast, hits = fraction with a return.
void BM_EmbreeCaptureInRegion(benchmark::State& state)
{
  const bool masked = state.range(0) != 0;
  const unsigned int threads = unsigned(state.range(1));
  const bool background = state.range(2) != 0;
  const CameraIntrinsics K = camera(640);
  SimulatedDepthSensor sensor(K);
  sensor.setScene(benchScene(background));
  sensor.setNumberOfThreads(threads);
  const std::vector<Pose> views = trialViews();
  const UpdateRegion& region = trialRegion(background);
  CloudXYZL cloud;
  sensor.capture(kV0, cloud); // warm-up: buffers allocated
  std::size_t cast = 0, hits = 0;
  for (auto _ : state) {
    cast = hits = 0;
    for (const Pose& view : views) {
      if (masked) {
        auto mask = std::make_shared<const RayMask>(
            regionRayMask(region, K, opticalFrame(view), kMapRangeM));
        cast += mask->pixelCount();
        sensor.setRayMask(std::move(mask));
      } else {
        cast += cloud.size();
      }
      sensor.capture(view, cloud);
      hits += returns(cloud);
      benchmark::DoNotOptimize(cloud.points.data());
    }
  }
  const double pixels = double(views.size()) * double(K.width) * double(K.height);
  state.counters["threads"] = threads;
  state.counters["mask"] = double(cast) / pixels;
  state.counters["hits"] = double(hits) / pixels;
}

/// Args: threads. Copy of the mesh into Embree and BVH build (medium quality, robust).
void BM_EmbreeBuild(benchmark::State& state)
{
  const unsigned int threads = unsigned(state.range(0));
  const Plant& plant = benchPlant();
  for (auto _ : state) {
    SensorScene scene;
    scene.setNumberOfThreads(threads);
    scene.addMesh(plant.mesh);
    scene.commit();
    benchmark::DoNotOptimize(&scene);
  }
  state.counters["threads"] = threads;
  state.counters["triangles"] = double(plant.mesh.size());
}

#ifdef PLANTNBV_BENCH_VTK

/// The scene's triangles as VTK poly data (the plant, plus floor and support).
vtkSmartPointer<vtkPolyData> vtkScene(bool background)
{
  TriangleMesh mesh = benchPlant().mesh;
  if (background) {
    // The floor and support makePlantScene adds with the default PlantSceneConfig (a 10 m
    // square at z = 0 and a 0.3 m box up to the base, both centred under the base).
    const float h = 5.0f;
    TriangleMesh floor;
    floor.vertices = {{1 - h, -h, 0}, {1 + h, -h, 0}, {1 + h, h, 0}, {1 - h, h, 0}};
    floor.triangles = {{0, 1, 2}, {0, 2, 3}};
    mesh.append(floor);
    TriangleMesh box;
    const Eigen::Vector3f lo(0.85f, -0.15f, 0.0f), hi(1.15f, 0.15f, 0.8f);
    for (int i = 0; i < 8; ++i)
      box.vertices.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(),
                                (i & 4) ? hi.z() : lo.z());
    box.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                     {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    mesh.append(box);
  }
  vtkNew<vtkPoints> points;
  points->SetNumberOfPoints(vtkIdType(mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    points->SetPoint(vtkIdType(i), mesh.vertices[i].x(), mesh.vertices[i].y(),
                     mesh.vertices[i].z());
  vtkNew<vtkCellArray> cells;
  for (const auto& t : mesh.triangles) {
    const vtkIdType ids[3] = {t[0], t[1], t[2]};
    cells->InsertNextCell(3, ids);
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(cells);
  return poly;
}

/// Args: width, background. Manual time: the sampled rays' time times 64.
void BM_VtkCellLocator(benchmark::State& state)
{
  const int width = int(state.range(0));
  const bool background = state.range(1) != 0;
  const CameraIntrinsics K = camera(width);
  vtkSmartPointer<vtkPolyData> poly = vtkScene(background);
  vtkNew<vtkCellLocator> locator;
  locator->SetDataSet(poly);
  const auto t0 = std::chrono::steady_clock::now();
  locator->BuildLocator();
  const double build_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // Our frame, for the comparison.
  SimulatedDepthSensor sensor(K);
  sensor.setScene(benchScene(background));
  CloudXYZL ours;
  sensor.capture(kV0, ours);

  const Pose T_W_O = opticalFrame(kV0);
  const Eigen::Vector3d o = T_W_O.position;
  constexpr int kStride = 8;
  std::vector<Eigen::Vector3d> ends;
  std::vector<std::size_t> pixels;
  for (std::uint32_t v = 0; v < K.height; v += kStride)
    for (std::uint32_t u = 0; u < K.width; u += kStride) {
      const Eigen::Vector3d d =
          T_W_O.orientation *
          Eigen::Vector3d((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0).normalized();
      ends.push_back(o + K.max_range_m * d);
      pixels.push_back(std::size_t(v) * K.width + u);
    }
  std::vector<double> range(ends.size());
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < ends.size(); ++i) {
      double t, x[3], pcoords[3];
      int sub_id;
      range[i] =
          locator->IntersectWithLine(o.data(), ends[i].data(), 0.0, t, x, pcoords, sub_id)
              ? (Eigen::Vector3d(x[0], x[1], x[2]) - o).norm()
              : HUGE_VAL;
    }
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    state.SetIterationTime(elapsed * kStride * kStride);
  }
  std::size_t mismatch = 0;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const pcl::PointXYZL& p = ours.points[pixels[i]];
    const bool ours_hit = std::isfinite(p.x);
    const bool vtk_hit = std::isfinite(range[i]) && range[i] >= K.min_range_m;
    if (ours_hit != vtk_hit)
      ++mismatch;
    else if (ours_hit &&
             std::abs((p.getVector3fMap().cast<double>() - o).norm() - range[i]) > 1e-4)
      ++mismatch;
  }
  state.counters["threads"] = 1;
  state.counters["sampled_rays"] = double(ends.size());
  state.counters["vtk_mismatch"] = double(mismatch);
  state.counters["locator_build_ms"] = build_s * 1e3;
  state.counters["triangles"] = double(poly->GetNumberOfCells());
}

// The plant alone only: with the 10 m floor and the support (background = 1) one
// extrapolated frame took 209 s (640 x 480), so those rows are left out of the default
// run (make the second list {0, 1} to measure them).
BENCHMARK(BM_VtkCellLocator)
    ->ArgsProduct({{640, 1024}, {0}})
    ->ArgNames({"width", "background"})
    ->UseManualTime()
    ->Iterations(3)
    ->Unit(benchmark::kMillisecond);

#endif // PLANTNBV_BENCH_VTK

BENCHMARK(BM_EmbreeCapture)
    ->ArgsProduct({{640, 1024}, {1, 2}, {0, 1}})
    ->ArgNames({"width", "threads", "background"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// The mask varies first: the two rows of a pair run one after the other.
BENCHMARK(BM_EmbreeCaptureInRegion)
    ->ArgsProduct({{0, 1}, {1, 2}, {0, 1}})
    ->ArgNames({"mask", "threads", "background"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

BENCHMARK(BM_EmbreeBuild)
    ->ArgsProduct({{1, 2}})
    ->ArgNames({"threads"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

} // namespace

BENCHMARK_MAIN();
