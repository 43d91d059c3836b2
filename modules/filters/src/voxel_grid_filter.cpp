// Compiles VoxelGridFilter once for the point types plantnbv uses (PCL's precompile
// scheme): users of these types include only voxel_grid_filter.h.
#include <pcl/point_types.h>

#include <plantnbv/filters/impl/voxel_grid_filter.hpp>

template class plantnbv::VoxelGridFilter<pcl::PointXYZ>;
template class plantnbv::VoxelGridFilter<pcl::PointXYZL>;
