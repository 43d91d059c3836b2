#include "arrays.h"

#include <cmath>
#include <sstream>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>

namespace plantnbv {
namespace python {

namespace {

using namespace pybind11::literals;

std::string describe(const py::handle& value)
{
  if (py::isinstance<py::array>(value)) {
    const auto a = py::reinterpret_borrow<py::array>(value);
    std::ostringstream s;
    s << "a " << py::str(a.dtype()).cast<std::string>() << " array of shape (";
    for (py::ssize_t d = 0; d < a.ndim(); ++d)
      s << (d ? ", " : "") << a.shape(d);
    s << (a.ndim() == 1 ? ",)" : ")");
    return s.str();
  }
  return "'" + py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>() +
         "'";
}

/// `value` as an array: arrays as they are, anything else through numpy.asarray (with
/// `dtype`, if given); objects NumPy cannot make numbers of are a TypeError.
py::array asArray(const py::handle& value, const char* argument,
                  const std::string& expected, const char* dtype = nullptr)
{
  if (py::isinstance<py::array>(value))
    return py::reinterpret_borrow<py::array>(value);
  if (value.is_none() || py::isinstance<py::str>(value) ||
      py::isinstance<py::bytes>(value))
    throw py::type_error(badArgument(argument, expected, value));
  try {
    py::object numpy = py::module_::import("numpy");
    py::array a = dtype ? numpy.attr("asarray")(value, "dtype"_a = dtype)
                        : numpy.attr("asarray")(value);
    if (a.dtype().kind() == 'O' || a.dtype().kind() == 'U' || a.dtype().kind() == 'S')
      throw py::type_error(badArgument(argument, expected, value));
    return a;
  } catch (py::error_already_set&) {
    throw py::type_error(badArgument(argument, expected, value));
  }
}

bool isFloat(const py::array& a)
{
  return a.dtype().kind() == 'f' && (a.itemsize() == 4 || a.itemsize() == 8);
}

/// Calls emit(i, x, y, z) for every row of an (N, 3) float array, reading it in place.
/// The rows of an (N, 3) float array. \throws py::value_error otherwise.
std::size_t rowCount3(const py::array& a, const char* argument,
                      const std::string& expected)
{
  if (!isFloat(a) || a.ndim() != 2 || a.shape(1) != 3)
    throw py::value_error(badArgument(argument, expected, a));
  return std::size_t(a.shape(0));
}

template <typename Emit>
void forEachRow3(const py::array& a, const char* argument, const std::string& expected,
                 Emit&& emit)
{
  rowCount3(a, argument, expected);
  auto rows = [&](auto tag) {
    using T = decltype(tag);
    const auto r = a.unchecked<T, 2>();
    for (py::ssize_t i = 0; i < r.shape(0); ++i)
      emit(std::size_t(i), float(r(i, 0)), float(r(i, 1)), float(r(i, 2)));
  };
  if (a.itemsize() == 4)
    rows(float{});
  else
    rows(double{});
}

const char* kPointsExpected = "an (N, 3) array of float32 or float64";

/// An (N,) array of integers >= 0 that fit in 32 bits.
std::vector<std::uint32_t> readIndexLike(const py::handle& values, const char* argument,
                                         std::size_t expected_count,
                                         const std::string& expected)
{
  const py::array a = asArray(values, argument, expected);
  const char kind = a.dtype().kind();
  if ((kind != 'i' && kind != 'u') || a.ndim() != 1)
    throw py::value_error(badArgument(argument, expected, a));
  if (std::size_t(a.shape(0)) != expected_count)
    throw py::value_error(std::string(argument) + ": expected " +
                          std::to_string(expected_count) +
                          " values (one per point), got " + std::to_string(a.shape(0)));
  const py::array_t<std::int64_t> wide = py::array_t<std::int64_t>::ensure(a);
  const auto r = wide.unchecked<1>();
  std::vector<std::uint32_t> out(std::size_t(r.shape(0)));
  for (py::ssize_t i = 0; i < r.shape(0); ++i) {
    if (r(i) < 0 || r(i) > std::int64_t(UINT32_MAX))
      throw py::value_error(std::string(argument) + "[" + std::to_string(i) +
                            "]: expected an integer in [0, 4294967295], got " +
                            std::to_string(r(i)));
    out[std::size_t(i)] = std::uint32_t(r(i));
  }
  return out;
}

} // namespace

std::recursive_mutex& libraryMutex()
{
  static std::recursive_mutex mutex;
  return mutex;
}

std::string badArgument(const char* argument, const std::string& expected,
                        const py::handle& value)
{
  return std::string(argument) + ": expected " + expected + ", got " + describe(value);
}

void readPoints(const py::handle& points, const char* argument, CloudXYZ& cloud)
{
  const py::array a = asArray(points, argument, kPointsExpected, "float64");
  cloud.resize(rowCount3(a, argument, kPointsExpected));
  forEachRow3(a, argument, kPointsExpected,
              [&](std::size_t i, float x, float y, float z) {
                cloud[i] = pcl::PointXYZ(x, y, z);
              });
  cloud.is_dense = false;
}

void readLabelledPoints(const py::handle& points, const py::handle& labels,
                        const char* argument, CloudXYZL& cloud)
{
  const py::array a = asArray(points, argument, kPointsExpected, "float64");
  cloud.resize(rowCount3(a, argument, kPointsExpected));
  forEachRow3(a, argument, kPointsExpected,
              [&](std::size_t i, float x, float y, float z) {
                cloud[i].x = x, cloud[i].y = y, cloud[i].z = z, cloud[i].label = 0;
              });
  cloud.is_dense = false;
  if (labels.is_none())
    return;
  const std::vector<std::uint32_t> l =
      readIndexLike(labels, "labels", cloud.size(), "an (N,) array of integers >= 0");
  for (std::size_t i = 0; i < l.size(); ++i)
    cloud[i].label = l[i];
}

std::vector<Eigen::Vector3f> readPointVector(const py::handle& points,
                                             const char* argument)
{
  const py::array a = asArray(points, argument, kPointsExpected, "float64");
  std::vector<Eigen::Vector3f> out(rowCount3(a, argument, kPointsExpected));
  forEachRow3(a, argument, kPointsExpected,
              [&](std::size_t i, float x, float y, float z) {
                out[i] = Eigen::Vector3f(x, y, z);
              });
  return out;
}

std::vector<PartLabel> readPartLabels(const py::handle& labels, const char* argument,
                                      std::size_t expected_count)
{
  if (labels.is_none())
    return {};
  const std::vector<std::uint32_t> l = readIndexLike(
      labels, argument, expected_count, "an (N,) array of part labels (integers 0-7)");
  std::vector<PartLabel> out(l.size());
  for (std::size_t i = 0; i < l.size(); ++i) {
    if (l[i] > std::uint32_t(kLastPartLabel))
      throw py::value_error(std::string(argument) + "[" + std::to_string(i) +
                            "]: expected a part label 0-7 (plantnbv.PART_LABELS), got " +
                            std::to_string(l[i]));
    out[i] = PartLabel(l[i]);
  }
  return out;
}

namespace {

const char* kPoseExpected =
    "a 4x4 rigid transform or (7,) [x, y, z, qx, qy, qz, qw] of finite numbers";

Pose poseFromRow(const double* v, const char* argument)
{
  for (int i = 0; i < 7; ++i)
    if (!std::isfinite(v[i]))
      throw py::value_error(std::string(argument) + ": expected finite numbers, got " +
                            std::to_string(v[i]) + " at index " + std::to_string(i));
  const double norm = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]);
  if (std::abs(norm - 1.0) > 1e-3)
    throw py::value_error(std::string(argument) +
                          ": expected a unit quaternion [qx, qy, qz, qw] (norm within "
                          "1e-3 of 1), got norm " +
                          std::to_string(norm));
  return Pose::fromXyzQuat(v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
}

Pose poseFromMatrix(const double* m, const char* argument) // row-major 4x4
{
  Eigen::Matrix4d T;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      T(r, c) = m[4 * r + c];
      if (!std::isfinite(T(r, c)))
        throw py::value_error(std::string(argument) + ": expected finite numbers, got " +
                              std::to_string(T(r, c)) + " at [" + std::to_string(r) +
                              ", " + std::to_string(c) + "]");
    }
  const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
  const double orthogonality = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
  if ((T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9 || orthogonality > 1e-6 ||
      R.determinant() < 0)
    throw py::value_error(std::string(argument) +
                          ": expected a rigid transform (a rotation, last row 0 0 0 1)");
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.linear() = R;
  iso.translation() = T.topRightCorner<3, 1>();
  return Pose::fromIsometry(iso);
}

} // namespace

Pose readPose(const py::handle& pose, const char* argument)
{
  const py::array a = asArray(pose, argument, kPoseExpected, "float64");
  if (a.dtype().kind() != 'f' && a.dtype().kind() != 'i' && a.dtype().kind() != 'u')
    throw py::type_error(badArgument(argument, kPoseExpected, a));
  const auto d =
      py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (d.ndim() == 1 && d.shape(0) == 7)
    return poseFromRow(d.data(), argument);
  if (d.ndim() == 2 && d.shape(0) == 4 && d.shape(1) == 4)
    return poseFromMatrix(d.data(), argument);
  throw py::value_error(badArgument(argument, kPoseExpected, a));
}

std::vector<Pose> readPoses(const py::handle& poses, const char* argument)
{
  const char* expected = "(K, 7) poses [x, y, z, qx, qy, qz, qw] or (K, 4, 4) transforms";
  const py::array a = asArray(poses, argument, expected, "float64");
  const auto d =
      py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!d || (a.dtype().kind() != 'f' && a.dtype().kind() != 'i'))
    throw py::type_error(badArgument(argument, expected, a));
  std::vector<Pose> out;
  if (d.ndim() == 2 && d.shape(1) == 7) {
    for (py::ssize_t k = 0; k < d.shape(0); ++k)
      out.push_back(poseFromRow(d.data(k, 0), argument));
  } else if (d.ndim() == 3 && d.shape(1) == 4 && d.shape(2) == 4) {
    for (py::ssize_t k = 0; k < d.shape(0); ++k)
      out.push_back(poseFromMatrix(d.data(k, 0, 0), argument));
  } else {
    throw py::value_error(badArgument(argument, expected, a));
  }
  return out;
}

