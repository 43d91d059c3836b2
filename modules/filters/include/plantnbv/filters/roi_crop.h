#pragma once
/// \file roi_crop.h
/// \brief Keeps the points inside a region of interest (a union of axis-aligned boxes).

#include <pcl/filters/filter_indices.h>

#include <plantnbv/common/box.h>

namespace plantnbv {

/// \brief pcl::CropBox for a union of boxes: keeps points inside any box of the ROI
/// (faces included, with the same double arithmetic as Box::contains). Honours the
/// pcl::FilterIndices options: setNegative (keep points outside every box),
/// extract_removed_indices (getRemovedIndices), setIndices, and drops non-finite points
/// (they are removed, in negative mode too). An empty ROI keeps nothing (negative: every
/// finite point). A point in several boxes is kept once; kept indices are in input order.
/// filter(cloud) copies is_dense from the input (pcl::copyPointCloud, as pcl::CropBox
/// does), although every point it keeps is finite.
///
/// setKeepOrganized(true) with filter(cloud) runs pcl::FilterIndices' own code: the
/// output is the input with x, y, z of every removed point set to the user filter value
/// (NaN by default; other fields such as the label are kept), width and height unchanged.
/// PCL switches extract_removed_indices on for this (printing a warning once if it was
/// off).
///
/// Compiled for pcl::PointXYZ and pcl::PointXYZL. Not thread-safe (one filter per
/// thread).
template <typename PointT>
class RoiCrop : public pcl::FilterIndices<PointT> {
  using PointCloud = typename pcl::FilterIndices<PointT>::PointCloud;

public:
  using Ptr = std::shared_ptr<RoiCrop<PointT>>;            ///< shared filter
  using ConstPtr = std::shared_ptr<const RoiCrop<PointT>>; ///< shared, read-only

  /// \param[in] extract_removed_indices true: getRemovedIndices() gives the points the
  /// last filter() call removed (pcl::FilterIndices' option).
  explicit RoiCrop(bool extract_removed_indices = false)
      : pcl::FilterIndices<PointT>(extract_removed_indices)
  {
    this->filter_name_ = "RoiCrop";
  }

  /// \param[in] roi the boxes to keep (world frame, metres); default: empty (keeps
  /// nothing).
  void setRoi(const Roi& roi) { roi_ = roi; }
  /// \brief The boxes kept.
  const Roi& getRoi() const { return roi_; }

protected:
  /// \brief The indices of the points kept (of the removed ones in negative mode), in
  /// input order; called by pcl::FilterIndices::filter.
  void applyFilter(pcl::Indices& indices) override;

private:
  Roi roi_;
};

} // namespace plantnbv
