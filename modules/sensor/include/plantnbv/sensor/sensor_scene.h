#pragma once
/// \file sensor_scene.h
/// \brief What the simulated depth sensor sees: triangle meshes and surfel clouds with
/// part labels, in the world frame, with one Embree 3 BVH over all of them. The sensor
/// knows no plants: a plant's scene (the plant on its support over a floor) is built one
/// floor up, in experiment/plant_scene.h.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <plantnbv/common/pcl_fwd.h>
#include <plantnbv/common/triangle_mesh.h>

namespace plantnbv {

/// \brief How a point cloud becomes surfels (discs).
struct SurfelOptions {
  /// Disc radius (metres). 0 (default) derives one radius per point from the local point
  /// spacing: radius_factor times the distance to the point's spacing_neighbours-th
  /// nearest neighbour, clamped to [1/4, 4] times the median of those distances (so
  /// isolated outliers do not become large discs). The defaults give sqrt(2) s on a
  /// square grid of spacing s (s / sqrt(2) closes every gap) and, on uniformly random
  /// points, about 2.7 times the mean nearest-neighbour distance, which leaves about
  /// 0.04% of the pixels of a plane uncovered (0.5% with the 4th neighbour, 1.8% with
  /// the 3rd). Otherwise finite and > 0: the same radius for every point.
  double radius_m = 0.0;
  /// Neighbour whose distance sets the radius (1 = the nearest), in [1, 32]; default 6.
  int spacing_neighbours = 6;
  /// Scale of the derived radius, > 0; default 1.
  double radius_factor = 1.0;

  /// \throws InvalidArgumentError naming the first bad field and its value.
  void validate() const;
};

/// \brief The radius of each surfel as SurfelOptions defines it (metres).
/// \throws InvalidArgumentError for invalid options, non-finite points, or a derived
/// radius with fewer than spacing_neighbours + 1 points.
std::vector<float> surfelRadii(const std::vector<Eigen::Vector3f>& points,
                               const SurfelOptions& options = {});

/// \brief Geometry in the world frame and its BVH (Embree 3, medium build quality).
///
/// Add meshes and surfels, then commit() builds the BVH once; SimulatedDepthSensor
/// casts rays against the committed scene. Adding geometry after commit() needs another
/// commit(). Triangles are hit from both sides (Embree's back-face culling is off in
/// Debian's build and not used here): leaflets are single surfaces. Each hit carries the
/// label of its triangle or surfel.
///
/// Thread safety: the add* methods and commit() must not run concurrently with anything
/// else on the same scene; a committed scene may be shared (std::shared_ptr<const>) by
/// any number of sensors capturing in parallel.
class SensorScene {
public:
  using Ptr = std::shared_ptr<SensorScene>;            ///< shared scene
  using ConstPtr = std::shared_ptr<const SensorScene>; ///< shared, read-only scene

  SensorScene();
  ~SensorScene();
  /// \brief Moves the geometry and the Embree scene (not copyable).
  SensorScene(SensorScene&&) noexcept;
  /// \brief Moves the geometry and the Embree scene.
  SensorScene& operator=(SensorScene&&) noexcept;
  SensorScene(const SensorScene&) = delete;
  SensorScene& operator=(const SensorScene&) = delete;

  /// \brief Adds a triangle mesh (world frame, metres); its labels, or `default_label`
  /// for every triangle if it has none. The vertices are copied.
  /// \return the geometry id of the mesh (0, 1, ... in the order of addition).
  /// \throws FormatError if the mesh is malformed (TriangleMesh::validate);
  /// InvalidArgumentError if it has no triangles.
  std::size_t addMesh(const TriangleMesh& mesh_W,
                      PartLabel default_label = PartLabel::unknown);

  /// \brief Adds a point cloud as ray-facing discs (Embree DISC_POINT): every ray sees a
  /// disc of the point's radius facing it, so no normals are needed.
  /// \param[in] points_W the points (world frame, metres), finite.
  /// \param[in] labels one per point, or empty (then `unknown`).
  /// \param[in] options the radius, fixed or from the spacing (SurfelOptions).
  /// \return the geometry id.
  /// \throws InvalidArgumentError for no points, non-finite points, a label count that
  /// differs from the point count, or invalid options.
  std::size_t addSurfels(const std::vector<Eigen::Vector3f>& points_W,
                         const std::vector<PartLabel>& labels,
                         const SurfelOptions& options = {});
  /// \brief As above, as oriented discs (Embree ORIENTED_DISC_POINT) with the given unit
  /// normals (one per point; they are normalised); such discs have a normal for the
  /// grazing-angle dropout of the noise model.
  std::size_t addSurfels(const std::vector<Eigen::Vector3f>& points_W,
                         const std::vector<PartLabel>& labels,
                         const std::vector<Eigen::Vector3f>& normals_W,
                         const SurfelOptions& options = {});
  /// \brief As the first overload, points and labels from a PCL cloud; non-finite points
  /// are skipped. \throws InvalidArgumentError if no finite point remains.
  std::size_t addSurfels(const CloudXYZL& cloud_W, const SurfelOptions& options = {});

  /// \brief Adds floorMesh(height_m, half_size_m, center_xy).
  std::size_t addFloor(double height_m, double half_size_m,
                       const Eigen::Vector2d& center_xy = Eigen::Vector2d::Zero());
  /// \brief Adds supportMesh(top_center_W, half_width_m, bottom_height_m).
  std::size_t addSupport(const Eigen::Vector3d& top_center_W, double half_width_m,
                         double bottom_height_m);

  /// \brief Builds (or rebuilds) the BVH, in time about linear in the primitives
  /// (docs/performance.md, "Sensor"). \throws Error if Embree reports an error.
  void commit();
  /// \brief True after commit() until geometry is added again.
  bool isCommitted() const;
  /// \brief Threads for commit() (Embree builds with TBB; 0, the default, uses all
  /// cores). Does not change results.
  void setNumberOfThreads(unsigned int threads) { threads_ = threads; }
  /// \brief Threads for commit(); 0 = all cores.
  unsigned int getNumberOfThreads() const { return threads_; }

  /// \brief Geometries added (meshes, surfel sets, floors, supports).
  std::size_t geometryCount() const;
  /// \brief Triangles over all meshes added.
  std::size_t triangleCount() const;
  /// \brief Surfels (discs) over all surfel sets added.
  std::size_t surfelCount() const;
  /// \brief Bounds of all geometry (metres, world frame; surfels with their radius).
  /// \throws InvalidArgumentError when the scene is empty.
  void bounds(Eigen::Vector3f& min, Eigen::Vector3f& max) const;

  /// Internal state (Embree handles); defined in the module's sources only.
  struct Impl;

private:
  friend class SimulatedDepthSensor;
  std::unique_ptr<Impl> impl_;
  unsigned int threads_ = 0;
};

/// \brief A horizontal square (2 triangles, labelled `background`) at `height_m`,
/// centred on `center_xy` (metres), `half_size_m` > 0.
/// \throws InvalidArgumentError for non-finite or non-positive values.
TriangleMesh floorMesh(double height_m, double half_size_m,
                       const Eigen::Vector2d& center_xy = Eigen::Vector2d::Zero());
/// \brief An axis-aligned box (12 triangles, labelled `background`) whose top face is
/// centred on `top_center_W` and whose bottom is at `bottom_height_m`.
/// \throws InvalidArgumentError unless the values are finite, half_width_m > 0 and the
/// top is above the bottom.
TriangleMesh supportMesh(const Eigen::Vector3d& top_center_W, double half_width_m,
                         double bottom_height_m);

} // namespace plantnbv
