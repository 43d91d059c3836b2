// Metrics, filters, mesh sampling, and the files: clouds, meshes, ROIs, depth images,
// frames folders.

#include <filesystem>
#include <optional>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/camera/depth_image.h>
#include <plantnbv/common/error.h>
#include <plantnbv/filters/roi_crop.h>
#include <plantnbv/filters/voxel_grid_filter.h>
#include <plantnbv/io/cloud_io.h>
#include <plantnbv/io/depth_image_io.h>
#include <plantnbv/io/frames_folder.h>
#include <plantnbv/io/mesh_io.h>
#include <plantnbv/io/roi_io.h>
#include <plantnbv/metrics/reconstruction_metrics.h>
#include <plantnbv/sampling/mesh_sampler.h>
#include <plantnbv/scenario/geometry_input.h>

#include "arrays.h"
#include "bindings.h"

namespace plantnbv {
namespace python {

namespace {

using namespace pybind11::literals;
using Path = std::filesystem::path;

py::dict metricsDict(const MetricsResult& r)
{
  return py::dict(
      "chamfer"_a = r.chamfer, "precision"_a = r.precision, "recall"_a = r.recall,
      "f1"_a = r.f1,
      "mean_dist_reconstruction_to_reference"_a = r.mean_dist_reconstruction_to_reference,
      "mean_dist_reference_to_reconstruction"_a = r.mean_dist_reference_to_reconstruction,
      "rho"_a = r.rho, "reference_points"_a = r.reference_points,
      "reconstruction_points"_a = r.reconstruction_points, "valid"_a = r.valid);
}

CloudXYZConstPtr cloudOf(const py::handle& points, const char* argument)
{
  auto cloud = std::make_shared<CloudXYZ>();
  readPoints(points, argument, *cloud);
  return cloud;
}

/// ReconstructionMetrics with the reference's tree kept: many reconstructions against
/// one ground truth.
class MetricsEvaluator {
public:
  MetricsEvaluator(const py::handle& reference, double rho, int threads,
                   bool reuse_distances)
  {
    metrics_.setNumberOfThreads(threads);
    metrics_.setThreshold(rho);
    metrics_.setReuseDistances(reuse_distances);
    setReference(reference);
  }
  void setReference(const py::handle& reference)
  {
    const CloudXYZConstPtr cloud = cloudOf(reference, "reference");
    ReleasedAndLocked lock;
    metrics_.setReference(cloud);
  }
  MetricsResult compute(const py::handle& reconstruction)
  {
    const CloudXYZConstPtr cloud = cloudOf(reconstruction, "reconstruction");
    ReleasedAndLocked lock;
    metrics_.setReconstruction(cloud);
    return metrics_.compute();
  }
  py::tuple distances(const py::handle& reconstruction)
  {
    const CloudXYZConstPtr cloud = cloudOf(reconstruction, "reconstruction");
    std::vector<double> r_to_t, t_to_r;
    {
      ReleasedAndLocked lock;
      metrics_.setReconstruction(cloud);
      metrics_.computeDistances(r_to_t, t_to_r);
    }
    return py::make_tuple(columnArray(r_to_t), columnArray(t_to_r));
  }
  bool reuseDistances() const { return metrics_.getReuseDistances(); }
  void setReuseDistances(bool reuse)
  {
    Locked lock;
    metrics_.setReuseDistances(reuse);
  }
  double rho() const { return metrics_.getThreshold(); }
  void setRho(double rho)
  {
    Locked lock;
    metrics_.setThreshold(rho);
  }

private:
  ReconstructionMetrics metrics_;
};

/// Points, or (points, labels) when labels were given.
py::object pointsOut(const CloudXYZL& cloud, bool with_labels)
{
  if (with_labels)
    return py::make_tuple(pointsArray(cloud), labelsArray(cloud));
  return pointsArray(cloud);
}

} // namespace

void bindClouds(py::module_& m)
{
  py::class_<MetricsResult>(m, "MetricsResult",
                            "Chamfer distance and precision / recall / F1 at rho of a "
                            "reconstruction R against a reference T (metres).")
      .def_readonly("chamfer", &MetricsResult::chamfer,
                    "The sum of the two directional means.")
      .def_readonly("precision", &MetricsResult::precision,
                    "Share of R closer than rho to T (strict <).")
      .def_readonly("recall", &MetricsResult::recall,
                    "Share of T closer than rho to R (strict <).")
      .def_readonly("f1", &MetricsResult::f1)
      .def_readonly("mean_dist_reconstruction_to_reference",
                    &MetricsResult::mean_dist_reconstruction_to_reference)
      .def_readonly("mean_dist_reference_to_reconstruction",
                    &MetricsResult::mean_dist_reference_to_reconstruction)
      .def_readonly("rho", &MetricsResult::rho)
      .def_readonly("reference_points", &MetricsResult::reference_points,
                    "Finite points of T.")
      .def_readonly("reconstruction_points", &MetricsResult::reconstruction_points,
                    "Finite points of R.")
      .def_readonly("valid", &MetricsResult::valid,
                    "False when a cloud has no finite point (then P = R = F1 = 0 and the "
                    "distances are inf).")
      .def("to_dict", &metricsDict)
      .def("__repr__", [](const MetricsResult& r) {
        return "MetricsResult(chamfer=" + std::to_string(r.chamfer) +
               ", precision=" + std::to_string(r.precision) +
               ", recall=" + std::to_string(r.recall) + ", f1=" + std::to_string(r.f1) +
               ", rho=" + std::to_string(r.rho) + ")";
      });

  m.def(
      "metrics",
      [](const py::handle& reference, const py::handle& reconstruction, double rho,
         int threads) {
        // Objects of its own: runs beside other threads' calls.
        const CloudXYZConstPtr t = cloudOf(reference, "reference");
        const CloudXYZConstPtr r = cloudOf(reconstruction, "reconstruction");
        py::gil_scoped_release release;
        ReconstructionMetrics metrics;
        metrics.setNumberOfThreads(threads);
        metrics.setThreshold(rho);
        metrics.setReference(t);
        metrics.setReconstruction(r);
        return metrics.compute();
      },
      "reference"_a, "reconstruction"_a, "rho"_a = 0.003, "threads"_a = 0,
      "Chamfer distance and precision / recall / F1 at rho (metres, strict <) of the "
      "reconstruction against the reference, both (N, 3) float32 or float64 arrays; "
      "non-finite points are ignored. Exact nearest-neighbour distances; the result does "
      "not depend on `threads` (0: all cores).");

  py::class_<MetricsEvaluator>(
      m, "ReconstructionMetrics",
      "Metrics of many reconstructions against one reference, whose search tree is "
      "built once.")
      .def(py::init<const py::handle&, double, int, bool>(), "reference"_a,
           "rho"_a = 0.003, "threads"_a = 0, "reuse_distances"_a = false)
      .def("set_reference", &MetricsEvaluator::setReference, "reference"_a)
      .def_property("rho", &MetricsEvaluator::rho, &MetricsEvaluator::setRho,
                    "The precision / recall threshold (metres, > 0).")
      .def_property("reuse_distances", &MetricsEvaluator::reuseDistances,
                    &MetricsEvaluator::setReuseDistances,
                    "Whether compute() keeps the distances it found, so that the next "
                    "compute() searches only what changed (a reconstruction that grows "
                    "view by view); the same results either way.")
      .def("compute", &MetricsEvaluator::compute, "reconstruction"_a,
           "The MetricsResult of this reconstruction.")
      .def("distances", &MetricsEvaluator::distances, "reconstruction"_a,
           "(reconstruction_to_reference, reference_to_reconstruction): each point's "
           "distance to the nearest point of the other cloud, in point order (NaN for "
           "non-finite points).");

  m.def(
      "views_to_reach",
      [](const std::vector<double>& curve, double tau) -> std::optional<int> {
        const int v = viewsToReach(curve, tau);
        return v < 0 ? std::nullopt : std::optional<int>(v);
      },
      "curve"_a, "tau"_a,
      "The number of views after which a metric curve (value after view 1, 2, ...) "
      "first reaches tau, or None.");

  m.def(
      "voxel_grid",
      [](const py::handle& points, double leaf_m, bool centres,
         const py::handle& labels) {
        VoxelGridFilter<pcl::PointXYZL> filter;
        filter.setLeafSize(leaf_m);
        filter.setOutputVoxelCentres(centres);
        auto cloud = std::make_shared<CloudXYZL>();
        readLabelledPoints(points, labels, "points", *cloud);
        CloudXYZL out;
        {
          py::gil_scoped_release release;
          filter.setInputCloud(cloud);
          filter.filter(out);
        }
        return pointsOut(out, !labels.is_none());
      },
      "points"_a, "leaf_m"_a = 0.003, "centres"_a = true, "labels"_a = py::none(),
      "One point per occupied voxel of a grid aligned with the world origin (OctoMap's "
      "lattice): the voxel centre, as trials and `plantnbv sample --voxel` make ground "
      "truth, or with centres=False the centroid of its points (`--centroids`). With "
      "labels, returns (points, labels), each voxel taking its most frequent label.");

  m.def(
      "crop_to_roi",
      [](const py::handle& points, const Roi& roi, const py::handle& labels,
         bool negative) {
        auto cloud = std::make_shared<CloudXYZL>();
        readLabelledPoints(points, labels, "points", *cloud);
        RoiCrop<pcl::PointXYZL> crop;
        crop.setRoi(roi);
        crop.setNegative(negative);
        crop.setInputCloud(cloud);
        CloudXYZL out;
        crop.filter(out);
        return pointsOut(out, !labels.is_none());
      },
      "points"_a, "roi"_a, "labels"_a = py::none(), "negative"_a = false,
      "The finite points inside any box of the ROI (negative=True: outside every box), "
      "in "
      "input order; with labels, (points, labels).");

  m.def(
      "sample_mesh",
      [](std::shared_ptr<TriangleMesh> mesh, std::size_t n, std::uint64_t seed,
         bool return_labels) {
        MeshSampler sampler;
        CloudXYZL cloud;
        {
          ReleasedAndLocked lock; // reads the mesh
          sampler.setInputMesh(mesh);
          sampler.setNumberOfPoints(n);
          sampler.setSeed(seed);
          sampler.sample(cloud);
        }
        return pointsOut(cloud, return_labels);
      },
      "mesh"_a, "n"_a = 100000, "seed"_a = 0, "return_labels"_a = false,
      "n points drawn uniformly over the mesh's surface (area-weighted), reproducible "
      "from the seed; with return_labels, (points, labels of their triangles).");
  m.def("ground_truth_sample_count", &groundTruthSampleCount, "area_m2"_a,
        "resolution_m"_a,
        "The surface samples that give ground truth at a voxel size (8 per voxel face).");

  m.def(
      "read_cloud",
      [](const Path& path, bool return_labels) {
        CloudXYZL cloud;
        {
          py::gil_scoped_release release;
          io::loadCloud(path.string(), cloud);
        }
        return pointsOut(cloud, return_labels);
      },
      "path"_a, "return_labels"_a = false,
      "The points of a .pcd or .ply file as (N, 3) float32 (organized clouds row by row, "
      "NaN where a pixel has no point); with return_labels, (points, labels).");
  m.def(
      "write_cloud",
      [](const Path& path, const py::handle& points, const py::handle& labels,
         bool binary) {
        // x y z only without labels, x y z label with them: each read once.
        auto write = [&](auto& cloud) {
          py::gil_scoped_release release;
          io::saveCloud(path.string(), cloud, binary);
        };
        if (labels.is_none()) {
          CloudXYZ cloud;
          readPoints(points, "points", cloud);
          write(cloud);
        } else {
          CloudXYZL cloud;
          readLabelledPoints(points, labels, "points", cloud);
          write(cloud);
        }
      },
      "path"_a, "points"_a, "labels"_a = py::none(), "binary"_a = true,
      "Writes a .pcd or .ply cloud (x y z float, and label uint when labels are given) "
      "that read_cloud and PCL read back exactly.");
  m.def(
      "read_geometry",
      [](const Path& path, double resolution_m, std::size_t mesh_points,
         std::uint64_t seed) {
        CloudXYZ cloud;
        std::string summary;
        {
          py::gil_scoped_release release;
          scenario::loadGeometryAsCloud(
              path.string(), "path", {resolution_m, mesh_points, seed}, cloud, summary);
        }
        return pointsArray(cloud);
      },
      "path"_a, "resolution_m"_a = 0.003, "mesh_points"_a = 0, "seed"_a = 0,
      "Any geometry file as (N, 3) float32 points, as `plantnbv eval` reads its inputs: "
      "a "
      "cloud's finite points; a mesh sampled (mesh_points, 0: automatic; seeded) and "
      "reduced to the centres of the voxels of resolution_m it falls in (the ground "
      "truth of trials); an octree's occupied voxel centres.");
  m.def(
      "read_mesh",
      [](const Path& path, const std::string& up_axis, double scale) {
        io::MeshLoadOptions options;
        options.up_axis = io::upAxisFromName(up_axis);
        options.scale = scale;
        py::gil_scoped_release release;
        return std::make_shared<TriangleMesh>(io::loadMesh(path.string(), options));
      },
      "path"_a, "up_axis"_a = "file", "scale"_a = 0.0,
      "A mesh (.ply .obj .stl .dae .wrl) in metres, z up: up_axis 'file' honours "
      "Collada's <up_axis> (VRML: y), or 'y' / 'z'; scale (metres per unit) replaces the "
      "file's unit when not 0.");
  m.def(
      "write_mesh",
      [](const Path& path, const TriangleMesh& mesh) {
        ReleasedAndLocked lock; // reads the mesh
        io::saveMeshPly(path.string(), mesh);
      },
      "path"_a, "mesh"_a, "Writes a binary PLY with a per-face label.");
  m.def(
      "read_roi", [](const Path& path) { return io::loadRoi(path.string()); }, "path"_a,
      "An ROI file (YAML: boxes with center, size, name).");
  m.def(
      "write_roi",
      [](const Path& path, const Roi& roi) { io::saveRoi(path.string(), roi); }, "path"_a,
      "roi"_a, "Writes an ROI file that read_roi reads back exactly.");
  m.def(
      "read_depth_png",
      [](const Path& path, double units_per_m) {
        DepthImage depth;
        {
          py::gil_scoped_release release;
          io::loadDepthPng(path.string(), depth, units_per_m);
        }
        return depthImageArray(depth);
      },
      "path"_a, "units_per_m"_a = 1000.0,
      "A 16-bit depth PNG as (H, W) float32 metres, NaN where it holds 0.");
  m.def(
      "write_depth_png",
      [](const Path& path, const py::handle& depth, double units_per_m) {
        const DepthImage d = readDepth(depth, "depth");
        py::gil_scoped_release release;
        io::saveDepthPng(path.string(), d.width, d.height, d.depth_m, units_per_m);
      },
      "path"_a, "depth"_a, "units_per_m"_a = 1000.0,
      "Writes (H, W) metres as a 16-bit PNG, rounded to 1 / units_per_m m; NaN -> 0.");
  m.def(
      "depth_to_points",
      [](const py::handle& depth, const CameraIntrinsics& intrinsics,
         const py::handle& T_W_O) {
        const DepthImage d = readDepth(depth, "depth");
        const Pose pose = readPose(T_W_O, "T_W_O");
        CloudXYZ cloud;
        {
          py::gil_scoped_release release;
          depthToCloud(d, intrinsics, pose, cloud);
        }
        return pointsArray(cloud).reshape(
            {py::ssize_t(d.height), py::ssize_t(d.width), py::ssize_t(3)});
      },
      "depth"_a, "intrinsics"_a, "T_W_O"_a,
      "Back-projects a depth image (metres: z in the optical frame) into the world "
      "frame: an (H, W, 3) float32 array, NaN where the depth is not > 0.");

  py::class_<io::FramesFolder>(
      m, "FramesFolder",
      "A frames folder (docs/real-robot.md: camera.yaml, depth.txt, groundtruth.txt, "
      "depth/*.png), each depth frame with the pose of the nearest timestamp.")
      .def(py::init([](const Path& path, double max_pose_dt_s, bool skip_unmatched,
                       double depth_scale) {
             io::FramesFolderOptions options;
             options.max_pose_dt_s = max_pose_dt_s;
             options.skip_unmatched = skip_unmatched;
             options.depth_scale = depth_scale;
             return io::FramesFolder(path.string(), options);
           }),
           "path"_a, "max_pose_dt_s"_a = 0.02, "skip_unmatched"_a = false,
           "depth_scale"_a = 0.0)
      .def_property_readonly(
          "intrinsics", [](const io::FramesFolder& f) { return f.camera().intrinsics; })
      .def_property_readonly(
          "depth_scale", [](const io::FramesFolder& f) { return f.camera().depth_scale; },
          "Depth units per metre of the PNGs.")
      .def("__len__", [](const io::FramesFolder& f) { return f.frames().size(); })
      .def_property_readonly("skipped", &io::FramesFolder::skippedFrames)
      .def_property_readonly("stamps",
                             [](const io::FramesFolder& f) {
                               std::vector<double> s;
                               for (const io::FrameRecord& r : f.frames())
                                 s.push_back(r.stamp_s);
                               return columnArray(s);
                             })
      .def_property_readonly(
          "poses",
          [](const io::FramesFolder& f) {
            std::vector<Pose> poses;
            for (const io::FrameRecord& r : f.frames())
              poses.push_back(r.T_W_O);
            return poseArray(poses);
          },
          "(K, 7) optical poses T_W_O [x, y, z, qx, qy, qz, qw].")
      .def(
          "depth",
          [](const io::FramesFolder& f, std::size_t i) {
            if (i >= f.frames().size())
              throw py::index_error("frame " + std::to_string(i) + " of " +
                                    std::to_string(f.frames().size()));
            DepthImage depth;
            {
              py::gil_scoped_release release;
              f.loadDepth(i, depth);
            }
            return depthImageArray(depth);
          },
          "i"_a, "Frame i's depth image, (H, W) float32 metres (NaN: no return).");

  py::class_<io::FramesFolderWriter>(
      m, "FramesFolderWriter",
      "Appends frames to a frames folder (creating it, or continuing one of the same "
      "camera).")
      .def(py::init([](const Path& path, const CameraIntrinsics& intrinsics,
                       double depth_scale) {
             io::CameraInfo info;
             info.intrinsics = intrinsics;
             info.depth_scale = depth_scale;
             return io::FramesFolderWriter(path.string(), info);
           }),
           "path"_a, "intrinsics"_a, "depth_scale"_a = 1000.0)
      .def("__len__", &io::FramesFolderWriter::frameCount)
      .def(
          "append",
          [](io::FramesFolderWriter& w, const py::handle& depth, const py::handle& T_W_O,
             double stamp_s) {
            const DepthImage d = readDepth(depth, "depth");
            const Pose pose = readPose(T_W_O, "T_W_O");
            ReleasedAndLocked lock;
            w.append(d, pose, stamp_s);
          },
          "depth"_a, "T_W_O"_a, "stamp_s"_a,
          "Writes depth/NNNNNN.png and appends its lines to depth.txt and "
          "groundtruth.txt.");
}

} // namespace python
} // namespace plantnbv
