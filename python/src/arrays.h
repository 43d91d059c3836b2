#pragma once
// NumPy arrays in and out of the library's types, with the one set of messages for a bad
// argument: "<argument>: expected <shape and dtype>, got <what came>". Conversions run
// with the GIL held; callers release it afterwards for the long work.

#include <cstdint>
#include <mutex>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <plantnbv/camera/depth_image.h>
#include <plantnbv/common/pcl_fwd.h>
#include <plantnbv/common/pose.h>
#include <plantnbv/common/triangle_mesh.h>

namespace plantnbv {
namespace python {

namespace py = pybind11;

/// Points: an (N, 3) float32 or float64 array of any strides (or a nested sequence of
/// numbers), read in place. Non-finite points are kept (the library ignores them).
/// \throws py::type_error for a non-numeric object, py::value_error for another shape.
void readPoints(const py::handle& points, const char* argument, CloudXYZ& cloud);
/// As readPoints, with one integer label per point (an (N,) array, values >= 0).
void readLabelledPoints(const py::handle& points, const py::handle& labels,
                        const char* argument, CloudXYZL& cloud);
std::vector<Eigen::Vector3f> readPointVector(const py::handle& points,
                                             const char* argument);
/// Part labels: an (N,) integer array of PartLabel values (0-7); None gives none.
std::vector<PartLabel> readPartLabels(const py::handle& labels, const char* argument,
                                      std::size_t expected_count);

/// A pose: a 4x4 homogeneous matrix (rigid, last row 0 0 0 1) or (7,) [x, y, z, qx, qy,
/// qz, qw] (ROS / TUM order; a quaternion within 1e-3 of unit norm).
Pose readPose(const py::handle& pose, const char* argument);
/// Poses: (K, 7) or (K, 4, 4).
std::vector<Pose> readPoses(const py::handle& poses, const char* argument);
Eigen::Vector3d readVector3(const py::handle& v, const char* argument);
/// An (H, W) depth image in metres, float32 or float64; NaN or 0 = no return.
DepthImage readDepth(const py::handle& depth, const char* argument);

py::array_t<float> pointsArray(const CloudXYZ& cloud);
py::array_t<float> pointsArray(const CloudXYZL& cloud);
py::array_t<float> pointsArray(const std::vector<Eigen::Vector3f>& points);
py::array_t<std::uint32_t> labelsArray(const CloudXYZL& cloud);
py::array_t<std::uint32_t> labelsArray(const std::vector<PartLabel>& labels);
py::array_t<float> depthImageArray(const DepthImage& depth); ///< (H, W) metres
/// (7,) [x, y, z, qx, qy, qz, qw].
py::array_t<double> poseArray(const Pose& pose);
py::array_t<double> poseArray(const std::vector<Pose>& poses); ///< (K, 7)
py::array_t<double> poseMatrix(const Pose& pose);              ///< 4x4
py::array_t<double> vectorArray(const Eigen::Vector3d& v);
template <typename T>
py::array_t<T> columnArray(const std::vector<T>& values)
{
  py::array_t<T> out(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

/// The one lock of the library objects Python holds: sessions, maps, sensors, metrics
/// evaluators, frames writers, and the plants and meshes that calls read with the GIL
/// released. The C++ classes are not thread-safe, and a call that released the GIL must
/// not meet another thread's call on the same object. Every call that releases the GIL
/// and touches such an object holds this lock, and so does every call that changes what
/// those calls read or reads what they change. Calls that work on objects of their own
/// (metrics(), read_cloud(), a trial once its plant is copied) release the GIL without
/// it and run in parallel. Recursive: a locked call may call another.
std::recursive_mutex& libraryMutex();

/// Releases the GIL, then takes libraryMutex(); gives it back before the GIL.
class ReleasedAndLocked {
  py::gil_scoped_release release_;
  std::lock_guard<std::recursive_mutex> lock_{libraryMutex()};
};
/// libraryMutex() with the GIL held, for short calls that build Python results.
class Locked {
  std::lock_guard<std::recursive_mutex> lock_{libraryMutex()};
};

/// The message head "<argument>: expected <expected>, got <description of `value`>".
std::string badArgument(const char* argument, const std::string& expected,
                        const py::handle& value);

} // namespace python
} // namespace plantnbv
