#pragma once
/// \file impl/roi_crop.hpp
/// \brief Template body of RoiCrop; included by src/roi_crop.cpp only (and by users who
/// need a point type other than PointXYZ / PointXYZL).

#include <cmath>
#include <vector>

#include <pcl/common/point_tests.h>

#include <plantnbv/filters/roi_crop.h>

namespace plantnbv {

template <typename PointT>
void RoiCrop<PointT>::applyFilter(pcl::Indices& indices)
{
  // Box::contains tests |p - centre| <= size / 2 in double; the same arithmetic here,
  // hoisted out of the loop, so that a point on a face is kept exactly when
  // Box::contains says so.
  struct HalfBox {
    double cx, cy, cz, hx, hy, hz;
  };
  std::vector<HalfBox> boxes;
  boxes.reserve(roi_.size());
  for (const Box& b : roi_.boxes())
    boxes.push_back({b.center.x(), b.center.y(), b.center.z(), 0.5 * b.size.x(),
                     0.5 * b.size.y(), 0.5 * b.size.z()});

  const PointCloud& input = *this->input_;
  const bool negative = this->negative_;
  const bool extract_removed = this->extract_removed_indices_;
  indices.clear();
  indices.reserve(this->indices_->size());
  this->removed_indices_->clear();

  for (const auto index : *this->indices_) {
    const PointT& p = input[index];
    bool keep = false; // a non-finite point is removed, in negative mode too
    if (pcl::isXYZFinite(p)) {
      const double x = p.x, y = p.y, z = p.z;
      bool inside = false;
      for (const HalfBox& b : boxes) {
        if (std::abs(x - b.cx) <= b.hx && std::abs(y - b.cy) <= b.hy &&
            std::abs(z - b.cz) <= b.hz) {
          inside = true;
          break;
        }
      }
      keep = inside != negative;
    }
    if (keep)
      indices.push_back(index);
    else if (extract_removed)
      this->removed_indices_->push_back(index);
  }
}

} // namespace plantnbv
