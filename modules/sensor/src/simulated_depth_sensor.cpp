#include <algorithm>
#include <cmath>
#include <cstdint>
#include <emmintrin.h>
#include <limits>
#include <omp.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/sensor/simulated_depth_sensor.h>

#include "sensor_scene_impl.h"

namespace plantnbv {

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

/// What a pixel's ray gave.
enum PixelStatus : std::uint8_t {
  kNoSurface = 0, ///< the ray met nothing
  kReturn = 1,    ///< a surface within [min_range_m, max_range_m]
  kTooNear = 2,   ///< the first surface is nearer than min_range_m
  kFar = 3,       ///< the first surface is beyond max_range_m
};

/// Counter-based draws: draw k of a pixel is a hash of (pixel seed, k), so the noise of
/// a pixel does not depend on which thread computes it, or when.
/// Draw indices: 0-1 lateral jitter, 2-3 axial noise, 4 edge dropout, 5 grazing dropout.
inline double uniformDraw(std::uint64_t pixel_seed, std::uint64_t k)
{
  return double(mixSeed(pixel_seed + k * 0x9e3779b97f4a7c15ULL) >> 11) * 0x1.0p-53;
}

/// Two independent standard normals (Box-Muller) from draws k and k + 1.
inline void normalPair(std::uint64_t pixel_seed, std::uint64_t k, double& n0, double& n1)
{
  const double u1 = 1.0 - uniformDraw(pixel_seed, k); // in (0, 1]
  const double u2 = uniformDraw(pixel_seed, k + 1);
  const double r = std::sqrt(-2.0 * std::log(u1));
  n0 = r * std::cos(2.0 * M_PI * u2);
  n1 = r * std::sin(2.0 * M_PI * u2);
}

/// Restores the caller's MXCSR when a parallel region ends: Embree wants flush-to-zero
/// and denormals-are-zero on the tracing threads, and OpenMP's pool threads run other
/// code afterwards.
class DenormalGuard {
public:
  DenormalGuard() : csr_(_mm_getcsr())
  {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
  }
  ~DenormalGuard() { _mm_setcsr(csr_); }
  DenormalGuard(const DenormalGuard&) = delete;
  DenormalGuard& operator=(const DenormalGuard&) = delete;

private:
  unsigned int csr_;
};

/// Writes a point with non-temporal stores: x, y, z, 1, then the label and zeroed
/// padding. A frame's cloud (32 bytes a pixel, 10 MB at 640 x 480) is larger than the
/// caches; plain stores read every line before writing it and kept 2 threads from
/// scaling (measured: 6.6 ms a frame instead of 5.0 ms without the writes). Callers
/// issue _mm_sfence() before other threads read the points.
inline void streamPoint(pcl::PointXYZL& p, float x, float y, float z, std::uint32_t label)
{
  static_assert(sizeof(pcl::PointXYZL) == 32,
                "pcl::PointXYZL: x, y, z, 1, label, padding");
  float* base = p.data; // 16-byte aligned: PCL points are EIGEN_ALIGN16
  _mm_stream_ps(base, _mm_setr_ps(x, y, z, 1.0f));
  _mm_stream_si128(reinterpret_cast<__m128i*>(base + 4),
                   _mm_setr_epi32(static_cast<int>(label), 0, 0, 0));
}

} // namespace

struct SimulatedDepthSensor::Buffers {
  /// Unit ray directions of the pixel centres in the optical frame, for `rays_for`
  /// (rebuilt when the intrinsics change), in tile order: for each 4 x 4 tile 16 x, then
  /// 16 y, then 16 z (lanes outside the image: (0, 0, 1)).
  std::vector<float> rays_O;
  CameraIntrinsics rays_for;
  std::vector<std::uint8_t> status;
  // With noise only: true range (inf without a surface), |cos| of the incidence angle,
  // and depth per unit range of the pixel's (jittered) ray.
  std::vector<float> range;
  std::vector<float> cos_incidence;
  std::vector<float> depth_per_range;
};

