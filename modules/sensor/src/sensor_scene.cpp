#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>
#include <sstream>
#include <tbb/task_arena.h>

#include <nanoflann.hpp>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>

#include "sensor_scene_impl.h"

namespace plantnbv {

namespace detail {

namespace {
thread_local std::string embree_error_message;

void onEmbreeError(void*, RTCError, const char* message)
{
  embree_error_message = message ? message : "";
}
} // namespace

std::shared_ptr<RTCDeviceTy> embreeDevice()
{
  static std::mutex mutex;
  static std::weak_ptr<RTCDeviceTy> shared;
  std::lock_guard<std::mutex> lock(mutex);
  std::shared_ptr<RTCDeviceTy> device = shared.lock();
  if (device)
    return device;
  RTCDevice raw = rtcNewDevice(nullptr);
  if (!raw)
    throw Error("Embree: rtcNewDevice failed (error " +
                std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(raw, onEmbreeError, nullptr);
  device.reset(raw, rtcReleaseDevice);
  shared = device;
  return device;
}

void checkEmbree(RTCDevice device, const char* what)
{
  const RTCError code = rtcGetDeviceError(device);
  if (code == RTC_ERROR_NONE)
    return;
  std::string message = std::string("Embree: ") + what + " failed (error " +
                        std::to_string(int(code)) + ")";
  if (!embree_error_message.empty())
    message += ": " + embree_error_message;
  embree_error_message.clear();
  throw Error(message);
}

} // namespace detail

namespace {

void requirePositive(double value, const char* name)
{
  if (!(std::isfinite(value) && value > 0.0)) {
    std::ostringstream s;
    s << name << " = " << value << " must be finite and > 0";
    throw InvalidArgumentError(s.str());
  }
}

} // namespace

void SurfelOptions::validate() const
{
  const SurfelOptions& o = *this;
  if (!(std::isfinite(o.radius_m) && o.radius_m >= 0.0)) {
    std::ostringstream s;
    s << "SurfelOptions::radius_m = " << o.radius_m
      << " must be finite and >= 0 (0: from the point spacing)";
    throw InvalidArgumentError(s.str());
  }
  if (o.spacing_neighbours < 1 || o.spacing_neighbours > 32)
    throw InvalidArgumentError(
        "SurfelOptions::spacing_neighbours = " + std::to_string(o.spacing_neighbours) +
        " must be in [1, 32]");
  requirePositive(o.radius_factor, "SurfelOptions::radius_factor");
}

namespace {

/// nanoflann's view of a point vector.
struct PointsAdaptor {
  const std::vector<Eigen::Vector3f>& points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  float kdtree_get_pt(std::size_t i, std::size_t d) const { return points[i][int(d)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const
  {
    return false;
  }
};

void checkPoints(const std::vector<Eigen::Vector3f>& points, const char* what)
{
  if (points.empty())
    throw InvalidArgumentError(std::string(what) + ": no points");
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!points[i].allFinite()) {
      std::ostringstream s;
      s << what << ": point " << i << " (" << points[i].transpose() << ") is not finite";
      throw InvalidArgumentError(s.str());
    }
}

} // namespace

std::vector<float> surfelRadii(const std::vector<Eigen::Vector3f>& points,
                               const SurfelOptions& options)
{
  options.validate();
  checkPoints(points, "surfelRadii");
  if (options.radius_m > 0.0)
    return std::vector<float>(points.size(), float(options.radius_m));

  const std::size_t k = std::size_t(options.spacing_neighbours);
  if (points.size() < k + 1)
    throw InvalidArgumentError("surfelRadii: " + std::to_string(points.size()) +
                               " points; a radius from the spacing needs at least " +
                               std::to_string(k + 1));
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<
      nanoflann::L2_Simple_Adaptor<float, PointsAdaptor>, PointsAdaptor, 3,
      std::uint32_t>;
  PointsAdaptor adaptor{points};
  Tree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  std::vector<float> spacing(points.size());
  const std::int64_t n = std::int64_t(points.size());
#pragma omp parallel
  {
    std::vector<std::uint32_t> indices(k + 1);
    std::vector<float> sqr_dists(k + 1);
#pragma omp for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) {
      // The point itself is its own nearest neighbour (distance 0): ask for k + 1.
      const std::size_t found = tree.knnSearch(points[std::size_t(i)].data(), k + 1,
                                               indices.data(), sqr_dists.data());
      spacing[std::size_t(i)] = std::sqrt(sqr_dists[found - 1]);
    }
  }
  std::vector<float> sorted = spacing;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const float median = sorted[sorted.size() / 2];
  if (!(median > 0.0f))
    throw InvalidArgumentError(
        "surfelRadii: most points coincide with their neighbours (median spacing 0); "
        "give SurfelOptions::radius_m");
  const float factor = float(options.radius_factor);
  for (float& r : spacing)
    r = factor * std::clamp(r, 0.25f * median, 4.0f * median);
  return spacing;
}

SensorScene::Impl::Impl() : device(detail::embreeDevice())
{
  scene = rtcNewScene(device.get());
  detail::checkEmbree(device.get(), "rtcNewScene");
  // Medium quality (Embree's default) builds about twice as fast as high quality and
  // traces about as fast for our frames. Robust mode makes the triangle test watertight:
  // without it a ray through a shared edge can slip between two triangles of a closed
  // mesh (seen on a UV sphere along a meridian) and would carve free space through a
  // leaf. Back-face culling is off in Debian's Embree build.
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_MEDIUM);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
}

SensorScene::Impl::~Impl()
{
  if (scene)
    rtcReleaseScene(scene);
}

SensorScene::SensorScene() : impl_(std::make_unique<Impl>()) {}
SensorScene::~SensorScene() = default;
SensorScene::SensorScene(SensorScene&&) noexcept = default;
SensorScene& SensorScene::operator=(SensorScene&&) noexcept = default;

std::size_t SensorScene::addMesh(const TriangleMesh& mesh_W, PartLabel default_label)
{
  mesh_W.validate();
  if (mesh_W.empty())
    throw InvalidArgumentError("SensorScene::addMesh: the mesh has no triangles");
  Impl& s = *impl_;
  RTCDevice device = s.device.get();
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  detail::checkEmbree(device, "rtcNewGeometry(TRIANGLE)");
  // Embree reads vertex buffers with 16-byte loads: its own buffers are padded.
  auto* vertices = static_cast<float*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                              3 * sizeof(float), mesh_W.vertices.size()));
  auto* indices = static_cast<std::uint32_t*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                              3 * sizeof(std::uint32_t), mesh_W.triangles.size()));
  if (!vertices || !indices) {
    rtcReleaseGeometry(geometry);
    detail::checkEmbree(device, "rtcSetNewGeometryBuffer");
    throw Error("Embree: rtcSetNewGeometryBuffer returned no buffer");
  }
  for (std::size_t i = 0; i < mesh_W.vertices.size(); ++i) {
    const Eigen::Vector3f& v = mesh_W.vertices[i];
    std::memcpy(vertices + 3 * i, v.data(), 3 * sizeof(float));
    s.min = s.min.cwiseMin(v);
    s.max = s.max.cwiseMax(v);
  }
  std::memcpy(indices, mesh_W.triangles.data(), mesh_W.triangles.size() * 3 * 4);
  rtcCommitGeometry(geometry);
  const unsigned int id = rtcAttachGeometry(s.scene, geometry);
  rtcReleaseGeometry(geometry);
  detail::checkEmbree(device, "rtcAttachGeometry");

  SceneGeometry g;
  g.kind = SceneGeometry::Kind::triangles;
  g.primitives = mesh_W.triangles.size();
  g.labels.resize(g.primitives);
  for (std::size_t t = 0; t < g.primitives; ++t)
    g.labels[t] = std::uint32_t(mesh_W.hasLabels() ? mesh_W.labels[t] : default_label);
  if (id != s.geometries.size())
    throw Error("Embree: unexpected geometry id " + std::to_string(id));
  s.geometries.push_back(std::move(g));
  s.committed = false;
  return id;
}

