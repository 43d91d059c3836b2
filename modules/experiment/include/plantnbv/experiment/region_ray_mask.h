#pragma once
/// \file region_ray_mask.h
/// \brief regionRayMask: the pixels whose rays may reach a map's update region, the only
/// ones a trial's simulated camera needs to cast.

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/camera/ray_mask.h>
#include <plantnbv/common/pose.h>
#include <plantnbv/octree/update_region.h>

namespace plantnbv {

/// \brief The pixels of camera `K`, its optical frame at `T_W_O` (world), whose rays up
/// to `range_m` may meet `region`: one of its bricks within `range_m` of the optical
/// centre, or the space outside its bounds (all of which the region holds; then every
/// pixel). Conservative as RayMask.
///
/// A pixel outside it changes, inserted with a range of `range_m`, only voxels outside
/// the region, which a map with that update region leaves alone; and where the region
/// holds the bricks around every triangle of the scene (a trial's), its ray ends on no
/// surface within range either, so the sensor need not cast it
/// (SimulatedDepthSensor::setRayMask).
///
/// \throws InvalidArgumentError as RayMask's constructor.
RayMask regionRayMask(const UpdateRegion& region, const CameraIntrinsics& K,
                      const Pose& T_W_O, double range_m);

} // namespace plantnbv
