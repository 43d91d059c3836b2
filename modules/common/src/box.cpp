#include <algorithm>
#include <sstream>

#include <Eigen/Geometry> // cross

#include <plantnbv/common/box.h>
#include <plantnbv/common/error.h>

namespace plantnbv {

namespace {
std::string str(const Eigen::Vector3d& v)
{
  std::ostringstream s;
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}
} // namespace

Box::Box(const Eigen::Vector3d& c, const Eigen::Vector3d& s, std::string n)
    : center(c), size(s), name(std::move(n))
{
  if (!center.allFinite() || !size.allFinite())
    throw InvalidArgumentError("box '" + name + "': centre " + str(center) +
                               " and size " + str(size) + " must be finite");
  if ((size.array() < 0.0).any())
    throw InvalidArgumentError("box '" + name + "': size " + str(size) +
                               " must not be negative");
}

Box Box::fromMinMax(const Eigen::Vector3d& min, const Eigen::Vector3d& max,
                    std::string name)
{
  if ((max.array() < min.array()).any())
    throw InvalidArgumentError("box '" + name + "': min " + str(min) + " exceeds max " +
                               str(max));
  return Box(0.5 * (min + max), max - min, std::move(name));
}

bool Box::overlaps(const Box& other) const
{
  return (min().array() <= other.max().array()).all() &&
         (other.min().array() <= max().array()).all();
}

bool Box::contains(const Eigen::Vector3d& p) const
{
  return ((p - center).cwiseAbs().array() <= 0.5 * size.array()).all();
}

bool Box::contains(float x, float y, float z) const
{
  return contains(Eigen::Vector3d(x, y, z));
}

bool Box::overlapsTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                           const Eigen::Vector3d& c) const
{
  const Eigen::Vector3d half = 0.5 * size;
  const Eigen::Vector3d v[3] = {a - center, b - center, c - center};
  // Separated along `axis` if the triangle's projection lies beyond the box's radius.
  auto separated = [&](const Eigen::Vector3d& axis) {
    const double p0 = axis.dot(v[0]), p1 = axis.dot(v[1]), p2 = axis.dot(v[2]);
    const double r = half.dot(axis.cwiseAbs());
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
  };
  for (int i = 0; i < 3; ++i)
    if (separated(Eigen::Vector3d::Unit(i)))
      return false;
  const Eigen::Vector3d edges[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  if (separated(edges[0].cross(edges[1])))
    return false;
  for (const Eigen::Vector3d& e : edges)
    for (int i = 0; i < 3; ++i)
      if (separated(e.cross(Eigen::Vector3d::Unit(i))))
        return false;
  return true;
}

Roi::Roi(std::vector<Box> boxes) : boxes_(std::move(boxes)) {}

void Roi::addBox(const Box& box)
{
  boxes_.push_back(box);
}

bool Roi::contains(const Eigen::Vector3d& p) const
{
  for (const Box& b : boxes_)
    if (b.contains(p))
      return true;
  return false;
}

bool Roi::contains(float x, float y, float z) const
{
  return contains(Eigen::Vector3d(x, y, z));
}

Box Roi::boundingBox() const
{
  if (boxes_.empty())
    throw InvalidArgumentError("the bounding box of an empty ROI is undefined");
  Eigen::Vector3d lo = boxes_.front().min(), hi = boxes_.front().max();
  for (const Box& b : boxes_) {
    lo = lo.cwiseMin(b.min());
    hi = hi.cwiseMax(b.max());
  }
  return Box::fromMinMax(lo, hi, "bounding_box");
}

} // namespace plantnbv
