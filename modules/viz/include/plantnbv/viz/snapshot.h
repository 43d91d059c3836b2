#pragma once
/// \file snapshot.h
/// \brief Offscreen pictures of a scene: a labelled plant mesh coloured by part, ROI
/// boxes as wireframes and point clouds, rendered by VTK into a PNG.
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
#include <plantnbv/common/triangle_mesh.h>
#include <plantnbv/viz/palette.h>

namespace plantnbv {
namespace viz {

/// \brief An 8-bit RGB image, rows from the top, 3 bytes per pixel.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb; ///< width * height * 3 bytes

  /// \brief The first of the 3 bytes of pixel (x, y), y counted from the top row.
  std::uint8_t* at(int x, int y) { return rgb.data() + 3 * (std::size_t(y) * width + x); }
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
  Eigen::Vector3d position{-1.0, 0.0, 0.0}; ///< metres, world frame
  Eigen::Vector3d focal_point{0.0, 0.0, 0.0};
  Eigen::Vector3d view_up{0.0, 0.0, 1.0}; ///< need not be orthogonal to the view axis
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
/// What is added is copied into VTK's structures at once; the arguments may be destroyed
/// afterwards. Empty meshes, clouds and ROIs add nothing. A scene with nothing in it
/// cannot be rendered (render throws): a picture of the background alone is almost
/// always a mistake.
///
/// Camera: by default it is placed automatically, front-left of the scene and slightly
/// above, like a person standing in front of the plant on the robot's side: it looks at
/// the centre of the bounding box of everything added, from a direction turned
/// `auto_azimuth_rad` from -x towards +y and raised `auto_elevation_rad`, as close as
/// everything allows (every vertex, box corner and point inside the picture, with
/// `auto_margin` to spare). It then moves sideways, keeping its direction, until the
/// scene is centred in the picture (perspective makes the near side look bigger), so
/// the focal point can differ from the centre by a few centimetres. A title gets a band
/// of its own at the top. Config::camera replaces it.
///
/// Thread safety: not thread-safe; render from one thread at a time (Xlib, OpenGL).
/// \code
/// plantnbv::viz::SceneSnapshot snapshot;
/// snapshot.addMesh(plant.mesh);
/// snapshot.addRoi(plantnbv::wholePlantRoi(plant), plantnbv::viz::distinctColor(0));
/// snapshot.render("plant.png"); // a 1200 x 900 PNG
/// \endcode
class SceneSnapshot {
public:
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
    /// Text in the top-left corner (UTF-8); empty (default) = none.
    std::string title;
    /// Height of the title's letters in pixels; 0 (default) = height / 22.
    int title_size_px = 0;
    /// Multisample anti-aliasing: samples per pixel, in [0, 16] (0 or 1: none);
    /// default 8.
    int multisamples = 8;

    /// \brief One line per field, for logs.
    std::string toString() const;
  };

  /// \brief An empty scene with the default Config.
  SceneSnapshot();
  /// \throws InvalidArgumentError naming the first field of `config` out of range.
  explicit SceneSnapshot(const Config& config);
  ~SceneSnapshot();
  SceneSnapshot(SceneSnapshot&&) noexcept;
  SceneSnapshot& operator=(SceneSnapshot&&) noexcept;
  SceneSnapshot(const SceneSnapshot&) = delete;
  SceneSnapshot& operator=(const SceneSnapshot&) = delete;

  /// \brief Replaces the configuration (the scene stays). \throws InvalidArgumentError
  /// naming the first field out of range.
  void setConfig(const Config& config);
  const Config& getConfig() const;

  /// \brief Adds a mesh coloured by part label (partLabelColor); a mesh without labels is
  /// drawn in the colour of PartLabel::unknown.
  /// \throws FormatError if the mesh is invalid (TriangleMesh::validate).
  void addMesh(const TriangleMesh& mesh);
  /// \brief Adds a mesh in one colour, ignoring its labels, e.g. a reconstruction.
  /// \throws FormatError if the mesh is invalid; InvalidArgumentError for a colour
  /// outside [0, 1].
  void addMesh(const TriangleMesh& mesh, const Rgb& color);

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

  /// \brief Removes everything added.
  void clear();
  /// \brief True when nothing that can be drawn was added.
  bool empty() const;

  /// \brief The bounding box of everything added (metres).
  /// \throws InvalidArgumentError when the scene is empty.
  void bounds(Eigen::Vector3d& min, Eigen::Vector3d& max) const;

  /// \brief The camera render() uses: Config::camera, or the automatic one.
  /// \throws InvalidArgumentError for an automatic camera on an empty scene.
  CameraPose camera() const;

  /// \brief Renders the scene offscreen into an image of the configured size (about
  /// 0.2-0.4 s for a 240k-triangle plant at 1200 x 900 with Mesa's software renderer).
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

} // namespace viz
} // namespace plantnbv
