// Compiles RoiCrop once for the point types plantnbv uses (PCL's precompile scheme):
// users of these types include only roi_crop.h.
#include <pcl/point_types.h>

#include <plantnbv/filters/impl/roi_crop.hpp>

template class plantnbv::RoiCrop<pcl::PointXYZ>;
template class plantnbv::RoiCrop<pcl::PointXYZL>;
