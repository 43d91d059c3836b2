#pragma once
/// \file snapshot.h
/// \brief Offscreen pictures of a scene: a labelled plant mesh coloured by part (opaque
/// or faded), ROI boxes as wireframes, point clouds, camera frustums with numbers and
/// polylines such as a camera path, rendered by VTK into a PNG.
///
/// World frame as everywhere in plantnbv: metres, x forward from the robot, z up.
/// Rendering needs an X server (display.h): run programs that render under
/// `xvfb-run -a` on machines without a screen.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <plantnbv/common/box.h>
#include <plantnbv/common/pose.h>
#include <plantnbv/common/triangle_mesh.h>
#include <plantnbv/viz/palette.h>

namespace plantnbv {
namespace viz {

/// \brief An 8-bit RGB image, rows from the top, 3 bytes per pixel.
struct RgbImage {
  int width = 0;                 ///< pixels
  int height = 0;                ///< pixels
  std::vector<std::uint8_t> rgb; ///< width * height * 3 bytes

  /// \brief The first of the 3 bytes of pixel (x, y), y counted from the top row.
  std::uint8_t* at(int x, int y) { return rgb.data() + 3 * (std::size_t(y) * width + x); }
  /// \brief The first of the 3 bytes of pixel (x, y), read-only.
  const std::uint8_t* at(int x, int y) const
  {
    return rgb.data() + 3 * (std::size_t(y) * width + x);
  }
};

/// \brief Writes `image` as an 8-bit RGB PNG (zlib level 6).
/// \throws IoError naming the path and the system's reason when the file cannot be
/// written; InvalidArgumentError when the image's size and bytes disagree or it is empty.
void writePng(const RgbImage& image, const std::string& png_path);

/// \brief A camera: where it is, the point it looks at, and which way is up in the image.
struct CameraPose {
  Eigen::Vector3d position{-1.0, 0.0, 0.0};   ///< metres, world frame
  Eigen::Vector3d focal_point{0.0, 0.0, 0.0}; ///< the point looked at, world frame
  Eigen::Vector3d view_up{0.0, 0.0, 1.0};     ///< need not be orthogonal to the view axis
};

/// \brief Builds a scene from our types and renders it offscreen to a PNG.
///
/// Meshes are drawn in the colour of each triangle's PartLabel (palette.h), smooth-shaded
/// and two-sided (leaflets are single surfaces: no face is culled, back faces are lit as
/// well). ROI boxes are wireframes of one colour each, unlit so the colour stays exact;
/// their parts hidden behind the plant show through faintly (35 % opacity), so small
/// boxes inside the foliage (leaf nodes) stay visible. Points are drawn as small shaded
/// spheres. Lighting is VTK's light kit (key, fill, back and head lights) with some
/// ambient light.
///
/// Meshes may be translucent (`opacity` below 1), e.g. a faded plant around the
/// occupied voxels of a reconstruction: translucent surfaces are blended in depth order
/// by dual depth peeling (up to 8 peels of the nearest and farthest layer left; deeper
/// layers, if any, are blended unsorted), so the result does not depend on the order
/// things were added; points, lines and opaque meshes show through them. VTK 9.1 cannot
/// peel in a multisampled picture, so a scene with translucent meshes is anti-aliased by
/// FXAA instead (when Config::multisamples > 1; edges a little softer) and renders more
/// slowly (each peel draws the translucent meshes again).
///
/// Camera frustums and polylines (a camera path) are lines like the ROIs: unlit, one
/// colour, their hidden parts showing through faintly. A frustum's label is text in
/// the frustum's colour on a pale box (a dark one for light colours), drawn over
/// everything next to the apex, on the side away from the frustum, and kept inside the
/// picture; labels whose apex is behind the camera or outside the picture (an explicit
/// camera) are not drawn.
///
/// What is added is copied into VTK's structures at once; the arguments may be destroyed
/// afterwards. Empty meshes, clouds, ROIs and polylines add nothing. A scene with nothing
/// in it cannot be rendered (render throws): a picture of the background alone is almost
/// always a mistake.
///
/// Camera: by default it is placed automatically, front-left of the scene and slightly
/// above, like a person standing in front of the plant on the robot's side: it looks at
/// the centre of the bounding box of everything added, from a direction turned
/// `auto_azimuth_rad` from -x towards +y and raised `auto_elevation_rad`, as close as
/// everything allows (every vertex, box corner and point inside the picture, with
/// `auto_margin` to spare). It then moves sideways, keeping its direction, until the
/// scene is centred in the picture (perspective makes the near side look bigger), so
/// the focal point can differ from the centre by a few centimetres. Frustum corners and
/// polyline points count as points (labels do not: they are moved inside the picture).
/// A title gets a band of its own at the top, a legend one at the bottom. Config::camera
/// replaces it.
///
/// Thread safety: not thread-safe; render from one thread at a time (Xlib, OpenGL).
/// \code
/// plantnbv::viz::SceneSnapshot snapshot;
/// snapshot.addMesh(plant.mesh);
/// snapshot.addRoi(plantnbv::wholePlantRoi(plant), plantnbv::viz::distinctColor(0));
/// snapshot.render("plant.png"); // a 1200 x 900 PNG
///
/// // The reconstruction: plant faded, occupied voxels, the camera path with its views.
/// plantnbv::viz::SceneSnapshot nbv;
/// nbv.addMesh(plant.mesh, 0.25);
/// nbv.addPoints(voxel_centers, plantnbv::viz::distinctColor(6), 4.0f);
/// nbv.addPolyline(view_positions, plantnbv::viz::distinctColor(7));
/// for (std::size_t i = 0; i < views.size(); ++i)
///   nbv.addCameraFrustum(views[i], fov_h_rad, fov_v_rad, 0.15,
///                        plantnbv::viz::distinctColor(0), std::to_string(i + 1));
/// nbv.render("nbv.png");
/// \endcode
class SceneSnapshot {
public:
  /// \brief The picture and its camera; defaults in each field.
  struct Config {
    int width = 1200;                 ///< image width in pixels, in [16, 8192]
    int height = 900;                 ///< image height in pixels, in [16, 8192]
    Rgb background{1.0f, 1.0f, 1.0f}; ///< white
    /// Explicit camera; empty (default) = automatic, as the class describes.
    std::optional<CameraPose> camera;
    /// Vertical field of view (rad), in (0, pi); default 30 deg (VTK's default).
    double view_angle_rad = 0.5235987755982988;
    /// Automatic camera: angle from -x (the robot's side) towards +y (left) (rad);
    /// default 35 deg. Any finite value.
    double auto_azimuth_rad = 0.6108652381980153;
    /// Automatic camera: angle above the horizontal (rad), in [-85, 85] deg; default
    /// 15 deg.
    double auto_elevation_rad = 0.2617993877991494;
    /// Automatic camera: fraction of the image half-size left free around the scene's
    /// bounding box, in [0, 0.5); default 0.04.
    double auto_margin = 0.04;
    /// Text in the top-left corner (UTF-8; '\n' starts a line); empty (default) = none.
    std::string title;
    /// Height of the title's letters in pixels; 0 (default) = height / 22.
    int title_size_px = 0;
    /// Height of the letters of frustum labels in pixels, in [0, 1000]; 0 (default) =
    /// height / 30 (30 px at the default size).
    int label_size_px = 0;
    /// Multisample anti-aliasing: samples per pixel, in [0, 16] (0 or 1: none);
    /// default 8. With translucent meshes, more than 1 means FXAA instead (see above).
    int multisamples = 8;

