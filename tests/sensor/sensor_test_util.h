#pragma once
// Shared by the sensor tests: small meshes with known geometry, a double-precision
// reference ray caster, and camera helpers.

#include <cmath>
#include <cstdint>
#include <limits>

#include <Eigen/Geometry>

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/common/pose.h>
#include <plantnbv/common/triangle_mesh.h>
#include <plantnbv/sensor/simulated_depth_sensor.h>

namespace plantnbv {
namespace test {

/// A square of side 2 * half_size centred on `center`, spanned by unit vectors `a` and
/// `b` (normal a x b), as 2 triangles with `label`.
inline TriangleMesh makeQuad(const Eigen::Vector3d& center, const Eigen::Vector3d& a,
                             const Eigen::Vector3d& b, double half_size,
                             PartLabel label = PartLabel::leaflet)
{
  TriangleMesh mesh;
  for (int i = 0; i < 4; ++i) {
    const double sa = (i == 1 || i == 2) ? 1.0 : -1.0;
    const double sb = (i >= 2) ? 1.0 : -1.0;
    mesh.vertices.push_back((center + half_size * (sa * a + sb * b)).cast<float>());
  }
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  mesh.labels = {label, label};
  return mesh;
}

/// The same mesh with every triangle's winding reversed (normals flipped).
inline TriangleMesh flipped(TriangleMesh mesh)
{
  for (auto& t : mesh.triangles)
    std::swap(t[1], t[2]);
  return mesh;
}

/// A UV sphere whose poles lie on the axis through `center` along unit `pole` (the
/// first pole at center - radius * pole): `rings` latitude bands, `segments` longitudes.
/// Every vertex is on the sphere, so the mesh lies inside it.
inline TriangleMesh makeUvSphere(const Eigen::Vector3d& center, double radius,
                                 const Eigen::Vector3d& pole, int rings, int segments,
                                 PartLabel label = PartLabel::fruit)
{
  const Eigen::Vector3d w = pole.normalized();
  const Eigen::Vector3d u = w.unitOrthogonal();
  const Eigen::Vector3d v = w.cross(u);
  TriangleMesh mesh;
  mesh.vertices.push_back((center - radius * w).cast<float>());
  for (int r = 1; r < rings; ++r) {
    const double theta = M_PI * r / rings; // from the first pole
    for (int s = 0; s < segments; ++s) {
      const double phi = 2.0 * M_PI * s / segments;
      const Eigen::Vector3d p =
          center + radius * (-std::cos(theta) * w +
                             std::sin(theta) * (std::cos(phi) * u + std::sin(phi) * v));
      mesh.vertices.push_back(p.cast<float>());
    }
  }
  mesh.vertices.push_back((center + radius * w).cast<float>());
  const std::uint32_t last = std::uint32_t(mesh.vertices.size() - 1);
  auto ring = [&](int r, int s) {
    return std::uint32_t(1 + (r - 1) * segments + (s % segments));
  };
  for (int s = 0; s < segments; ++s)
    mesh.triangles.push_back({0, ring(1, s + 1), ring(1, s)});
  for (int r = 1; r + 1 < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      mesh.triangles.push_back({ring(r, s), ring(r, s + 1), ring(r + 1, s + 1)});
      mesh.triangles.push_back({ring(r, s), ring(r + 1, s + 1), ring(r + 1, s)});
    }
  for (int s = 0; s < segments; ++s)
    mesh.triangles.push_back({last, ring(rings - 1, s), ring(rings - 1, s + 1)});
  mesh.labels.assign(mesh.triangles.size(), label);
  return mesh;
}

/// The unit ray direction of pixel (u, v) in the world (double precision, no jitter).
inline Eigen::Vector3d pixelRay(const CameraIntrinsics& K, const Pose& T_W_C, double u,
                                double v)
{
  const Pose T_W_O = opticalFrame(T_W_C);
  return T_W_O.orientation *
         Eigen::Vector3d((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0).normalized();
}

/// Nearest hit of a ray with a mesh (Moller-Trumbore in double, both sides); infinity
/// if none. Barycentric bounds have a tolerance of 1e-9: Moller-Trumbore is not
/// watertight, and a ray through a shared edge can miss both of its triangles by a
/// rounding error (a pixel ray in the plane of a sphere's meridian does).
inline double referenceRange(const TriangleMesh& mesh, const Eigen::Vector3d& o,
                             const Eigen::Vector3d& d)
{
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>();
    const Eigen::Vector3d e1 = mesh.vertices[t[1]].cast<double>() - a;
    const Eigen::Vector3d e2 = mesh.vertices[t[2]].cast<double>() - a;
    const Eigen::Vector3d p = d.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-300)
      continue;
    const Eigen::Vector3d s = o - a;
    const double bu = s.dot(p) / det;
    constexpr double kTolerance = 1e-9;
    if (bu < -kTolerance || bu > 1.0 + kTolerance)
      continue;
    const Eigen::Vector3d q = s.cross(e1);
    const double bv = d.dot(q) / det;
    if (bv < -kTolerance || bu + bv > 1.0 + kTolerance)
      continue;
    const double range = e2.dot(q) / det;
    if (range > 0.0 && range < best)
      best = range;
  }
  return best;
}

/// A small camera with an exact centre pixel: odd size, principal point on a pixel.
inline CameraIntrinsics smallCamera(std::uint32_t width = 65, std::uint32_t height = 49,
                                    double f = 60.0)
{
  return CameraIntrinsics::custom(width, height, f, f, 0.5 * (width - 1),
                                  0.5 * (height - 1));
}

} // namespace test
} // namespace plantnbv
