// Plants (generated, from mesh files, from scans), their ROIs and anatomy, placed plants,
// and the simulated depth camera.

#include <cmath>
#include <filesystem>
#include <optional>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <variant>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/camera/optical_frame.h>
#include <plantnbv/common/error.h>
#include <plantnbv/experiment/plant_scene.h>
#include <plantnbv/plant/anatomy_json.h>
#include <plantnbv/plant/plant_model.h>
#include <plantnbv/plant/plant_rois.h>
#include <plantnbv/plant/tomato_plant_generator.h>
#include <plantnbv/scenario/placed_plant.h>
#include <plantnbv/sensor/simulated_depth_sensor.h>

#include "arrays.h"
#include "bindings.h"

namespace plantnbv {
namespace python {

namespace {

using namespace pybind11::literals;
using scenario::PlacedPlant;
using scenario::PlantSource;

RoiKind roiKindOf(const std::string& name)
{
  const std::optional<RoiKind> kind = roiKindFromName(name);
  if (!kind)
    throw InvalidArgumentError("kind: expected one of " + roiKindNames() + ", got '" +
                               name + "'");
  return *kind;
}

bool isNumberList(py::handle value)
{
  if (!py::isinstance<py::list>(value))
    return false;
  for (py::handle item : py::reinterpret_borrow<py::list>(value))
    if (!py::isinstance<py::float_>(item) && !py::isinstance<py::int_>(item))
      return false;
  return py::len(value) > 0;
}

/// JSON lists of numbers and of points become float64 arrays; the rest is kept.
py::object withArrays(py::handle value)
{
  if (py::isinstance<py::dict>(value)) {
    py::dict out;
    for (auto item : py::reinterpret_borrow<py::dict>(value))
      out[item.first] = withArrays(item.second);
    return std::move(out);
  }
  if (!py::isinstance<py::list>(value) || py::len(value) == 0)
    return py::reinterpret_borrow<py::object>(value);
  const py::list list = py::reinterpret_borrow<py::list>(value);
  bool points = true;
  for (py::handle item : list)
    points = points && isNumberList(item);
  if (points || isNumberList(value))
    return py::module_::import("numpy").attr("asarray")(list, "dtype"_a = "float64");
  py::list out;
  for (py::handle item : list)
    out.append(withArrays(item));
  return std::move(out);
}

/// The anatomy as dicts of NumPy arrays, through the one schema of anatomy_json.h.
py::object anatomyDict(const Plant& plant)
{
  return withArrays(py::module_::import("json").attr("loads")(anatomyToJson(plant)));
}

void bindPlant(py::module_& m)
{
  py::class_<Plant, std::shared_ptr<Plant>>(
      m, "Plant",
      "A plant with ground truth: its mesh (a part label per triangle) or scanned "
      "points, "
      "its anatomy, and the pose it is in (world frame once placed).")
      .def_property(
          "name", [](const Plant& p) { return p.name; },
          [](Plant& p, std::string name) {
            Locked lock;
            p.name = std::move(name);
          })
      .def_property_readonly(
          "mesh", [](const Plant& p) { return std::make_shared<TriangleMesh>(p.mesh); },
          "A copy of the mesh (empty for a scan).")
      .def_property_readonly(
          "scan_points", [](const Plant& p) { return pointsArray(p.scan_points); },
          "(N, 3) float32; empty for a mesh plant.")
      .def_property_readonly("scan_labels",
                             [](const Plant& p) { return labelsArray(p.scan_labels); })
      .def_property_readonly("base_position",
                             [](const Plant& p) { return vectorArray(p.base_position); })
      .def_readonly("yaw_rad", &Plant::yaw_rad)
      .def_property_readonly("leaf_node_count", &Plant::leafNodeCount)
      .def_property_readonly(
          "anatomy", &anatomyDict,
          "The anatomy (stem axis, leaves and their nodes, trusses and "
          "fruits) as dicts of arrays, keys as in anatomy.json.")
      .def("anatomy_json", &anatomyToJson, "The anatomy as anatomy.json's text.")
      .def(
          "place",
          [](Plant& p, const py::handle& base, double yaw_deg) {
            const Eigen::Vector3d b = readVector3(base, "base");
            Locked lock;
            posePlant(p, b, yaw_deg * M_PI / 180.0);
          },
          "base"_a = std::vector<double>{1.0, 0.0, 0.8}, "yaw_deg"_a = 0.0,
          "Puts the stem base at `base` (world, metres) turned by yaw_deg about the stem "
          "(absolute: placing again first undoes the pose). The paper's base is "
          "(1.0, 0, 0.8).")
      .def(
          "roi",
          [](const Plant& p, const std::string& kind) {
            return plantRoi(p, roiKindOf(kind));
          },
          "kind"_a,
          "The paper's ROI of a kind: 'whole_plant', 'main_stem', 'leaf_nodes', 'fruit'.")
      .def(
          "leaf_node_roi",
          [](const Plant& p, std::optional<std::vector<int>> indices,
             const py::handle& size) {
            return leafNodeRoi(p, indices ? *indices : defaultLeafNodeIndices(p),
                               readVector3(size, "size"));
          },
          "indices"_a = py::none(), "size"_a = std::vector<double>{0.03, 0.03, 0.05},
          "Boxes at the chosen leaf nodes (default: the paper's low, middle, high).")
      .def("fruit_roi", &fruitRoi, "margin_m"_a = 0.0, "One box per truss of fruit.")
      .def("bounding_box_roi", &boundingBoxRoi)
      .def("__repr__", [](const Plant& p) {
        return "Plant('" + p.name + "', " + std::to_string(p.mesh.size()) +
               " triangles, " + std::to_string(p.scan_points.size()) + " scan points, " +
               std::to_string(p.leafNodeCount()) + " leaf nodes)";
      });

  m.def(
      "generate_plant",
      [](std::uint64_t seed, double growth_stage, double variation,
         double divergence_angle_deg, bool simplified, double mesh_detail) {
        TomatoPlantGenerator::Config c;
        c.seed = seed;
        c.growth_stage = growth_stage;
        c.variation = variation;
        c.divergence_angle_rad = divergence_angle_deg * M_PI / 180.0;
        c.simplified = simplified;
        c.mesh_detail = mesh_detail;
        const TomatoPlantGenerator generator(c);
        py::gil_scoped_release release;
        return std::make_shared<Plant>(generator.generate());
      },
      "seed"_a = 0, "growth_stage"_a = 0.5, "variation"_a = 1.0,
      "divergence_angle_deg"_a = 137.5, "simplified"_a = false, "mesh_detail"_a = 1.0,
      "A procedural tomato plant with part labels and anatomy, in the plant frame (base "
      "at the origin, z up); the same arguments give the same plant on every machine.");
  m.def(
      "default_plant",
      [](int index, bool simplified) {
        const TomatoPlantGenerator generator(defaultPlantConfig(index, simplified));
        py::gil_scoped_release release;
        return std::make_shared<Plant>(generator.generate());
      },
      "index"_a, "simplified"_a = false,
      "Plant `index` (0-9) of the default set (seed = index, growth stage = index / 9), "
      "in the plant frame.");
  m.def(
      "plant_from_mesh",
      [](const TriangleMesh& mesh, const std::string& name, bool keep_frame) {
        return std::make_shared<Plant>(plantFromMesh(mesh, name, keep_frame));
      },
      "mesh"_a, "name"_a = "model", "keep_frame"_a = false,
      "A plant from a mesh: its bounding box's bottom-face centre becomes the base "
      "(keep_frame: the coordinates are kept). Only the stem axis of the anatomy is "
      "known.");
  m.def(
      "plant_from_scan",
      [](const py::handle& points, const py::handle& labels, const std::string& name,
         bool keep_frame) {
        std::vector<Eigen::Vector3f> p = readPointVector(points, "points");
        std::vector<PartLabel> l = readPartLabels(labels, "labels", p.size());
        return std::make_shared<Plant>(
            plantFromScan(std::move(p), std::move(l), name, keep_frame));
      },
      "points"_a, "labels"_a = py::none(), "name"_a = "scan", "keep_frame"_a = false,
      "A plant from a scanned cloud (finite points), placed as plant_from_mesh; the "
      "camera sees it as surfels.");

  py::class_<PlacedPlant, std::shared_ptr<PlacedPlant>>(
      m, "PlacedPlant",
      "A plant placed in the world as trials place it, with its ROIs by level name.")
      .def_property_readonly("plant",
                             [](const std::shared_ptr<PlacedPlant>& p) {
                               return std::shared_ptr<Plant>(
                                   p, &p->plant); // shares the placed plant
                             })
      .def_property_readonly(
          "rois",
          [](const PlacedPlant& p) {
            py::dict d;
            for (const auto& [kind, roi] : p.rois)
              d[roiKindName(kind)] = roi;
            if (!p.model_rois.empty())
              d["model_rois"] = p.model_rois;
            return d;
          },
          "{level name: Roi}: every kind of a generated plant (fruit when it has "
          "fruit); whole_plant for a model; model_rois for a model's ROI file.")
      .def_readonly("description", &PlacedPlant::description)
      .def_readonly("warnings", &PlacedPlant::warnings,
                    "What place_plant warned about (UserWarning), e.g. a label rule "
                    "that labelled nothing.")
      .def("__repr__", [](const PlacedPlant& p) {
        return "PlacedPlant('" + p.plant.name + "', " + p.description + ")";
      });
  m.def(
      "place_plant",
      [](std::optional<std::uint64_t> seed, std::optional<double> stage, bool simplified,
         const std::variant<std::string, std::vector<std::string>>& model,
         const std::string& labels, double scale, const std::string& up_axis,
         const std::string& rois, bool keep_frame, double yaw_deg,
         const py::handle& base) {
        PlantSource source;
        source.seed = seed;
        source.stage = stage;
        source.simplified = simplified;
        if (const auto* files = std::get_if<std::vector<std::string>>(&model)) {
          if (!files->empty()) { // a plant split into several mesh files
            source.model = files->front();
            source.model_parts.assign(files->begin() + 1, files->end());
          }
        } else {
          source.model = std::get<std::string>(model);
        }
        source.labels = labels;
        source.scale = scale;
        source.up_axis = io::upAxisFromName(up_axis);
        source.rois = rois;
        source.keep_frame = keep_frame;
        source.yaw_deg = yaw_deg;
        source.base = readVector3(base, "base");
        std::shared_ptr<PlacedPlant> placed;
        {
          py::gil_scoped_release release;
          placed = std::make_shared<PlacedPlant>(scenario::makePlacedPlant(source));
        }
        for (const std::string& w : placed->warnings) // as the tool prints them
          if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0)
            throw py::error_already_set(); // warnings turned into errors
        return placed;
      },
      py::kw_only(), "seed"_a = py::none(), "stage"_a = py::none(),
      "simplified"_a = false, "model"_a = "", "labels"_a = "", "scale"_a = 0.0,
      "up_axis"_a = "file", "rois"_a = "", "keep_frame"_a = false, "yaw_deg"_a = 0.0,
      "base"_a = std::vector<double>{1.0, 0.0, 0.8},
      "The plant of `plantnbv reconstruct --plant/--model`: a generated tomato plant "
      "(seed, optional growth stage) or a model file (mesh or scanned cloud, with part "
      "label rules `labels` on node, geometry or material names, metres per file unit "
      "`scale` (0: the file's), the file's up axis `up_axis` ('file': Collada's "
      "<up_axis>, VRML y, other formats z; or 'y', 'z'), and an ROI file `rois`; a list "
      "of mesh files for a "
      "plant split into several, as --model repeated), placed at `base` turned by "
      "yaw_deg (within +-360 degrees). A label rule that labels nothing, a Collada "
      "file without <unit> and an ROI box that misses the plant are UserWarnings.");
}

py::dict captureDict(const CloudXYZL& cloud, const DepthImage& depth, const Pose& T_W_C)
{
  const py::ssize_t h = depth.height, w = depth.width;
  py::array_t<std::uint32_t> labels = labelsArray(cloud);
  return py::dict("depth"_a = depthImageArray(depth),
                  "points"_a = pointsArray(cloud).reshape({h, w, py::ssize_t(3)}),
                  "labels"_a = labels.reshape({h, w}), "T_W_C"_a = poseArray(T_W_C),
                  "T_W_O"_a = poseArray(opticalFrame(T_W_C)));
}

void bindSensor(py::module_& m)
{
  py::class_<SimulatedDepthSensor>(
      m, "SimulatedDepthSensor",
      "A simulated depth camera (Embree ray casting): renders a plant on its support "
      "over a floor from a pose, giving depth, world points and part labels per pixel.")
      .def(py::init<const CameraIntrinsics&>(),
           "intrinsics"_a = CameraIntrinsics::l515(L515Mode::vga_640x480))
      .def_property("intrinsics", &SimulatedDepthSensor::getIntrinsics,
                    [](SimulatedDepthSensor& s, const CameraIntrinsics& c) {
                      Locked lock;
                      s.setIntrinsics(c);
                    })
      .def(
          "set_plant",
          [](SimulatedDepthSensor& s, const Plant& plant, bool floor, bool support) {
            PlantSceneConfig config;
            config.floor = floor;
            config.support = support;
            ReleasedAndLocked lock; // reads the plant, changes the sensor
            s.setScene(makePlantScene(plant, config));
          },
          "plant"_a, "floor"_a = true, "support"_a = true,
          "The scene: the plant (mesh, or scan as surfels) and, as trials have them, the "
          "floor at z = 0 and a support under the base.")
      .def(
          "set_noise",
          [](SimulatedDepthSensor& s, bool enabled, std::uint64_t seed) {
            Locked lock;
            NoiseConfig noise;
            noise.enabled = enabled;
            noise.seed = seed;
            s.setNoise(noise);
          },
          "enabled"_a = true, "seed"_a = 0,
          "The L515 noise model (axial and lateral noise, grazing and edge dropouts).")
      .def(
          "capture",
          [](SimulatedDepthSensor& s, const py::handle& T_W_C, const py::handle& T_W_O) {
            if (T_W_C.is_none() == T_W_O.is_none())
              throw py::type_error(
                  "capture: give the camera's pose as T_W_C (body frame) "
                  "or T_W_O (optical frame), one of them");
            const Pose body = T_W_C.is_none() ? bodyFrame(readPose(T_W_O, "T_W_O"))
                                              : readPose(T_W_C, "T_W_C");
            CloudXYZL cloud;
            DepthImage depth;
            {
              ReleasedAndLocked lock;
              s.capture(body, cloud, &depth);
            }
            return captureDict(cloud, depth, body);
          },
          "T_W_C"_a = py::none(), "T_W_O"_a = py::none(),
          "One frame from the camera at body pose T_W_C (x forward, y left, z up) or "
          "optical pose T_W_O: {'depth': (H, W) float32 metres (NaN: no return), "
          "'points': (H, W, 3) float32 world, 'labels': (H, W) uint32 part labels, "
          "'T_W_C', 'T_W_O': (7,)}.");
}

} // namespace

void bindPlants(py::module_& m)
{
  bindPlant(m);
  bindSensor(m);
}

} // namespace python
} // namespace plantnbv
