#pragma once
/// \file memory_estimate.h
/// \brief Upper estimates of what putting depth views into a map and planning on it
/// allocate, computed from the configuration before anything is allocated, for the
/// memory cap (plantnbv/common/memory_cap.h). docs/reliability.md compares them with
/// measured peaks.

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/planning/information_gain.h>

namespace plantnbv {

/// \brief The memory of one frame of the camera, in bytes: its depth, points and labels
/// (32 bytes a pixel).
double estimatedFrameMemoryBytes(const CameraIntrinsics& camera);

/// \brief The memory of one depth view into a map, in bytes: the voxels of the view's
/// free space (the camera's frustum out to the nearer of the map's and the camera's
/// range, at the map's resolution) at 32 bytes each (an OcTree leaf and its share of the
/// inner nodes), plus the frame (estimatedFrameMemoryBytes). Views
/// overlap, so a map of many views stays near one view's. Used by TrialConfig,
/// `capture --map` and `integrate`. \throws nothing (no validation).
double estimatedViewMemoryBytes(const OccupancyMap::Config& map,
                                const CameraIntrinsics& camera);

/// \brief The memory of the gain's ray directions, in bytes (24 a ray).
double estimatedGainMemoryBytes(const GainConfig& gain);

} // namespace plantnbv