    /// \brief One line per field, for logs.
    std::string toString() const;
  };

  /// \brief An empty scene with the default Config.
  SceneSnapshot();
  /// \throws InvalidArgumentError naming the first field of `config` out of range.
  explicit SceneSnapshot(const Config& config);
  ~SceneSnapshot();
  /// \brief Moves the scene and the configuration (not copyable).
  SceneSnapshot(SceneSnapshot&&) noexcept;
  /// \brief Moves the scene and the configuration.
  SceneSnapshot& operator=(SceneSnapshot&&) noexcept;
  SceneSnapshot(const SceneSnapshot&) = delete;
  SceneSnapshot& operator=(const SceneSnapshot&) = delete;

  /// \brief Replaces the configuration (the scene stays). \throws InvalidArgumentError
  /// naming the first field out of range.
  void setConfig(const Config& config);
  /// \brief The configuration of the next render().
  const Config& getConfig() const;

  /// \brief Adds a mesh coloured by part label (partLabelColor); a mesh without labels is
  /// drawn in the colour of PartLabel::unknown.
  /// \param[in] opacity in (0, 1]; default 1 (opaque). Below 1 the mesh is translucent
  /// (faded: 0.2-0.35 keeps the parts recognisable and what is inside visible).
  /// \throws FormatError if the mesh is invalid (TriangleMesh::validate);
  /// InvalidArgumentError for an opacity outside (0, 1].
  void addMesh(const TriangleMesh& mesh, double opacity = 1.0);
  /// \brief Adds a mesh in one colour, ignoring its labels, e.g. a reconstruction.
  /// \param[in] opacity in (0, 1]; default 1 (opaque), as above.
  /// \throws FormatError if the mesh is invalid; InvalidArgumentError for a colour
  /// outside [0, 1] or an opacity outside (0, 1].
  void addMesh(const TriangleMesh& mesh, const Rgb& color, double opacity = 1.0);

  /// \brief Adds every box of `roi` as a wireframe in `color`, lines `line_width_px`
  /// wide (default 2).
  /// \throws InvalidArgumentError for a colour outside [0, 1] or a line width outside
  /// (0, 20].
  void addRoi(const Roi& roi, const Rgb& color, float line_width_px = 2.0f);