namespace {

bool sameCamera(const CameraIntrinsics& a, const CameraIntrinsics& b)
{
  return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy &&
         a.cx == b.cx && a.cy == b.cy;
}

/// The unit direction through image point (x, y) (pixels) in the optical frame.
inline Eigen::Vector3d opticalRay(const CameraIntrinsics& K, double x, double y)
{
  return Eigen::Vector3d((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1.0).normalized();
}

/// A ray mask (or none) of the camera's image size. \throws InvalidArgumentError.
void requireMaskFits(const RayMask* mask, const CameraIntrinsics& K, const char* who)
{
  if (mask && (mask->width() != K.width || mask->height() != K.height))
    throw InvalidArgumentError(std::string("SimulatedDepthSensor::") + who +
                               ": a ray mask of " + std::to_string(mask->width()) + " x " +
                               std::to_string(mask->height()) + " pixels for a camera of " +
                               std::to_string(K.width) + " x " + std::to_string(K.height));
}

} // namespace

SimulatedDepthSensor::SimulatedDepthSensor()
    : SimulatedDepthSensor(CameraIntrinsics::l515(L515Mode::xga_1024x768))
{
}

SimulatedDepthSensor::SimulatedDepthSensor(const CameraIntrinsics& intrinsics)
    : buffers_(std::make_unique<Buffers>())
{
  setIntrinsics(intrinsics);
}

SimulatedDepthSensor::~SimulatedDepthSensor() = default;
SimulatedDepthSensor::SimulatedDepthSensor(SimulatedDepthSensor&&) noexcept = default;
SimulatedDepthSensor&
SimulatedDepthSensor::operator=(SimulatedDepthSensor&&) noexcept = default;

void SimulatedDepthSensor::setScene(SensorScene::ConstPtr scene)
{
  if (!scene)
    throw InvalidArgumentError("SimulatedDepthSensor::setScene: the scene is null");
  if (!scene->isCommitted())
    throw InvalidArgumentError(
        "SimulatedDepthSensor::setScene: the scene is not committed (call "
        "SensorScene::commit() after adding geometry)");
  scene_ = std::move(scene);
}

void SimulatedDepthSensor::setIntrinsics(const CameraIntrinsics& intrinsics)
{
  intrinsics.validate();
  intrinsics_ = intrinsics;
}

void SimulatedDepthSensor::setRayMask(std::shared_ptr<const RayMask> mask)
{
  requireMaskFits(mask.get(), intrinsics_, "setRayMask");
  ray_mask_ = std::move(mask);
}

void SimulatedDepthSensor::setNoise(const NoiseConfig& noise)
{
  noise.validate();
  noise_ = noise;
  frame_index_ = 0;
}

void SimulatedDepthSensor::capture(const Pose& T_W_C, CloudXYZL& cloud, DepthImage* depth,
                                   CloudXYZ* far_points_W)
{
  if (!scene_)
    throw Error("SimulatedDepthSensor::capture: no scene set (setScene)");
  if (!scene_->isCommitted())
    throw Error("SimulatedDepthSensor::capture: the scene was changed and not committed "
                "again (SensorScene::commit())");
  const SensorScene::Impl& scene = *scene_->impl_;
  const CameraIntrinsics& K = intrinsics_;
  const std::uint32_t W = K.width, H = K.height;
  const std::size_t N = std::size_t(W) * H;
  const bool noisy = noise_.enabled;
  const bool jitter = noisy && noise_.lateral_sigma_px > 0.0;
  const std::uint64_t frame_seed = deriveSeed(noise_.seed, frame_index_);

  const RayMask* mask = ray_mask_.get();
  requireMaskFits(mask, K, "capture"); // the intrinsics may have changed since

  const Pose T_W_O = opticalFrame(T_W_C);
  const Eigen::Matrix3d R_W_O = T_W_O.orientation.toRotationMatrix();
  const Eigen::Matrix3f R = R_W_O.cast<float>();
  const Eigen::Vector3d o = T_W_O.position;
  const Eigen::Vector3f o_f = o.cast<float>();
  const float min_range = float(K.min_range_m), max_range = float(K.max_range_m);

  cloud.header.frame_id = "world";
  cloud.header.seq = std::uint32_t(frame_index_);
  cloud.header.stamp = 0;
  cloud.width = W;
  cloud.height = H;
  cloud.points.resize(N);
  cloud.sensor_origin_ = Eigen::Vector4f(o_f.x(), o_f.y(), o_f.z(), 0.0f);
  cloud.sensor_orientation_ = T_W_O.orientation.cast<float>();
  if (depth) {
    depth->width = W;
    depth->height = H;
    depth->depth_m.resize(N);
  }
  Buffers& b = *buffers_;
  b.status.resize(N);
  if (noisy) {
    b.range.resize(N);
    b.cos_incidence.resize(N);
    b.depth_per_range.resize(N);
  }
  const int threads = threads_ > 0 ? int(threads_) : omp_get_max_threads();
  const std::uint32_t tiles_x = (W + 3) / 4, tiles_y = (H + 3) / 4;
  const std::int64_t tiles = std::int64_t(tiles_x) * tiles_y;
  if (b.rays_O.size() != std::size_t(48 * tiles) || !sameCamera(b.rays_for, K)) {
    b.rays_O.resize(std::size_t(48 * tiles));
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::int64_t tile = 0; tile < tiles; ++tile) {
      const std::uint32_t tx = std::uint32_t(tile % tiles_x) * 4;
      const std::uint32_t ty = std::uint32_t(tile / tiles_x) * 4;
      float* r = &b.rays_O[std::size_t(48 * tile)];
      for (int k = 0; k < 16; ++k) {
        const std::uint32_t u = tx + (k & 3), v = ty + (k >> 2);
        const Eigen::Vector3f d = (u < W && v < H)
                                      ? Eigen::Vector3f(opticalRay(K, u, v).cast<float>())
                                      : Eigen::Vector3f(Eigen::Vector3f::UnitZ());
        r[k] = d.x();
        r[16 + k] = d.y();
        r[32 + k] = d.z();
      }
    }
    b.rays_for = K;
  }