Eigen::Vector3d readVector3(const py::handle& v, const char* argument)
{
  const char* expected = "3 finite numbers";
  const py::array a = asArray(v, argument, expected, "float64");
  const auto d =
      py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!d || d.ndim() != 1 || d.shape(0) != 3)
    throw py::value_error(badArgument(argument, expected, a));
  const Eigen::Vector3d out(d.at(0), d.at(1), d.at(2));
  if (!out.allFinite())
    throw py::value_error(std::string(argument) + ": expected 3 finite numbers, got [" +
                          std::to_string(out.x()) + ", " + std::to_string(out.y()) +
                          ", " + std::to_string(out.z()) + "]");
  return out;
}

DepthImage readDepth(const py::handle& depth, const char* argument)
{
  const char* expected = "an (H, W) depth image in metres, float32 or float64";
  const py::array a = asArray(depth, argument, expected, "float64");
  if (!isFloat(a) || a.ndim() != 2 || a.shape(0) < 1 || a.shape(1) < 1)
    throw py::value_error(badArgument(argument, expected, a));
  DepthImage out;
  out.height = std::uint32_t(a.shape(0));
  out.width = std::uint32_t(a.shape(1));
  out.depth_m.resize(std::size_t(out.width) * out.height);
  auto fill = [&](auto tag) {
    using T = decltype(tag);
    const auto r = a.unchecked<T, 2>();
    for (py::ssize_t v = 0; v < r.shape(0); ++v)
      for (py::ssize_t u = 0; u < r.shape(1); ++u)
        out.depth_m[std::size_t(v) * out.width + std::size_t(u)] = float(r(v, u));
  };
  if (a.itemsize() == 4)
    fill(float{});
  else
    fill(double{});
  return out;
}

