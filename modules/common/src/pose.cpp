#include <sstream>

#include <plantnbv/common/error.h>
#include <plantnbv/common/pose.h>

namespace plantnbv {

Pose::Pose(const Eigen::Vector3d& p, const Eigen::Quaterniond& q)
    : position(p), orientation(q)
{
  if (!position.allFinite() || !orientation.coeffs().allFinite()) {
    std::ostringstream s;
    s << "pose (" << position.transpose() << "; " << orientation.coeffs().transpose()
      << ") must be finite";
    throw InvalidArgumentError(s.str());
  }
  const double n = orientation.norm();
  if (n < 1e-9)
    throw InvalidArgumentError("pose quaternion must not be zero");
  orientation.coeffs() /= n;
}

Pose Pose::fromXyzQuat(double x, double y, double z, double qx, double qy, double qz,
                       double qw)
{
  return Pose(Eigen::Vector3d(x, y, z), Eigen::Quaterniond(qw, qx, qy, qz));
}

Pose Pose::fromIsometry(const Eigen::Isometry3d& T)
{
  return Pose(T.translation(), Eigen::Quaterniond(T.rotation()));
}

Eigen::Isometry3d Pose::toIsometry() const
{
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = orientation.toRotationMatrix();
  T.translation() = position;
  return T;
}

} // namespace plantnbv