namespace {

std::size_t addSurfelGeometry(SensorScene::Impl& s,
                              const std::vector<Eigen::Vector3f>& points,
                              const std::vector<PartLabel>& labels,
                              const std::vector<Eigen::Vector3f>* normals,
                              const SurfelOptions& options)
{
  checkPoints(points, "SensorScene::addSurfels");
  if (!labels.empty() && labels.size() != points.size())
    throw InvalidArgumentError(
        "SensorScene::addSurfels: " + std::to_string(labels.size()) + " labels for " +
        std::to_string(points.size()) + " points (expected one per point, or none)");
  if (normals) {
    if (normals->size() != points.size())
      throw InvalidArgumentError(
          "SensorScene::addSurfels: " + std::to_string(normals->size()) +
          " normals for " + std::to_string(points.size()) + " points");
    for (std::size_t i = 0; i < normals->size(); ++i)
      if (!(*normals)[i].allFinite() || (*normals)[i].squaredNorm() < 1e-20f)
        throw InvalidArgumentError("SensorScene::addSurfels: normal " +
                                   std::to_string(i) + " is zero or not finite");
  }
  const std::vector<float> radii = surfelRadii(points, options);

  RTCDevice device = s.device.get();
  RTCGeometry geometry =
      rtcNewGeometry(device, normals ? RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT
                                     : RTC_GEOMETRY_TYPE_DISC_POINT);
  detail::checkEmbree(device, "rtcNewGeometry(DISC_POINT)");
  auto* vertices = static_cast<float*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                              4 * sizeof(float), points.size()));
  float* normal_buffer = nullptr;
  if (normals)
    normal_buffer = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3,
                                3 * sizeof(float), points.size()));
  if (!vertices || (normals && !normal_buffer)) {
    rtcReleaseGeometry(geometry);
    detail::checkEmbree(device, "rtcSetNewGeometryBuffer");
    throw Error("Embree: rtcSetNewGeometryBuffer returned no buffer");
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f& p = points[i];
    vertices[4 * i + 0] = p.x();
    vertices[4 * i + 1] = p.y();
    vertices[4 * i + 2] = p.z();
    vertices[4 * i + 3] = radii[i];
    s.min = s.min.cwiseMin(p - Eigen::Vector3f::Constant(radii[i]));
    s.max = s.max.cwiseMax(p + Eigen::Vector3f::Constant(radii[i]));
    if (normals) {
      const Eigen::Vector3f n = (*normals)[i].normalized();
      std::memcpy(normal_buffer + 3 * i, n.data(), 3 * sizeof(float));
    }
  }
  rtcCommitGeometry(geometry);
  const unsigned int id = rtcAttachGeometry(s.scene, geometry);
  rtcReleaseGeometry(geometry);
  detail::checkEmbree(device, "rtcAttachGeometry");

  SceneGeometry g;
  g.kind = normals ? SceneGeometry::Kind::oriented_surfels : SceneGeometry::Kind::surfels;
  g.primitives = points.size();
  g.labels.resize(g.primitives, std::uint32_t(PartLabel::unknown));
  for (std::size_t i = 0; i < labels.size(); ++i)
    g.labels[i] = std::uint32_t(labels[i]);
  if (id != s.geometries.size())
    throw Error("Embree: unexpected geometry id " + std::to_string(id));
  s.geometries.push_back(std::move(g));
  s.committed = false;
  return id;
}

} // namespace