namespace {

template <typename Cloud>
py::array_t<float> cloudPoints(const Cloud& cloud)
{
  py::array_t<float> out({py::ssize_t(cloud.size()), py::ssize_t(3)});
  float* p = out.mutable_data();
  for (const auto& q : cloud) {
    *p++ = q.x;
    *p++ = q.y;
    *p++ = q.z;
  }
  return out;
}

} // namespace

py::array_t<float> pointsArray(const CloudXYZ& cloud)
{
  return cloudPoints(cloud);
}

py::array_t<float> pointsArray(const CloudXYZL& cloud)
{
  return cloudPoints(cloud);
}

py::array_t<float> pointsArray(const std::vector<Eigen::Vector3f>& points)
{
  py::array_t<float> out({py::ssize_t(points.size()), py::ssize_t(3)});
  float* p = out.mutable_data();
  for (const Eigen::Vector3f& q : points)
    for (int k = 0; k < 3; ++k)
      *p++ = q[k];
  return out;
}

py::array_t<std::uint32_t> labelsArray(const CloudXYZL& cloud)
{
  py::array_t<std::uint32_t> out(py::ssize_t(cloud.size()));
  std::uint32_t* p = out.mutable_data();
  for (const auto& q : cloud)
    *p++ = q.label;
  return out;
}

