#pragma once
/// \file box.h
/// \brief Axis-aligned boxes and regions of interest (the paper's attention ROIs,
/// section 2.3: each cuboid is given by its centre and the lengths of its sides).

#include <string>
#include <vector>

#include <Eigen/Core>

namespace plantnbv {

/// \brief An axis-aligned cuboid in the world frame, given by centre and size (metres).
/// A point on a face is inside (closed box).
struct Box {
  Eigen::Vector3d center{Eigen::Vector3d::Zero()}; ///< centre, world frame, metres
  Eigen::Vector3d size{Eigen::Vector3d::Zero()};   ///< side lengths along x, y, z, metres
  std::string name;                                ///< optional, e.g. "leaf_node_3"

  Box() = default;
  /// \throws InvalidArgumentError if a size is negative or a value is not finite.
  Box(const Eigen::Vector3d& center, const Eigen::Vector3d& size, std::string name = "");
  /// \brief The box spanning [min, max]. \throws InvalidArgumentError if min > max.
  static Box fromMinMax(const Eigen::Vector3d& min, const Eigen::Vector3d& max,
                        std::string name = "");

  /// \brief The lowest corner, center - size / 2 (metres).
  Eigen::Vector3d min() const { return center - 0.5 * size; }
  /// \brief The highest corner, center + size / 2 (metres).
  Eigen::Vector3d max() const { return center + 0.5 * size; }
  /// \brief The volume in cubic metres.
  double volume() const { return size.prod(); }

  /// \brief True if the point is inside or on a face (|p - center| <= size / 2 on every
  /// axis, in double).
  bool contains(const Eigen::Vector3d& p) const;
  /// \brief contains() for a float point, as PCL stores it.
  bool contains(float x, float y, float z) const;
  /// \brief True if the two closed boxes share a point (touching faces count).
  bool overlaps(const Box& other) const;
  /// \brief True if the triangle abc and the closed box share a point (exact
  /// separating-axis test: the box's 3 face normals, the triangle's normal and the 9
  /// cross products of their edges). A triangle touching a face overlaps.
  bool overlapsTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                        const Eigen::Vector3d& c) const;
};

/// \brief A region of interest: a union of boxes. An empty ROI contains nothing.
class Roi {
public:
  Roi() = default;
  /// \brief The union of these boxes (duplicates and overlaps allowed).
  explicit Roi(std::vector<Box> boxes);

  /// \brief Adds a box to the union.
  void addBox(const Box& box);
  /// \brief The boxes, in the order given.
  const std::vector<Box>& boxes() const { return boxes_; }
  /// \brief True if the ROI has no box (it contains nothing).
  bool empty() const { return boxes_.empty(); }
  /// \brief The number of boxes.
  std::size_t size() const { return boxes_.size(); }

  /// \brief True if any box contains the point.
  bool contains(const Eigen::Vector3d& p) const;
  /// \brief contains() for a float point, as PCL stores it.
  bool contains(float x, float y, float z) const;
  /// \brief The smallest box holding all boxes. \throws InvalidArgumentError when empty.
  Box boundingBox() const;

private:
  std::vector<Box> boxes_;
};

} // namespace plantnbv