std::size_t SensorScene::addSurfels(const std::vector<Eigen::Vector3f>& points_W,
                                    const std::vector<PartLabel>& labels,
                                    const SurfelOptions& options)
{
  return addSurfelGeometry(*impl_, points_W, labels, nullptr, options);
}

std::size_t SensorScene::addSurfels(const std::vector<Eigen::Vector3f>& points_W,
                                    const std::vector<PartLabel>& labels,
                                    const std::vector<Eigen::Vector3f>& normals_W,
                                    const SurfelOptions& options)
{
  return addSurfelGeometry(*impl_, points_W, labels, &normals_W, options);
}

std::size_t SensorScene::addSurfels(const CloudXYZL& cloud_W,
                                    const SurfelOptions& options)
{
  std::vector<Eigen::Vector3f> points;
  std::vector<PartLabel> labels;
  points.reserve(cloud_W.size());
  labels.reserve(cloud_W.size());
  for (const pcl::PointXYZL& p : cloud_W.points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      continue;
    points.emplace_back(p.x, p.y, p.z);
    labels.push_back(PartLabel(p.label));
  }
  if (points.empty())
    throw InvalidArgumentError("SensorScene::addSurfels: the cloud of " +
                               std::to_string(cloud_W.size()) +
                               " points has no finite point");
  return addSurfels(points, labels, options);
}

