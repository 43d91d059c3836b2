#pragma once
/// \file pcl_fwd.h
/// \brief Forward declarations of the PCL types our public headers name, so that users
/// of those headers do not compile PCL's (heavy) headers. Include <pcl/point_types.h>
/// and <pcl/point_cloud.h> in the .cpp that fills or reads a cloud.

#include <memory>

namespace pcl {
struct PointXYZ;
struct PointXYZL;
template <typename PointT>
class PointCloud;
} // namespace pcl

namespace plantnbv {
/// \brief A cloud of points (x, y, z in metres).
using CloudXYZ = pcl::PointCloud<pcl::PointXYZ>;
/// \brief A cloud of points with a label each (a PartLabel, triangle_mesh.h).
using CloudXYZL = pcl::PointCloud<pcl::PointXYZL>;
/// \brief A shared read-only CloudXYZ.
using CloudXYZConstPtr = std::shared_ptr<const CloudXYZ>;
/// \brief A shared read-only CloudXYZL.
using CloudXYZLConstPtr = std::shared_ptr<const CloudXYZL>;
} // namespace plantnbv