py::array_t<std::uint32_t> labelsArray(const std::vector<PartLabel>& labels)
{
  py::array_t<std::uint32_t> out(py::ssize_t(labels.size()));
  std::uint32_t* p = out.mutable_data();
  for (PartLabel l : labels)
    *p++ = std::uint32_t(l);
  return out;
}

py::array_t<float> depthImageArray(const DepthImage& depth)
{
  py::array_t<float> out({py::ssize_t(depth.height), py::ssize_t(depth.width)});
  std::copy(depth.depth_m.begin(), depth.depth_m.end(), out.mutable_data());
  return out;
}

py::array_t<double> poseArray(const Pose& pose)
{
  py::array_t<double> out(7);
  double* p = out.mutable_data();
  const Eigen::Quaterniond& q = pose.orientation;
  for (double x : {pose.position.x(), pose.position.y(), pose.position.z(), q.x(), q.y(),
                   q.z(), q.w()})
    *p++ = x;
  return out;
}

py::array_t<double> poseArray(const std::vector<Pose>& poses)
{
  py::array_t<double> out({py::ssize_t(poses.size()), py::ssize_t(7)});
  double* p = out.mutable_data();
  for (const Pose& pose : poses) {
    const Eigen::Quaterniond& q = pose.orientation;
    for (double x : {pose.position.x(), pose.position.y(), pose.position.z(), q.x(),
                     q.y(), q.z(), q.w()})
      *p++ = x;
  }
  return out;
}

py::array_t<double> poseMatrix(const Pose& pose)
{
  py::array_t<double> out({py::ssize_t(4), py::ssize_t(4)});
  const Eigen::Matrix4d T = pose.toIsometry().matrix();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      out.mutable_at(r, c) = T(r, c);
  return out;
}

py::array_t<double> vectorArray(const Eigen::Vector3d& v)
{
  py::array_t<double> out(3);
  for (int k = 0; k < 3; ++k)
    out.mutable_at(k) = v[k];
  return out;
}

} // namespace python
} // namespace plantnbv
