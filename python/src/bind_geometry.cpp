// Box, Roi, poses and frames, camera intrinsics, part labels, Mesh.

#include <pybind11/stl.h>
#include <sstream>

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/camera/optical_frame.h>
#include <plantnbv/common/box.h>
#include <plantnbv/common/error.h>
#include <plantnbv/common/triangle_mesh.h>

#include "arrays.h"
#include "bindings.h"

namespace plantnbv {
namespace python {

namespace {

using namespace pybind11::literals;

/// contains() of a box or an ROI over (N, 3) points: an (N,) bool array.
template <typename Region>
py::array_t<bool> containsPoints(const Region& region, const py::handle& points)
{
  const std::vector<Eigen::Vector3f> p = readPointVector(points, "points");
  py::array_t<bool> out(py::ssize_t(p.size()));
  bool* o = out.mutable_data();
  for (const Eigen::Vector3f& q : p)
    *o++ = region.contains(q.x(), q.y(), q.z());
  return out;
}

std::string boxRepr(const Box& b)
{
  std::ostringstream s;
  s << "Box(center=[" << b.center.x() << ", " << b.center.y() << ", " << b.center.z()
    << "], size=[" << b.size.x() << ", " << b.size.y() << ", " << b.size.z() << "]"
    << (b.name.empty() ? "" : ", name='" + b.name + "'") << ")";
  return s.str();
}

std::vector<std::array<std::uint32_t, 3>> readTriangles(const py::handle& triangles,
                                                        std::size_t vertex_count)
{
  const char* expected = "an (F, 3) array of vertex indices (integers >= 0)";
  if (!py::isinstance<py::array>(triangles) && !py::isinstance<py::list>(triangles) &&
      !py::isinstance<py::tuple>(triangles))
    throw py::type_error(badArgument("triangles", expected, triangles));
  const py::array a = py::module_::import("numpy").attr("asarray")(triangles);
  if ((a.dtype().kind() != 'i' && a.dtype().kind() != 'u') || a.ndim() != 2 ||
      a.shape(1) != 3)
    throw py::value_error(badArgument("triangles", expected, a));
  const auto t = py::array_t<std::int64_t>::ensure(a);
  const auto r = t.unchecked<2>();
  std::vector<std::array<std::uint32_t, 3>> out(std::size_t(r.shape(0)));
  for (py::ssize_t f = 0; f < r.shape(0); ++f)
    for (int k = 0; k < 3; ++k) {
      if (r(f, k) < 0 || std::uint64_t(r(f, k)) >= vertex_count)
        throw py::value_error("triangles[" + std::to_string(f) + "]: vertex index " +
                              std::to_string(r(f, k)) + " is not in [0, " +
                              std::to_string(vertex_count) + ")");
      out[std::size_t(f)][std::size_t(k)] = std::uint32_t(r(f, k));
    }
  return out;
}

} // namespace

void bindGeometry(py::module_& m)
{
  py::class_<Box>(
      m, "Box",
      "An axis-aligned box in the world frame, by centre and size (metres). A "
      "point on a face is inside.")
      .def(py::init(
               [](const py::handle& center, const py::handle& size, std::string name) {
                 return Box(readVector3(center, "center"), readVector3(size, "size"),
                            std::move(name));
               }),
           "center"_a, "size"_a, "name"_a = "")
      .def_static(
          "from_min_max",
          [](const py::handle& min, const py::handle& max, std::string name) {
            return Box::fromMinMax(readVector3(min, "min"), readVector3(max, "max"),
                                   std::move(name));
          },
          "min"_a, "max"_a, "name"_a = "", "The box spanning [min, max].")
      .def_property_readonly("center", [](const Box& b) { return vectorArray(b.center); })
      .def_property_readonly("size", [](const Box& b) { return vectorArray(b.size); })
      .def_property_readonly("min", [](const Box& b) { return vectorArray(b.min()); })
      .def_property_readonly("max", [](const Box& b) { return vectorArray(b.max()); })
      .def_readwrite("name", &Box::name)
      .def_property_readonly("volume", &Box::volume, "Cubic metres.")
      .def("contains", &containsPoints<Box>, "points"_a,
           "An (N,) bool array: which of the (N, 3) points lie in the box.")
      .def("__repr__", &boxRepr);

  py::class_<Roi>(m, "Roi",
                  "A region of interest: a union of boxes (world frame). An empty ROI "
                  "contains nothing; a planner given one attends to every voxel.")
      .def(py::init<>())
      .def(py::init([](const std::vector<Box>& boxes) { return Roi(boxes); }), "boxes"_a)
      .def("add_box", &Roi::addBox, "box"_a)
      .def_property_readonly("boxes", &Roi::boxes, "The boxes (copies).")
      .def("__len__", &Roi::size)
      .def("__bool__", [](const Roi& r) { return !r.empty(); })
      .def("__iter__", [](const Roi& r) { return py::iter(py::cast(r.boxes())); })
      .def("contains", &containsPoints<Roi>, "points"_a,
           "An (N,) bool array: which of the (N, 3) points lie in any box.")
      .def("bounding_box", &Roi::boundingBox, "The smallest box holding every box.")
      .def("__repr__", [](const Roi& r) {
        std::string s = "Roi([";
        for (std::size_t i = 0; i < r.size(); ++i)
          s += (i ? ", " : "") + boxRepr(r.boxes()[i]);
        return s + "])";
      });

  m.def(
      "pose_matrix",
      [](const py::handle& pose) { return poseMatrix(readPose(pose, "pose")); }, "pose"_a,
      "The 4x4 homogeneous matrix of a pose ((7,) or 4x4).");
  m.def(
      "pose_vector",
      [](const py::handle& pose) { return poseArray(readPose(pose, "pose")); }, "pose"_a,
      "The (7,) [x, y, z, qx, qy, qz, qw] of a pose ((7,) or 4x4), quaternion "
      "normalised.");
  m.def(
      "optical_from_body",
      [](const py::handle& T_W_C) {
        return poseArray(opticalFrame(readPose(T_W_C, "T_W_C")));
      },
      "T_W_C"_a,
      "The optical frame T_W_O (z forward, x right, y down: OpenCV, ROS *_optical_frame, "
      "TUM) of a camera whose body frame (x forward, y left, z up) is T_W_C.");
  m.def(
      "body_from_optical",
      [](const py::handle& T_W_O) {
        return poseArray(bodyFrame(readPose(T_W_O, "T_W_O")));
      },
      "T_W_O"_a, "The body frame T_W_C of a camera whose optical frame is T_W_O.");

  py::class_<CameraIntrinsics>(
      m, "CameraIntrinsics",
      "Pinhole intrinsics without distortion and the range limits of a depth camera. "
      "OpenCV's pixel convention: pixel (u, v) is column u, row v; pixel centres at "
      "integer coordinates.")
      .def(py::init([](std::uint32_t width, std::uint32_t height, double fx, double fy,
                       double cx, double cy, double min_range_m, double max_range_m) {
             CameraIntrinsics c = CameraIntrinsics::custom(width, height, fx, fy, cx, cy);
             c.min_range_m = min_range_m;
             c.max_range_m = max_range_m;
             c.validate();
             return c;
           }),
           "width"_a, "height"_a, "fx"_a, "fy"_a, "cx"_a, "cy"_a, "min_range_m"_a = 0.25,
           "max_range_m"_a = 9.0)
      .def_static(
          "l515",
          [](const std::string& mode) {
            if (mode == "1024x768")
              return CameraIntrinsics::l515(L515Mode::xga_1024x768);
            if (mode == "640x480")
              return CameraIntrinsics::l515(L515Mode::vga_640x480);
            if (mode == "320x240")
              return CameraIntrinsics::l515(L515Mode::qvga_320x240);
            throw InvalidArgumentError("mode: expected '1024x768', '640x480' or "
                                       "'320x240', got '" +
                                       mode + "'");
          },
          "mode"_a = "1024x768",
          "The Intel RealSense L515 (70 deg horizontal field of view, 0.25-9 m).")
      .def_static("parse", &parseCameraIntrinsics, "spec"_a,
                  "From 'l515', 'l515-640', 'l515-320' or 'WxH:fx,fy,cx,cy'.")
      .def_static(
          "from_matrix",
          [](const py::handle& K, std::uint32_t width, std::uint32_t height) {
            const auto k =
                py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(K);
            if (!k || k.ndim() != 2 || k.shape(0) != 3 || k.shape(1) != 3)
              throw py::value_error(badArgument("K", "a 3x3 camera matrix", K));
            return CameraIntrinsics::custom(width, height, k.at(0, 0), k.at(1, 1),
                                            k.at(0, 2), k.at(1, 2));
          },
          "K"_a, "width"_a, "height"_a,
          "From a 3x3 camera matrix (OpenCV's K, ROS CameraInfo.k).")
      .def_readwrite("width", &CameraIntrinsics::width)
      .def_readwrite("height", &CameraIntrinsics::height)
      .def_readwrite("fx", &CameraIntrinsics::fx)
      .def_readwrite("fy", &CameraIntrinsics::fy)
      .def_readwrite("cx", &CameraIntrinsics::cx)
      .def_readwrite("cy", &CameraIntrinsics::cy)
      .def_readwrite("min_range_m", &CameraIntrinsics::min_range_m)
      .def_readwrite("max_range_m", &CameraIntrinsics::max_range_m)
      .def_property_readonly(
          "K",
          [](const CameraIntrinsics& c) {
            py::array_t<double> K({3, 3});
            const double k[9] = {c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1};
            std::copy(k, k + 9, K.mutable_data());
            return K;
          },
          "The 3x3 camera matrix.")
      .def_property_readonly("horizontal_fov_rad", &CameraIntrinsics::horizontalFov)
      .def_property_readonly("vertical_fov_rad", &CameraIntrinsics::verticalFov)
      .def("validate", &CameraIntrinsics::validate,
           "Raises InvalidArgumentError naming the first bad field.")
      .def("__repr__", [](const CameraIntrinsics& c) {
        return "CameraIntrinsics(" + c.toString() + ")";
      });

  py::dict labels;
  for (PartLabel l :
       {PartLabel::unknown, PartLabel::stem, PartLabel::petiole, PartLabel::leaflet,
        PartLabel::peduncle, PartLabel::fruit, PartLabel::background, PartLabel::flower})
    labels[partLabelName(l)] = std::uint32_t(l);
  m.attr("PART_LABELS") = labels;

  py::class_<TriangleMesh, std::shared_ptr<TriangleMesh>>(
      m, "Mesh",
      "A triangle mesh: vertices (V, 3) float32 in metres (world frame, z up), triangles "
      "(F, 3) uint32, and optionally a part label per triangle (plantnbv.PART_LABELS). "
      "The properties are copies.")
      .def(py::init([](const py::handle& vertices, const py::handle& triangles,
                       const py::handle& labels) {
             auto mesh = std::make_shared<TriangleMesh>();
             mesh->vertices = readPointVector(vertices, "vertices");
             mesh->triangles = readTriangles(triangles, mesh->vertices.size());
             mesh->labels = readPartLabels(labels, "labels", mesh->triangles.size());
             mesh->validate();
             return mesh;
           }),
           "vertices"_a, "triangles"_a, "labels"_a = py::none())
      .def_property_readonly(
          "vertices", [](const TriangleMesh& mesh) { return pointsArray(mesh.vertices); })
      .def_property_readonly(
          "triangles",
          [](const TriangleMesh& mesh) {
            py::array_t<std::uint32_t> t({py::ssize_t(mesh.size()), py::ssize_t(3)});
            std::uint32_t* p = t.mutable_data();
            for (const auto& f : mesh.triangles)
              for (std::uint32_t i : f)
                *p++ = i;
            return t;
          })
      .def_property(
          "labels", [](const TriangleMesh& mesh) { return labelsArray(mesh.labels); },
          [](TriangleMesh& mesh, const py::handle& labels) {
            std::vector<PartLabel> l = readPartLabels(labels, "labels", mesh.size());
            Locked lock;
            mesh.labels = std::move(l);
          },
          "(F,) uint32 part labels, empty when the mesh has none.")
      .def_property_readonly(
          "node_names",
          [](const TriangleMesh& mesh) {
            py::list names;
            for (std::uint32_t id : mesh.node_ids)
              names.append(mesh.node_names[id]);
            return names;
          },
          "The scene-graph node name of every triangle (empty when the file gave none).")
      .def("__len__", &TriangleMesh::size, "The number of triangles.")
      .def(
          "bounds",
          [](const TriangleMesh& mesh) {
            Eigen::Vector3f min, max;
            mesh.bounds(min, max);
            return py::make_tuple(vectorArray(min.cast<double>()),
                                  vectorArray(max.cast<double>()));
          },
          "(min, max) of the vertices.")
      .def(
          "area",
          [](const TriangleMesh& mesh) {
            double area = 0;
            for (std::size_t t = 0; t < mesh.size(); ++t)
              area += mesh.triangleArea(t);
            return area;
          },
          "The surface area in square metres.")
      .def("__repr__", [](const TriangleMesh& mesh) {
        return "Mesh(" + std::to_string(mesh.vertices.size()) + " vertices, " +
               std::to_string(mesh.size()) + " triangles" +
               (mesh.hasLabels() ? ", labelled" : "") + ")";
      });
}

} // namespace python
} // namespace plantnbv