TriangleMesh floorMesh(double height_m, double half_size_m, const Eigen::Vector2d& center_xy)
{
  if (!std::isfinite(height_m) || !center_xy.allFinite())
    throw InvalidArgumentError("floorMesh: height and centre must be finite");
  requirePositive(half_size_m, "floorMesh: half_size_m");
  TriangleMesh mesh;
  const float h = float(half_size_m), z = float(height_m);
  const float x = float(center_xy.x()), y = float(center_xy.y());
  mesh.vertices = {
      {x - h, y - h, z}, {x + h, y - h, z}, {x + h, y + h, z}, {x - h, y + h, z}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  mesh.node_names = {"floor"};
  mesh.node_ids = {0, 0};
  mesh.labels.assign(mesh.triangles.size(), PartLabel::background);
  return mesh;
}

TriangleMesh supportMesh(const Eigen::Vector3d& top_center_W, double half_width_m,
                         double bottom_height_m)
{
  if (!top_center_W.allFinite() || !std::isfinite(bottom_height_m))
    throw InvalidArgumentError("supportMesh: values must be finite");
  requirePositive(half_width_m, "supportMesh: half_width_m");
  if (!(top_center_W.z() > bottom_height_m)) {
    std::ostringstream s;
    s << "supportMesh: top z = " << top_center_W.z() << " must be above the bottom z = "
      << bottom_height_m;
    throw InvalidArgumentError(s.str());
  }
  TriangleMesh mesh;
  const Eigen::Vector3f lo(float(top_center_W.x() - half_width_m),
                           float(top_center_W.y() - half_width_m),
                           float(bottom_height_m));
  const Eigen::Vector3f hi(float(top_center_W.x() + half_width_m),
                           float(top_center_W.y() + half_width_m),
                           float(top_center_W.z()));
  for (int i = 0; i < 8; ++i)
    mesh.vertices.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(),
                               (i & 4) ? hi.z() : lo.z());
  // Two triangles per face (outward winding; both sides are hit anyway).
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  mesh.node_names = {"support"};
  mesh.node_ids.assign(mesh.triangles.size(), 0);
  mesh.labels.assign(mesh.triangles.size(), PartLabel::background);
  return mesh;
}

std::size_t SensorScene::addFloor(double height_m, double half_size_m,
                                  const Eigen::Vector2d& center_xy)
{
  return addMesh(floorMesh(height_m, half_size_m, center_xy), PartLabel::background);
}

std::size_t SensorScene::addSupport(const Eigen::Vector3d& top_center_W,
                                    double half_width_m, double bottom_height_m)
{
  return addMesh(supportMesh(top_center_W, half_width_m, bottom_height_m),
                 PartLabel::background);
}

void SensorScene::commit()
{
  Impl& s = *impl_;
  auto build = [&] { rtcCommitScene(s.scene); };
  // Embree builds with TBB; an arena bounds its threads.
  if (threads_ > 0) {
    tbb::task_arena arena{static_cast<int>(threads_)};
    arena.execute(build);
  } else {
    build();
  }
  detail::checkEmbree(s.device.get(), "rtcCommitScene");
  s.committed = true;
}

bool SensorScene::isCommitted() const
{
  return impl_->committed;
}

std::size_t SensorScene::geometryCount() const
{
  return impl_->geometries.size();
}

std::size_t SensorScene::triangleCount() const
{
  std::size_t n = 0;
  for (const SceneGeometry& g : impl_->geometries)
    if (g.kind == SceneGeometry::Kind::triangles)
      n += g.primitives;
  return n;
}

std::size_t SensorScene::surfelCount() const
{
  std::size_t n = 0;
  for (const SceneGeometry& g : impl_->geometries)
    if (g.kind != SceneGeometry::Kind::triangles)
      n += g.primitives;
  return n;
}

void SensorScene::bounds(Eigen::Vector3f& min, Eigen::Vector3f& max) const
{
  if (impl_->geometries.empty())
    throw InvalidArgumentError("SensorScene::bounds: the scene is empty");
  min = impl_->min;
  max = impl_->max;
}

} // namespace plantnbv
