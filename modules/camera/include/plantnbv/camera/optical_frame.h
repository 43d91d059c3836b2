#pragma once
/// \file optical_frame.h
/// \brief The two camera frames of plantnbv: the body frame of a Viewpoint (x forward,
/// y left, z up; the paper's Table 1, trials, the sector) and the optical frame (z
/// forward, x right, y down; OpenCV, ROS `*_optical_frame`, TUM trajectories, frames
/// folders and `plan`'s output). Both share the optical centre.

#include <plantnbv/common/pose.h>

namespace plantnbv {

/// \brief The optical frame of a camera whose body frame is T_W_C:
/// T_W_O = T_W_C * R_C_O, R_C_O's columns (0,-1,0), (0,0,-1), (1,0,0).
Pose opticalFrame(const Pose& T_W_C);

/// \brief The body frame of a camera whose optical frame is T_W_O (the inverse of
/// opticalFrame): T_W_C = T_W_O * R_C_O^T.
Pose bodyFrame(const Pose& T_W_O);

} // namespace plantnbv
