#include <plantnbv/camera/optical_frame.h>

namespace plantnbv {

namespace {

Eigen::Quaterniond rotationBodyFromOptical()
{
  Eigen::Matrix3d R_C_O;
  R_C_O << 0.0, 0.0, 1.0, -1.0, 0.0, 0.0, 0.0, -1.0, 0.0;
  return Eigen::Quaterniond(R_C_O);
}

} // namespace

Pose opticalFrame(const Pose& T_W_C)
{
  return Pose(T_W_C.position, T_W_C.orientation * rotationBodyFromOptical());
}

Pose bodyFrame(const Pose& T_W_O)
{
  return Pose(T_W_O.position, T_W_O.orientation * rotationBodyFromOptical().conjugate());
}

} // namespace plantnbv