  /// \brief Adds points (metres, world frame; non-finite ones are skipped) in one colour,
  /// each a sphere `point_size_px` pixels across (default 3), e.g. a reconstruction.
  /// \throws InvalidArgumentError for a colour outside [0, 1] or a size outside (0, 100].
  void addPoints(const std::vector<Eigen::Vector3f>& points, const Rgb& color,
                 float point_size_px = 3.0f);
  /// \brief Adds points coloured by part label, e.g. a labelled scan (Plant::scan_points
  /// and scan_labels). `labels` is empty (all unknown) or holds one label per point.
  /// \throws InvalidArgumentError for a label count that differs from the point count,
  /// a label outside PartLabel, or a size outside (0, 100].
  void addPoints(const std::vector<Eigen::Vector3f>& points,
                 const std::vector<PartLabel>& labels, float point_size_px = 3.0f);

  /// \brief Adds a camera's viewing frustum as lines: the pyramid from the camera's
  /// position (the apex) to the rectangle `depth_m` ahead, and that rectangle.
  ///
  /// The camera body frame is plantnbv's (pose.h): x forward (the viewing direction), y
  /// left, z up; the rectangle's corners are at x = depth_m, y = +-depth_m *
  /// tan(horizontal_fov_rad / 2), z = +-depth_m * tan(vertical_fov_rad / 2).
  /// \param[in] T_W_C the camera body frame in the world (metres).
  /// \param[in] horizontal_fov_rad, vertical_fov_rad full opening angles, in (0, pi).
  /// \param[in] depth_m distance of the far rectangle from the apex (m), in (0, 1e3].
  /// \param[in] color colour of the lines and the label.
  /// \param[in] label text next to the apex, e.g. the view's number "3"; empty
  /// (default) = none. Letters Config::label_size_px high.
  /// \param[in] line_width_px in (0, 20]; default 2.
  /// \throws InvalidArgumentError for a non-finite pose or a zero quaternion, an angle,
  /// depth, colour or line width out of range.
  void addCameraFrustum(const Pose& T_W_C, double horizontal_fov_rad,
                        double vertical_fov_rad, double depth_m, const Rgb& color,
                        const std::string& label = "", float line_width_px = 2.0f);

  /// \brief Adds a line through `points` in order (metres, world frame), e.g. the camera
  /// path of a reconstruction, `line_width_px` wide (default 2).
  ///
  /// A non-finite point breaks the line: the parts before and after it are drawn, not
  /// joined; a part of a single point draws nothing, so a polyline without 2
  /// consecutive finite points adds nothing.
  /// \throws InvalidArgumentError for a colour outside [0, 1] or a line width outside
  /// (0, 20].
  void addPolyline(const std::vector<Eigen::Vector3d>& points, const Rgb& color,
                   float line_width_px = 2.0f);

  /// \brief Adds an entry to the legend: a square of `color`, then `text` (UTF-8).
  ///
  /// The legend is a band along the bottom of the picture: the entries in the order
  /// added, left to right, wrapping to further rows (letters 3/4 of
  /// Config::label_size_px high, widths estimated from the letter count). The automatic camera leaves the band free.
  /// A legend alone is not a scene: empty() stays true.
  /// \throws InvalidArgumentError for an empty text or a colour outside [0, 1].
  void addLegendEntry(const std::string& text, const Rgb& color);

  /// \brief Removes everything added, the legend too.
  void clear();
  /// \brief True when nothing that can be drawn was added.
  bool empty() const;

  /// \brief The bounding box of everything added (metres).
  /// \throws InvalidArgumentError when the scene is empty.
  void bounds(Eigen::Vector3d& min, Eigen::Vector3d& max) const;

  /// \brief The camera render() uses: Config::camera, or the automatic one.
  /// \throws InvalidArgumentError for an automatic camera on an empty scene.
  CameraPose camera() const;

  /// \brief Renders the scene offscreen into an image of the configured size (with
  /// Mesa's software renderer a few hundred milliseconds for a plant, about twice as long
  /// with the plant translucent).
  /// \throws InvalidArgumentError when the scene is empty or the explicit camera is
  /// degenerate (position on the focal point, view up along the view axis, non-finite);
  /// Error when there is no X display (display.h gives the message).
  RgbImage renderImage() const;

  /// \brief renderImage(), written as a PNG (writePng).
  /// \throws as renderImage(), and IoError when the PNG cannot be written.
  void render(const std::string& png_path) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// \brief Adds a legend entry for each part label that occurs in `labels` (a mesh's or a
/// scan's, or a captured cloud's), in PartLabel order: the part's name in its colour
/// (partLabelColor). Nothing when `labels` is empty.
void addPartLegend(const std::vector<PartLabel>& labels, SceneSnapshot& snapshot);

} // namespace viz
} // namespace plantnbv
