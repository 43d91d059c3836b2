#pragma once
/// \file pose.h
/// \brief Rigid poses. Frames and units follow docs/architecture.md ("Conventions"):
/// metres, world frame x forward from the robot base and z up. A `Viewpoint` is the
/// camera body frame (x forward, y left, z up), as the paper's Table 1 gives v0; the
/// optical frame (z forward) is derived inside the sensor.

#include <Eigen/Geometry>

namespace plantnbv {

/// \brief A rigid transform given as position + unit quaternion, e.g. T_W_C (camera in
/// world). Construction normalises the quaternion.
struct Pose {
  /// The frame's origin in the parent frame (metres), e.g. the camera centre in T_W_C.
  Eigen::Vector3d position{Eigen::Vector3d::Zero()};
  /// The frame's rotation relative to the parent frame, a unit quaternion.
  Eigen::Quaterniond orientation{Eigen::Quaterniond::Identity()};

  Pose() = default;
  /// \throws InvalidArgumentError on non-finite values or a zero quaternion.
  Pose(const Eigen::Vector3d& position, const Eigen::Quaterniond& orientation);
  /// \brief From x, y, z and a quaternion given as qx, qy, qz, qw (ROS order).
  static Pose fromXyzQuat(double x, double y, double z, double qx, double qy, double qz,
                          double qw);
  /// \brief From a rigid transform (its rotation and translation).
  static Pose fromIsometry(const Eigen::Isometry3d& T);

  /// \brief The same transform as a 4x4 isometry, e.g. T_W_C maps camera points to world.
  Eigen::Isometry3d toIsometry() const;
  /// \brief The body x axis (the viewing direction of a Viewpoint) in the parent frame.
  Eigen::Vector3d forward() const { return orientation * Eigen::Vector3d::UnitX(); }
};

/// \brief A camera viewpoint: the pose of the camera body frame in the world.
using Viewpoint = Pose;

} // namespace plantnbv
