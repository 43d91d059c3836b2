#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkLightKit.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkProperty.h>
#include <vtkProperty2D.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <plantnbv/common/error.h>
#include <plantnbv/viz/snapshot.h>

#include "window_image.h"
#include "x_display.h"

namespace plantnbv {
namespace viz {

namespace {

/// Relative luminance of an sRGB colour (Rec. 709 weights): picks dark or light text.
double luminance(const Rgb& c)
{
  return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

constexpr double kPi = 3.14159265358979323846;
/// Opacity of the lines (ROIs, frustums, polylines) drawn over everything, where the
/// plant hides them.
constexpr double kHiddenLineOpacity = 0.35;
/// Depth peeling of translucent meshes: at most this many peels (dual depth peeling
/// takes the nearest and the farthest layer in each), the rest is blended unsorted.
constexpr int kMaxPeels = 8;

std::string str(double v)
{
  std::ostringstream out;
  out << v;
  return out.str();
}

void checkColor(const Rgb& c, const char* what)
{
  for (float v : {c.r, c.g, c.b})
    if (!(v >= 0.0f && v <= 1.0f))
      throw InvalidArgumentError(std::string(what) + " (" + str(c.r) + ", " + str(c.g) +
                                 ", " + str(c.b) +
                                 ") is not a colour: expected 3 values in [0, 1]");
}

void checkRange(double v, double lo, double hi, const std::string& what)
{
  if (!(v > lo && v <= hi))
    throw InvalidArgumentError(what + " " + str(v) + " is outside (" + str(lo) + ", " +
                               str(hi) + "]");
}

void checkConfig(const SceneSnapshot::Config& c)
{
  if (c.width < 16 || c.width > 8192 || c.height < 16 || c.height > 8192)
    throw InvalidArgumentError("snapshot size " + std::to_string(c.width) + " x " +
                               std::to_string(c.height) +
                               " px is outside [16, 8192] x [16, 8192]");
  checkColor(c.background, "background colour");
  if (!(c.view_angle_rad > 0.0 && c.view_angle_rad < kPi))
    throw InvalidArgumentError("view_angle_rad " + str(c.view_angle_rad) +
                               " is outside (0, pi)");
  if (!std::isfinite(c.auto_azimuth_rad))
    throw InvalidArgumentError("auto_azimuth_rad " + str(c.auto_azimuth_rad) +
                               " is not finite");
  const double max_elevation = 85.0 * kPi / 180.0;
  if (!(std::abs(c.auto_elevation_rad) <= max_elevation))
    throw InvalidArgumentError("auto_elevation_rad " + str(c.auto_elevation_rad) +
                               " is outside [-85, 85] deg");
  if (!(c.auto_margin >= 0.0 && c.auto_margin < 0.5))
    throw InvalidArgumentError("auto_margin " + str(c.auto_margin) +
                               " is outside [0, 0.5)");
  if (c.title_size_px < 0 || c.title_size_px > 1000)
    throw InvalidArgumentError("title_size_px " + std::to_string(c.title_size_px) +
                               " is outside [0, 1000]");
  if (c.label_size_px < 0 || c.label_size_px > 1000)
    throw InvalidArgumentError("label_size_px " + std::to_string(c.label_size_px) +
                               " is outside [0, 1000]");
  if (c.multisamples < 0 || c.multisamples > 16)
    throw InvalidArgumentError("multisamples " + std::to_string(c.multisamples) +
                               " is outside [0, 16]");
}

void checkCamera(const CameraPose& camera)
{
  const Eigen::Vector3d axis = camera.focal_point - camera.position;
  if (!camera.position.allFinite() || !camera.focal_point.allFinite() ||
      !camera.view_up.allFinite())
    throw InvalidArgumentError("the camera has a non-finite position, focal point or "
                               "view up");
  if (axis.norm() < 1e-9)
    throw InvalidArgumentError("the camera's position is its focal point: no view axis");
  if (axis.normalized().cross(camera.view_up).norm() < 1e-6 * camera.view_up.norm() ||
      camera.view_up.norm() < 1e-12)
    throw InvalidArgumentError("the camera's view up is zero or along its view axis");
}

/// A copy of `values` in a new VTK float array of 3 components.
vtkSmartPointer<vtkFloatArray> floatArray3(const std::vector<Eigen::Vector3f>& values)
{
  auto array = vtkSmartPointer<vtkFloatArray>::New();
  array->SetNumberOfComponents(3);
  array->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
  float* out = array->GetPointer(0);
  for (const auto& v : values) {
    out[0] = v.x();
    out[1] = v.y();
    out[2] = v.z();
    out += 3;
  }
  return array;
}

/// Cells of `vertices_per_cell` consecutive ids each.
vtkSmartPointer<vtkCellArray> uniformCells(const std::vector<vtkIdType>& connectivity,
                                           vtkIdType vertices_per_cell)
{
  const auto cell_count = static_cast<vtkIdType>(connectivity.size()) / vertices_per_cell;
  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfTuples(cell_count + 1);
  for (vtkIdType i = 0; i <= cell_count; ++i)
    offsets->SetValue(i, i * vertices_per_cell);
  vtkNew<vtkIdTypeArray> ids;
  ids->SetNumberOfTuples(static_cast<vtkIdType>(connectivity.size()));
  std::copy(connectivity.begin(), connectivity.end(), ids->GetPointer(0));
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  cells->SetData(offsets, ids);
  return cells;
}

void setColor(vtkProperty* property, const Rgb& color)
{
  property->SetColor(color.r, color.g, color.b);
}

/// A smooth-shaded, two-sided actor for the triangles `tris` of `mesh`.
vtkSmartPointer<vtkActor> surfaceActor(const TriangleMesh& mesh,
                                       const std::vector<std::size_t>& tris,
                                       const Rgb& color, bool glossy, double opacity)
{
  std::vector<vtkIdType> remap(mesh.vertices.size(), -1);
  std::vector<Eigen::Vector3f> vertices;
  std::vector<vtkIdType> connectivity;
  connectivity.reserve(3 * tris.size());
  for (std::size_t t : tris)
    for (std::uint32_t v : mesh.triangles[t]) {
      if (remap[v] < 0) {
        remap[v] = static_cast<vtkIdType>(vertices.size());
        vertices.push_back(mesh.vertices[v]);
      }
      connectivity.push_back(remap[v]);
    }
  // Area-weighted vertex normals: smooth shading without VTK's normals filter.
  std::vector<Eigen::Vector3f> normals(vertices.size(), Eigen::Vector3f::Zero());
  for (std::size_t i = 0; i < connectivity.size(); i += 3) {
    const Eigen::Vector3f& a = vertices[connectivity[i]];
    const Eigen::Vector3f n =
        (vertices[connectivity[i + 1]] - a).cross(vertices[connectivity[i + 2]] - a);
    for (std::size_t k = 0; k < 3; ++k)
      normals[connectivity[i + k]] += n;
  }
  for (auto& n : normals) {
    const float norm = n.norm();
    n = norm > 0.0f ? Eigen::Vector3f(n / norm) : Eigen::Vector3f::UnitZ();
  }

  vtkNew<vtkPoints> points;
  points->SetData(floatArray3(vertices));
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetPolys(uniformCells(connectivity, 3));
  poly->GetPointData()->SetNormals(floatArray3(normals));

  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(poly);
  mapper->ScalarVisibilityOff();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  vtkProperty* property = actor->GetProperty();
  setColor(property, color);
  property->SetInterpolationToPhong();
  // Leaflets are single surfaces: both sides must be drawn (and lit, see render()).
  property->BackfaceCullingOff();
  property->FrontfaceCullingOff();
  property->SetAmbient(0.25);
  property->SetDiffuse(0.8);
  property->SetSpecular(glossy ? 0.35 : 0.05);
  property->SetSpecularPower(glossy ? 30.0 : 10.0);
  property->SetSpecularColor(1.0, 1.0, 1.0);
  property->SetOpacity(opacity);
  return actor;
}

/// Unlit lines of one colour between `vertices`, `segments` holding 2 vertex ids per
/// line: the actor drawn with the scene, and the same lines faint for the overlay.
std::array<vtkSmartPointer<vtkActor>, 2>
lineActors(const std::vector<Eigen::Vector3f>& vertices,
           const std::vector<vtkIdType>& segments, const Rgb& color, float line_width_px)
{
  vtkNew<vtkPoints> points;
  points->SetData(floatArray3(vertices));
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetLines(uniformCells(segments, 2));
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(poly);
  mapper->ScalarVisibilityOff();
  std::array<vtkSmartPointer<vtkActor>, 2> actors;
  for (std::size_t overlay = 0; overlay < 2; ++overlay) {
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    vtkProperty* property = actor->GetProperty();
    setColor(property, color);
    property->SetLineWidth(line_width_px);
    // Unlit: the lines keep exactly the caller's colour.
    property->LightingOff();
    if (overlay)
      property->SetOpacity(kHiddenLineOpacity);
    actors[overlay] = actor;
  }
  return actors;
}

/// Points drawn as shaded spheres; `colors` holds 3 bytes per point or is empty.
vtkSmartPointer<vtkActor> pointActor(const std::vector<Eigen::Vector3f>& points_in,
                                     const std::vector<std::uint8_t>& colors,
                                     const Rgb& color, float point_size_px)
{
  std::vector<Eigen::Vector3f> points;
  std::vector<std::uint8_t> kept_colors;
  points.reserve(points_in.size());
  for (std::size_t i = 0; i < points_in.size(); ++i) {
    if (!points_in[i].allFinite())
      continue;
    points.push_back(points_in[i]);
    if (!colors.empty())
      kept_colors.insert(kept_colors.end(), colors.begin() + 3 * i,
                         colors.begin() + 3 * i + 3);
  }
  if (points.empty())
    return nullptr;
  std::vector<vtkIdType> connectivity(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    connectivity[i] = static_cast<vtkIdType>(i);

  vtkNew<vtkPoints> vtk_points;
  vtk_points->SetData(floatArray3(points));
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(vtk_points);
  poly->SetVerts(uniformCells(connectivity, 1));
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(poly);
  if (!kept_colors.empty()) {
    vtkNew<vtkUnsignedCharArray> scalars;
    scalars->SetNumberOfComponents(3);
    scalars->SetNumberOfTuples(static_cast<vtkIdType>(points.size()));
    std::memcpy(scalars->GetPointer(0), kept_colors.data(), kept_colors.size());
    poly->GetPointData()->SetScalars(scalars);
    mapper->SetColorModeToDirectScalars();
    mapper->SetScalarModeToUsePointData();
    mapper->ScalarVisibilityOn();
  } else {
    mapper->ScalarVisibilityOff();
  }
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  vtkProperty* property = actor->GetProperty();
  setColor(property, color);
  property->SetPointSize(point_size_px);
  property->RenderPointsAsSpheresOn();
  property->SetAmbient(0.3);
  property->SetDiffuse(0.7);
  return actor;
}

int titleSizePx(const SceneSnapshot::Config& c)
{
  return c.title_size_px > 0 ? c.title_size_px : std::max(8, c.height / 22);
}

int labelSizePx(const SceneSnapshot::Config& c)
{
  return c.label_size_px > 0 ? c.label_size_px : std::max(8, c.height / 30);
}

/// One entry of the legend, placed: its row (0 = the bottom one) and left edge (px).
struct LegendEntry {
  std::string text;
  Rgb color;
  int row = 0;
  double left_px = 0.0;
};

/// The legend's geometry: letters 3/4 of the frustum labels' height, a square of the
/// letter height, a gap, the text (0.55 letter heights per character), a wider gap to
/// the next entry.
struct LegendLayout {
  explicit LegendLayout(const SceneSnapshot::Config& c) : size(0.75 * labelSizePx(c)) {}
  double size;
  double margin() const { return 0.5 * size; }
  double rowHeight() const { return 1.6 * size; }
  double swatchGap() const { return 0.5 * size; }
  double width(const std::string& text) const
  {
    return size + swatchGap() + 0.55 * size * double(text.size()) + 1.5 * size;
  }

  /// Places the entries in rows of at most `width_px`; returns the number of rows.
  int place(std::vector<LegendEntry>& entries, int width_px) const
  {
    int rows = entries.empty() ? 0 : 1;
    double x = margin();
    for (LegendEntry& e : entries) {
      const double w = width(e.text);
      if (x > margin() && x + w > width_px - margin()) {
        ++rows;
        x = margin();
      }
      e.row = rows - 1;
      e.left_px = x;
      x += w;
    }
    for (LegendEntry& e : entries) // row 0 at the bottom: the first row on top
      e.row = rows - 1 - e.row;
    return rows;
  }
  /// The band's height in pixels.
  double band(int rows) const { return rows ? rows * rowHeight() + margin() : 0.0; }
};

/// Projects world points into the picture of `pose` as VTK does (perspective, vertical
/// view angle, square pixels): display coordinates in pixels, y from the bottom row.
class Projection {
public:
  Projection(const CameraPose& pose, const SceneSnapshot::Config& c)
      : position_(pose.position), width_(c.width), height_(c.height)
  {
    forward_ = (pose.focal_point - pose.position).normalized();
    right_ = forward_.cross(pose.view_up).normalized();
    up_ = right_.cross(forward_);
    focal_px_ = 0.5 * c.height / std::tan(0.5 * c.view_angle_rad);
  }
  /// Distance of `p` in front of the camera along the view axis (m).
  double depth(const Eigen::Vector3d& p) const { return (p - position_).dot(forward_); }
  const Eigen::Vector3d& forward() const { return forward_; }
  /// For a point in front of the camera (depth > 0).
  Eigen::Vector2d display(const Eigen::Vector3d& p) const
  {
    const Eigen::Vector3d d = p - position_;
    const double z = d.dot(forward_);
    return {0.5 * width_ + focal_px_ * d.dot(right_) / z,
            0.5 * height_ + focal_px_ * d.dot(up_) / z};
  }

private:
  Eigen::Vector3d position_, forward_, right_, up_;
  double width_, height_, focal_px_;
};

/// A frustum's label, placed at render time when the camera is known.
struct FrustumLabel {
  std::string text;
  Rgb color;
  Eigen::Vector3d apex; ///< the camera's position (world frame)
  Eigen::Vector3d axis; ///< unit viewing direction
  double depth_m = 0.0; ///< the frustum's length along `axis`
};

/// Adds the text actors of `labels` to `overlay`, a renderer in a window of the
/// configured size: next to each apex, on the side away from its frustum, inside the
/// picture. Labels whose apex is behind the camera or outside the picture are skipped.
void addLabelActors(const std::vector<FrustumLabel>& labels, const CameraPose& pose,
                    const SceneSnapshot::Config& c, vtkRenderer* overlay)
{
  const Projection projection(pose, c);
  const int size_px = labelSizePx(c);
  for (const FrustumLabel& label : labels) {
    const double apex_depth = projection.depth(label.apex);
    if (!(apex_depth > 1e-6))
      continue;
    const Eigen::Vector2d apex = projection.display(label.apex);
    if (apex.x() < 0.0 || apex.x() > c.width || apex.y() < 0.0 || apex.y() > c.height)
      continue;
    // A point on the frustum's axis in front of the camera: its far end, or nearer when
    // the far end is behind the camera.
    double t = label.depth_m;
    const double toward = label.axis.dot(projection.forward());
    if (apex_depth + t * toward < 0.5 * apex_depth)
      t = -0.5 * apex_depth / toward;
    Eigen::Vector2d away = apex - projection.display(label.apex + t * label.axis);
    // Looking along the frustum's axis: any side will do.
    away = away.norm() > 1.0 ? Eigen::Vector2d(away.normalized())
                             : Eigen::Vector2d(1.0, 1.0).normalized();

    auto text = vtkSmartPointer<vtkTextActor>::New();
    text->SetInput(label.text.c_str());
    vtkTextProperty* property = text->GetTextProperty();
    property->SetFontSize(size_px);
    property->SetFontFamilyToArial();
    property->BoldOn();
    property->SetColor(label.color.r, label.color.g, label.color.b);
    property->SetJustificationToCentered();
    property->SetVerticalJustificationToCentered();
    // A box behind the letters keeps them readable over the plant and lines: pale for
    // dark colours, dark for light ones (yellow).
    const double box = luminance(label.color) > 0.6 ? 0.15 : 1.0;
    property->SetBackgroundColor(box, box, box);
    property->SetBackgroundOpacity(0.8);
    overlay->AddActor2D(text);

    // The box's half-size: measured by VTK (FreeType), or estimated.
    double extent[2] = {0.0, 0.0};
    text->GetSize(overlay, extent);
    if (!(extent[0] > 0.0 && extent[1] > 0.0)) {
      extent[0] = 0.65 * size_px * label.text.size() + 4.0;
      extent[1] = 1.2 * size_px + 4.0;
    }
    const Eigen::Vector2d half(0.5 * extent[0], 0.5 * extent[1]);
    // The box's centre moves from the apex along `away` until the box clears the apex,
    // plus a gap.
    const double gap = 0.25 * size_px;
    const double reach =
        std::min(std::abs(away.x()) > 1e-9 ? half.x() / std::abs(away.x()) : 1e300,
                 std::abs(away.y()) > 1e-9 ? half.y() / std::abs(away.y()) : 1e300);
    Eigen::Vector2d center = apex + (reach + gap) * away;
    // Inside the picture, with 2 pixels to spare (centred where it cannot fit).
    const auto clamp = [](double v, double half_size, double size) {
      const double lo = half_size + 2.0, hi = size - half_size - 2.0;
      return lo <= hi ? std::clamp(v, lo, hi) : 0.5 * size;
    };
    center.x() = clamp(center.x(), half.x(), c.width);
    center.y() = clamp(center.y(), half.y(), c.height);
    text->GetPositionCoordinate()->SetCoordinateSystemToDisplay();
    text->SetPosition(center.x(), center.y());
  }
}

/// The legend along the bottom (SceneSnapshot::addLegendEntry): squares and texts.
void addLegendActors(std::vector<LegendEntry> entries, const SceneSnapshot::Config& c,
                     vtkRenderer* overlay)
{
  const LegendLayout layout(c);
  layout.place(entries, c.width);
  const double ink = luminance(c.background) > 0.5 ? 0.1 : 0.95;
  for (const LegendEntry& e : entries) {
    const double middle = layout.margin() + (e.row + 0.5) * layout.rowHeight();
    const double half = 0.5 * layout.size;
    vtkNew<vtkPoints> corners;
    corners->InsertNextPoint(e.left_px, middle - half, 0.0);
    corners->InsertNextPoint(e.left_px + layout.size, middle - half, 0.0);
    corners->InsertNextPoint(e.left_px + layout.size, middle + half, 0.0);
    corners->InsertNextPoint(e.left_px, middle + half, 0.0);
    vtkNew<vtkCellArray> square;
    const vtkIdType ids[4] = {0, 1, 2, 3};
    square->InsertNextCell(4, ids);
    vtkNew<vtkPolyData> polygon;
    polygon->SetPoints(corners);
    polygon->SetPolys(square);
    vtkNew<vtkPolyDataMapper2D> mapper;
    mapper->SetInputData(polygon);
    vtkNew<vtkActor2D> swatch;
    swatch->SetMapper(mapper);
    swatch->GetProperty()->SetColor(e.color.r, e.color.g, e.color.b);
    overlay->AddActor2D(swatch);

    vtkNew<vtkTextActor> text;
    text->SetInput(e.text.c_str());
    vtkTextProperty* property = text->GetTextProperty();
    property->SetFontSize(static_cast<int>(layout.size));
    property->SetFontFamilyToArial();
    property->SetColor(ink, ink, ink);
    property->SetJustificationToLeft();
    property->SetVerticalJustificationToCentered();
    text->GetPositionCoordinate()->SetCoordinateSystemToDisplay();
    text->SetPosition(e.left_px + layout.size + layout.swatchGap(), middle);
    overlay->AddActor2D(text);
  }
}

std::uint8_t toByte(float v)
{
  return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

} // namespace

std::string SceneSnapshot::Config::toString() const
{
  std::ostringstream out;
  out << "width: " << width << " px\nheight: " << height << " px\nbackground: ("
      << background.r << ", " << background.g << ", " << background.b << ")\ncamera: ";
  if (camera)
    out << "position (" << camera->position.transpose() << "), focal point ("
        << camera->focal_point.transpose() << "), view up ("
        << camera->view_up.transpose() << ")";
  else
    out << "automatic";
  out << "\nview_angle_rad: " << view_angle_rad
      << "\nauto_azimuth_rad: " << auto_azimuth_rad
      << "\nauto_elevation_rad: " << auto_elevation_rad
      << "\nauto_margin: " << auto_margin << "\ntitle: \"" << title
      << "\"\ntitle_size_px: " << title_size_px << "\nlabel_size_px: " << label_size_px
      << "\nmultisamples: " << multisamples << "\n";
  return out.str();
}

struct SceneSnapshot::Impl {
  Config config;
  std::vector<vtkSmartPointer<vtkActor>> actors;
  /// Lines again (ROIs, frustums, polylines), drawn faintly over everything (see the
  /// class comment).
  std::vector<vtkSmartPointer<vtkActor>> overlay_actors;
  std::vector<FrustumLabel> labels;
  std::vector<LegendEntry> legend;
  bool translucent = false;   ///< a mesh with opacity below 1 was added
  Eigen::AlignedBox3d bounds; ///< empty until something is added
  /// Every point drawn (vertices, box corners, cloud points): the automatic camera fits
  /// them, not the bounding box, whose corners are often empty space.
  std::vector<Eigen::Vector3f> points;

  void extend(const Eigen::Vector3f& p)
  {
    bounds.extend(p.cast<double>());
    points.push_back(p);
  }
  /// Extends by the vertices the triangles use.
  void extend(const TriangleMesh& mesh)
  {
    std::vector<bool> used(mesh.vertices.size(), false);
    for (const auto& tri : mesh.triangles)
      for (std::uint32_t v : tri)
        used[v] = true;
    for (std::size_t v = 0; v < used.size(); ++v)
      if (used[v])
        extend(mesh.vertices[v]);
  }
  /// Adds lines (lineActors) and extends by their vertices.
  void addLines(const std::vector<Eigen::Vector3f>& vertices,
                const std::vector<vtkIdType>& segments, const Rgb& color,
                float line_width_px)
  {
    const auto line_actors = lineActors(vertices, segments, color, line_width_px);
    actors.push_back(line_actors[0]);
    overlay_actors.push_back(line_actors[1]);
    for (const auto& v : vertices)
      extend(v);
  }
};

SceneSnapshot::SceneSnapshot() : impl_(std::make_unique<Impl>()) {}

SceneSnapshot::SceneSnapshot(const Config& config) : SceneSnapshot()
{
  setConfig(config);
}

SceneSnapshot::~SceneSnapshot() = default;
SceneSnapshot::SceneSnapshot(SceneSnapshot&&) noexcept = default;
SceneSnapshot& SceneSnapshot::operator=(SceneSnapshot&&) noexcept = default;

void SceneSnapshot::setConfig(const Config& config)
{
  checkConfig(config);
  if (config.camera)
    checkCamera(*config.camera);
  impl_->config = config;
}

const SceneSnapshot::Config& SceneSnapshot::getConfig() const
{
  return impl_->config;
}

void SceneSnapshot::addMesh(const TriangleMesh& mesh, double opacity)
{
  checkRange(opacity, 0.0, 1.0, "mesh opacity");
  mesh.validate();
  if (mesh.empty())
    return;
  constexpr std::size_t kLabelCount = 7;
  std::vector<std::size_t> by_label[kLabelCount];
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    const auto label = mesh.hasLabels() ? static_cast<std::size_t>(mesh.labels[t]) : 0;
    if (label >= kLabelCount)
      throw InvalidArgumentError("triangle " + std::to_string(t) + " has part label " +
                                 std::to_string(label) + ", not a PartLabel");
    by_label[label].push_back(t);
  }
  for (std::size_t label = 0; label < kLabelCount; ++label)
    if (!by_label[label].empty()) {
      const auto part = static_cast<PartLabel>(label);
      impl_->actors.push_back(surfaceActor(mesh, by_label[label], partLabelColor(part),
                                           part == PartLabel::fruit, opacity));
    }
  impl_->extend(mesh);
  impl_->translucent = impl_->translucent || opacity < 1.0;
}

void SceneSnapshot::addMesh(const TriangleMesh& mesh, const Rgb& color, double opacity)
{
  checkColor(color, "mesh colour");
  checkRange(opacity, 0.0, 1.0, "mesh opacity");
  mesh.validate();
  if (mesh.empty())
    return;
  std::vector<std::size_t> all(mesh.size());
  for (std::size_t t = 0; t < all.size(); ++t)
    all[t] = t;
  impl_->actors.push_back(surfaceActor(mesh, all, color, false, opacity));
  impl_->extend(mesh);
  impl_->translucent = impl_->translucent || opacity < 1.0;
}

void SceneSnapshot::addRoi(const Roi& roi, const Rgb& color, float line_width_px)
{
  checkColor(color, "ROI colour");
  checkRange(line_width_px, 0.0, 20.0, "ROI line width (px)");
  if (roi.empty())
    return;
  // The 12 edges of each box, between corners numbered by their (x, y, z) bits.
  static constexpr int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                        {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  std::vector<Eigen::Vector3f> corners;
  std::vector<vtkIdType> connectivity;
  for (const Box& box : roi.boxes()) {
    const auto base = static_cast<vtkIdType>(corners.size());
    const Eigen::Vector3d lo = box.min(), hi = box.max();
    for (int c = 0; c < 8; ++c)
      corners.emplace_back(Eigen::Vector3d((c & 1) ? hi.x() : lo.x(),
                                           (c & 2) ? hi.y() : lo.y(),
                                           (c & 4) ? hi.z() : lo.z())
                               .cast<float>());
    for (const auto& edge : kEdges) {
      connectivity.push_back(base + edge[0]);
      connectivity.push_back(base + edge[1]);
    }
  }
  impl_->addLines(corners, connectivity, color, line_width_px);
}

void SceneSnapshot::addCameraFrustum(const Pose& T_W_C, double horizontal_fov_rad,
                                     double vertical_fov_rad, double depth_m,
                                     const Rgb& color, const std::string& label,
                                     float line_width_px)
{
  if (!T_W_C.position.allFinite() || !T_W_C.orientation.coeffs().allFinite())
    throw InvalidArgumentError("the frustum's pose is not finite");
  if (!(T_W_C.orientation.norm() > 1e-12))
    throw InvalidArgumentError("the frustum's pose has a zero quaternion");
  for (double fov : {horizontal_fov_rad, vertical_fov_rad})
    if (!(fov > 0.0 && fov < kPi))
      throw InvalidArgumentError("frustum field of view " + str(fov) +
                                 " rad is outside (0, pi)");
  checkRange(depth_m, 0.0, 1e3, "frustum depth (m)");
  checkColor(color, "frustum colour");
  checkRange(line_width_px, 0.0, 20.0, "frustum line width (px)");

  const Eigen::Quaterniond q = T_W_C.orientation.normalized();
  const double half_y = depth_m * std::tan(0.5 * horizontal_fov_rad);
  const double half_z = depth_m * std::tan(0.5 * vertical_fov_rad);
  // The apex, then the far rectangle's corners in order round it (body frame: x
  // forward, y left, z up): top left, top right, bottom right, bottom left.
  const Eigen::Vector3d corners_C[5] = {{0.0, 0.0, 0.0},
                                        {depth_m, half_y, half_z},
                                        {depth_m, -half_y, half_z},
                                        {depth_m, -half_y, -half_z},
                                        {depth_m, half_y, -half_z}};
  std::vector<Eigen::Vector3f> vertices;
  for (const auto& p_C : corners_C)
    vertices.push_back((T_W_C.position + q * p_C).cast<float>());
  const std::vector<vtkIdType> segments = {0, 1, 0, 2, 0, 3, 0, 4,
                                           1, 2, 2, 3, 3, 4, 4, 1};
  impl_->addLines(vertices, segments, color, line_width_px);
  if (!label.empty())
    impl_->labels.push_back(
        {label, color, T_W_C.position, q * Eigen::Vector3d::UnitX(), depth_m});
}

void SceneSnapshot::addPolyline(const std::vector<Eigen::Vector3d>& points,
                                const Rgb& color, float line_width_px)
{
  checkColor(color, "polyline colour");
  checkRange(line_width_px, 0.0, 20.0, "polyline line width (px)");
  std::vector<Eigen::Vector3f> vertices;
  std::vector<vtkIdType> segments;
  // Vertices of the current unbroken run start at run_begin.
  std::size_t run_begin = 0;
  for (const Eigen::Vector3d& p : points) {
    if (!p.allFinite()) {
      // A lone point before the break draws nothing: drop it.
      if (vertices.size() == run_begin + 1)
        vertices.pop_back();
      run_begin = vertices.size();
      continue;
    }
    vertices.push_back(p.cast<float>());
    const auto i = static_cast<vtkIdType>(vertices.size() - 1);
    if (vertices.size() > run_begin + 1) {
      segments.push_back(i - 1);
      segments.push_back(i);
    }
  }
  if (vertices.size() == run_begin + 1)
    vertices.pop_back();
  if (segments.empty())
    return;
  impl_->addLines(vertices, segments, color, line_width_px);
}

void SceneSnapshot::addPoints(const std::vector<Eigen::Vector3f>& points,
                              const Rgb& color, float point_size_px)
{
  checkColor(color, "point colour");
  checkRange(point_size_px, 0.0, 100.0, "point size (px)");
  auto actor = pointActor(points, {}, color, point_size_px);
  if (!actor)
    return;
  impl_->actors.push_back(actor);
  for (const auto& p : points)
    if (p.allFinite())
      impl_->extend(p);
}

void SceneSnapshot::addPoints(const std::vector<Eigen::Vector3f>& points,
                              const std::vector<PartLabel>& labels, float point_size_px)
{
  checkRange(point_size_px, 0.0, 100.0, "point size (px)");
  if (!labels.empty() && labels.size() != points.size())
    throw InvalidArgumentError(std::to_string(labels.size()) + " labels for " +
                               std::to_string(points.size()) +
                               " points: expected one label per point, or none");
  std::vector<std::uint8_t> colors(3 * points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Rgb c = partLabelColor(labels.empty() ? PartLabel::unknown : labels[i]);
    colors[3 * i] = toByte(c.r);
    colors[3 * i + 1] = toByte(c.g);
    colors[3 * i + 2] = toByte(c.b);
  }
  auto actor =
      pointActor(points, colors, partLabelColor(PartLabel::unknown), point_size_px);
  if (!actor)
    return;
  impl_->actors.push_back(actor);
  for (const auto& p : points)
    if (p.allFinite())
      impl_->extend(p);
}

void SceneSnapshot::addLegendEntry(const std::string& text, const Rgb& color)
{
  if (text.empty())
    throw InvalidArgumentError("a legend entry needs a text");
  checkColor(color, "legend colour");
  impl_->legend.push_back({text, color});
}

void SceneSnapshot::clear()
{
  impl_->actors.clear();
  impl_->overlay_actors.clear();
  impl_->labels.clear();
  impl_->legend.clear();
  impl_->translucent = false;
  impl_->bounds.setEmpty();
  impl_->points.clear();
}

bool SceneSnapshot::empty() const
{
  return impl_->actors.empty();
}

void SceneSnapshot::bounds(Eigen::Vector3d& min, Eigen::Vector3d& max) const
{
  if (empty())
    throw InvalidArgumentError("the bounds of an empty scene are undefined: add a mesh, "
                               "points or an ROI first");
  min = impl_->bounds.min();
  max = impl_->bounds.max();
}

CameraPose SceneSnapshot::camera() const
{
  const Config& c = impl_->config;
  if (c.camera)
    return *c.camera;
  Eigen::Vector3d min, max;
  bounds(min, max);
  const Eigen::Vector3d center = 0.5 * (min + max);
  // From the centre towards the camera: -x (the robot's side), turned towards +y (left)
  // and raised.
  const double ce = std::cos(c.auto_elevation_rad);
  const Eigen::Vector3d to_camera(-std::cos(c.auto_azimuth_rad) * ce,
                                  std::sin(c.auto_azimuth_rad) * ce,
                                  std::sin(c.auto_elevation_rad));
  const Eigen::Vector3d forward = -to_camera;
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d up = right.cross(forward);
  // The picture's half-height in tangent units, and the part of it the scene may use:
  // the margin all round, and a band at the top for the title.
  const double tan_half = std::tan(0.5 * c.view_angle_rad);
  const double title_band =
      c.title.empty()
          ? 0.0
          : 2.0 *
                (0.02 * c.height +
                 1.25 * titleSizePx(c) *
                     double(1 + std::count(c.title.begin(), c.title.end(), '\n'))) /
                c.height;
  std::vector<LegendEntry> legend = impl_->legend;
  const LegendLayout layout(c);
  const double legend_band = 2.0 * layout.band(layout.place(legend, c.width)) / c.height;
  // A huge title or legend still leaves the scene a tenth of the height.
  const double tan_top = tan_half * std::max(0.1, 1.0 - c.auto_margin - title_band);
  const double tan_bottom = tan_half * std::max(0.1, 1.0 - c.auto_margin - legend_band);
  const double tan_side = tan_half * (1.0 - c.auto_margin) * c.width / c.height;
  const double target_y = 0.5 * (tan_top - tan_bottom); // centre of the usable part
  const auto& points = impl_->points;
  // The nearest distance from `focal` at which every point projects inside the usable
  // part of the picture: |x| <= tan_side * depth, -tan_bottom * depth <= y <= tan_top *
  // depth, with depth = distance + z.
  const auto fit = [&](const Eigen::Vector3d& focal) {
    double distance = 0.0;
    for (const Eigen::Vector3f& p : points) {
      const Eigen::Vector3d d = p.cast<double>() - focal;
      const double x = d.dot(right), y = d.dot(up), z = d.dot(forward);
      distance = std::max({distance, std::abs(x) / tan_side - z,
                           (y > 0 ? y / tan_top : -y / tan_bottom) - z, 0.01 - z});
    }
    return distance;
  };
  // Perspective makes the near side of the scene look bigger: move the focal point
  // sideways (the view direction stays) until the picture of the scene is centred.
  Eigen::Vector3d focal = center;
  double distance = fit(focal);
  for (int iteration = 0; iteration < 4 && distance > 0.01; ++iteration) {
    Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
    for (const Eigen::Vector3f& p : points) {
      const Eigen::Vector3d d = p.cast<double>() - focal;
      const double depth = distance + d.dot(forward);
      const Eigen::Vector2d image(d.dot(right) / depth, d.dot(up) / depth);
      lo = lo.cwiseMin(image);
      hi = hi.cwiseMax(image);
    }
    const Eigen::Vector2d offset =
        (0.5 * (lo + hi) - Eigen::Vector2d(0.0, target_y)) * distance;
    focal += offset.x() * right + offset.y() * up;
    distance = fit(focal);
  }
  if (distance <= 0.01) // a single point: any distance shows it
    distance = 1.0;
  CameraPose pose;
  pose.focal_point = focal;
  pose.position = focal + distance * to_camera;
  pose.view_up = up;
  return pose;
}

RgbImage SceneSnapshot::renderImage() const
{
  if (empty())
    throw InvalidArgumentError("cannot render an empty scene: add a mesh, points or an "
                               "ROI first");
  const Config& c = impl_->config;
  const CameraPose pose = camera();

  vtkNew<vtkCamera> camera;
  camera->SetPosition(pose.position.data());
  camera->SetFocalPoint(pose.focal_point.data());
  camera->SetViewUp(pose.view_up.data());
  camera->SetViewAngle(c.view_angle_rad * 180.0 / kPi);

  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(c.background.r, c.background.g, c.background.b);
  // Back faces of leaflets are lit like front faces.
  renderer->TwoSidedLightingOn();
  renderer->SetActiveCamera(camera);
  vtkNew<vtkLightKit> lights;
  lights->AddLightsToRenderer(renderer);
  for (const auto& actor : impl_->actors)
    renderer->AddActor(actor);
  double bounds[6] = {impl_->bounds.min().x(), impl_->bounds.max().x(),
                      impl_->bounds.min().y(), impl_->bounds.max().y(),
                      impl_->bounds.min().z(), impl_->bounds.max().z()};
  renderer->ResetCameraClippingRange(bounds);
  // Translucent meshes are sorted per pixel by depth peeling (see the class comment).
  // VTK 9.1's peeling draws nothing translucent into a multisampled window, and its
  // alternative without peeling (weighted-average blending) ignores which surface is
  // in front; so multisampling gives way to FXAA here.
  const bool peel = impl_->translucent;
  if (peel) {
    renderer->UseDepthPeelingOn();
    renderer->SetMaximumNumberOfPeels(kMaxPeels);
    renderer->SetOcclusionRatio(0.0);
    renderer->SetUseFXAA(c.multisamples > 1);
  }

  // A second layer with its own depth buffer: ROI lines hidden by the plant show through.
  vtkNew<vtkRenderer> overlay;
  overlay->SetLayer(1);
  overlay->SetActiveCamera(camera);
  overlay->InteractiveOff();
  for (const auto& actor : impl_->overlay_actors)
    overlay->AddActor(actor);

  if (!c.title.empty()) {
    vtkNew<vtkTextActor> title;
    title->SetInput(c.title.c_str());
    vtkTextProperty* text = title->GetTextProperty();
    text->SetFontSize(titleSizePx(c));
    text->SetFontFamilyToArial();
    text->SetVerticalJustificationToTop();
    text->SetJustificationToLeft();
    const double ink = luminance(c.background) > 0.5 ? 0.1 : 0.95;
    text->SetColor(ink, ink, ink);
    title->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    title->SetPosition(0.02, 0.98);
    overlay->AddActor2D(title);
  }

  addLegendActors(impl_->legend, c, overlay);

  // The connection outlives the window, which uses it and does not close it.
  detail::XDisplayConnection display;
  vtkNew<vtkRenderWindow> window;
  window->SetDisplayId(display.handle());
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(peel ? 0 : c.multisamples);
  window->SetSize(c.width, c.height);
  window->SetNumberOfLayers(2);
  window->AddRenderer(renderer);
  window->AddRenderer(overlay);
  if (peel)
    window->AlphaBitPlanesOn();
  // Frustum labels, placed now that the picture's size and camera are known: they need
  // the window for their size.
  addLabelActors(impl_->labels, pose, c, overlay);
  window->Render();

  RgbImage image = detail::readWindowImage(window, c.width, c.height);
  window->Finalize();
  return image;
}

void SceneSnapshot::render(const std::string& png_path) const
{
  writePng(renderImage(), png_path);
}

void addPartLegend(const std::vector<PartLabel>& labels, SceneSnapshot& snapshot)
{
  constexpr std::size_t kLabels = static_cast<std::size_t>(kLastPartLabel) + 1;
  bool seen[kLabels] = {};
  for (PartLabel l : labels)
    if (static_cast<std::size_t>(l) < kLabels)
      seen[static_cast<std::size_t>(l)] = true;
  for (std::size_t l = 0; l < kLabels; ++l)
    if (seen[l]) {
      const PartLabel label = static_cast<PartLabel>(l);
      snapshot.addLegendEntry(partLabelName(label), partLabelColor(label));
    }
}

} // namespace viz
} // namespace plantnbv