  // The unit direction of pixel i = (u, v) in the optical frame: the pixel centre's, or
  // with lateral noise a jittered one (draws 0 and 1 of the pixel).
  auto jitteredRay = [&](std::uint32_t u, std::uint32_t v,
                         std::size_t i) -> Eigen::Vector3f {
    double du, dv;
    normalPair(deriveSeed(frame_seed, i), 0, du, dv);
    return opticalRay(K, u + noise_.lateral_sigma_px * du,
                      v + noise_.lateral_sigma_px * dv)
        .cast<float>();
  };

  RTCScene rtc_scene = scene.scene;
  const std::vector<SceneGeometry>& geometries = scene.geometries;
  const float* rays_O = b.rays_O.data();

  // Pass 1: trace 4 x 4 packets; write points (NaN outside the range limits), depth,
  // and with noise the per-pixel data pass 2 needs.
#pragma omp parallel num_threads(threads)
  {
    DenormalGuard denormals;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) RTCRayHit16 packet;
    alignas(64) int valid[16];
    alignas(64) float depth_per_range[16];
    // Embree changes only tfar and the hit: the rest is set once.
    for (int k = 0; k < 16; ++k) {
      packet.ray.org_x[k] = o_f.x();
      packet.ray.org_y[k] = o_f.y();
      packet.ray.org_z[k] = o_f.z();
      packet.ray.tnear[k] = 0.0f;
      packet.ray.time[k] = 0.0f;
      packet.ray.mask[k] = 0xFFFFFFFFu;
      packet.ray.id[k] = unsigned(k);
      packet.ray.flags[k] = 0;
    }

#pragma omp for schedule(dynamic, 16) nowait
    for (std::int64_t tile = 0; tile < tiles; ++tile) {
      const std::uint32_t tx = std::uint32_t(tile % tiles_x) * 4;
      const std::uint32_t ty = std::uint32_t(tile / tiles_x) * 4;
      const float* r = rays_O + 48 * tile;
      for (int k = 0; k < 16; ++k) {
        const float x = r[k], y = r[16 + k], z = r[32 + k];
        packet.ray.dir_x[k] = R(0, 0) * x + R(0, 1) * y + R(0, 2) * z;
        packet.ray.dir_y[k] = R(1, 0) * x + R(1, 1) * y + R(1, 2) * z;
        packet.ray.dir_z[k] = R(2, 0) * x + R(2, 1) * y + R(2, 2) * z;
        depth_per_range[k] = z;
        packet.ray.tfar[k] = kInf;
        packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
      }
      // in_image: the pixel exists; valid: it is cast (in the mask). A pixel not cast
      // keeps no hit: no return.
      const bool full = tx + 4 <= W && ty + 4 <= H;
      bool in_image[16];
      bool any = false;
      for (int k = 0; k < 16; ++k) {
        const std::uint32_t u = tx + (k & 3), v = ty + (k >> 2);
        in_image[k] = full || (u < W && v < H);
        valid[k] = in_image[k] && (!mask || mask->containsPixel(u, v)) ? -1 : 0;
        any = any || valid[k];
      }
      if (jitter)
        for (int k = 0; k < 16; ++k) {
          if (!valid[k])
            continue;
          const std::uint32_t u = tx + (k & 3), v = ty + (k >> 2);
          const Eigen::Vector3f d_O = jitteredRay(u, v, std::size_t(v) * W + u);
          const Eigen::Vector3f d_W = R * d_O;
          packet.ray.dir_x[k] = d_W.x();
          packet.ray.dir_y[k] = d_W.y();
          packet.ray.dir_z[k] = d_W.z();
          depth_per_range[k] = d_O.z();
        }
      if (any)
        rtcIntersect16(valid, rtc_scene, &context, &packet);

      for (int k = 0; k < 16; ++k) {
        if (!in_image[k])
          continue;
        const std::uint32_t u = tx + (k & 3), v = ty + (k >> 2);
        const std::size_t i = std::size_t(v) * W + u;
        const unsigned int geom = packet.hit.geomID[k];
        float t = kInf;
        PixelStatus status = kNoSurface;
        if (geom != RTC_INVALID_GEOMETRY_ID) {
          t = packet.ray.tfar[k];
          status = t < min_range ? kTooNear : (t > max_range ? kFar : kReturn);
        }
        b.status[i] = status;
        if (status == kReturn)
          streamPoint(cloud.points[i], o_f.x() + t * packet.ray.dir_x[k],
                      o_f.y() + t * packet.ray.dir_y[k],
                      o_f.z() + t * packet.ray.dir_z[k],
                      geometries[geom].labels[packet.hit.primID[k]]);
        else
          streamPoint(cloud.points[i], kNaN, kNaN, kNaN, 0);
        if (depth)
          depth->depth_m[i] = status == kReturn ? t * depth_per_range[k] : kNaN;
        if (noisy) {
          b.range[i] = t;
          b.depth_per_range[i] = depth_per_range[k];
          float c = 1.0f;
          if (status != kNoSurface) {
            const float nx = packet.hit.Ng_x[k], ny = packet.hit.Ng_y[k],
                        nz = packet.hit.Ng_z[k];
            const float n = std::sqrt(nx * nx + ny * ny + nz * nz);
            if (n > 0.0f)
              c = std::min(1.0f,
                           std::abs(nx * packet.ray.dir_x[k] + ny * packet.ray.dir_y[k] +
                                    nz * packet.ray.dir_z[k]) /
                               n);
          }
          b.cos_incidence[i] = c;
        }
      }
    }
    _mm_sfence(); // the streamed points are visible after the region's barrier
  }

  // Pass 2 (noise): dropout on depth edges and at grazing angles, then axial noise.
  if (noisy) {
    const NoiseConfig& nc = noise_;
    const float edge_jump = float(nc.edge_jump_m);
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::int64_t row = 0; row < std::int64_t(H); ++row) {
      const std::uint32_t v = std::uint32_t(row);
      for (std::uint32_t u = 0; u < W; ++u) {
        const std::size_t i = std::size_t(v) * W + u;
        if (b.status[i] != kReturn)
          continue;
        const std::uint64_t pixel_seed = deriveSeed(frame_seed, i);
        const float r = b.range[i];
        bool edge = false;
        if (u > 0)
          edge |= std::abs(b.range[i - 1] - r) > edge_jump;
        if (u + 1 < W)
          edge |= std::abs(b.range[i + 1] - r) > edge_jump;
        if (v > 0)
          edge |= std::abs(b.range[i - W] - r) > edge_jump;
        if (v + 1 < H)
          edge |= std::abs(b.range[i + W] - r) > edge_jump;
        bool drop = edge && uniformDraw(pixel_seed, 4) < nc.edge_dropout_probability;
        if (!drop) {
          const double incidence = std::acos(double(b.cos_incidence[i]));
          drop = uniformDraw(pixel_seed, 5) < nc.grazingDropoutProbability(incidence);
        }
        double noisy_range = r;
        if (!drop) {
          double n0, n1;
          normalPair(pixel_seed, 2, n0, n1);
          noisy_range = double(r) + nc.axialSigma(r) * n0;
          drop = !(noisy_range > 0.0);
        }
        pcl::PointXYZL& p = cloud.points[i];
        if (drop) {
          b.status[i] = kNoSurface;
          p.x = p.y = p.z = kNaN;
          p.label = 0;
          if (depth)
            depth->depth_m[i] = kNaN;
          continue;
        }
        const float scale = float(noisy_range / double(r));
        p.x = o_f.x() + (p.x - o_f.x()) * scale;
        p.y = o_f.y() + (p.y - o_f.y()) * scale;
        p.z = o_f.z() + (p.z - o_f.z()) * scale;
        if (depth)
          depth->depth_m[i] = float(noisy_range * double(b.depth_per_range[i]));
      }
    }
  }

  std::size_t returns = 0;
  for (std::uint8_t s : b.status)
    returns += s == kReturn;
  cloud.is_dense = returns == N;

  if (far_points_W) {
    far_points_W->clear();
    far_points_W->header = cloud.header;
    for (std::uint32_t v = 0; v < H; ++v)
      for (std::uint32_t u = 0; u < W; ++u) {
        const std::size_t i = std::size_t(v) * W + u;
        if (b.status[i] != kFar)
          continue;
        const std::size_t tile = std::size_t(v / 4) * tiles_x + u / 4;
        const int k = int(v % 4) * 4 + int(u % 4);
        const float* r = rays_O + 48 * tile;
        const Eigen::Vector3f d_O =
            jitter ? jitteredRay(u, v, i) : Eigen::Vector3f(r[k], r[16 + k], r[32 + k]);
        const Eigen::Vector3f q = o_f + max_range * (R * d_O);
        far_points_W->push_back(pcl::PointXYZ(q.x(), q.y(), q.z()));
      }
    far_points_W->width = std::uint32_t(far_points_W->size());
    far_points_W->height = 1;
    far_points_W->is_dense = true;
  }
  ++frame_index_;
}

} // namespace plantnbv
