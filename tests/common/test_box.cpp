#include <gtest/gtest.h>

#include <plantnbv/common/box.h>
#include <plantnbv/common/error.h>

using plantnbv::Box;
using plantnbv::Roi;

TEST(Box, ContainsIsClosedOnFaces)
{
  // Sizes exact in binary, so the corner is exactly on the faces.
  const Box b(Eigen::Vector3d(1, 0, 1), Eigen::Vector3d(0.5, 0.25, 1.0));
  EXPECT_TRUE(b.contains(Eigen::Vector3d(1, 0, 1)));
  EXPECT_TRUE(b.contains(Eigen::Vector3d(1.25, 0.125, 1.5))); // corner
  EXPECT_FALSE(b.contains(Eigen::Vector3d(1.2501, 0, 1)));
  EXPECT_FALSE(b.contains(Eigen::Vector3d(1, -0.1251, 1)));
  EXPECT_DOUBLE_EQ(b.volume(), 0.5 * 0.25 * 1.0);
}

TEST(Box, RejectsNegativeSizeAndNonFinite)
{
  EXPECT_THROW(Box(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.1, -0.1, 0.1)),
               plantnbv::InvalidArgumentError);
  EXPECT_THROW(Box(Eigen::Vector3d(NAN, 0, 0), Eigen::Vector3d::Ones()),
               plantnbv::InvalidArgumentError);
  EXPECT_THROW(Box::fromMinMax(Eigen::Vector3d::Ones(), Eigen::Vector3d::Zero()),
               plantnbv::InvalidArgumentError);
}

TEST(Roi, UnionAndBoundingBox)
{
  Roi roi;
  EXPECT_FALSE(roi.contains(Eigen::Vector3d::Zero()));
  EXPECT_THROW(roi.boundingBox(), plantnbv::InvalidArgumentError);
  roi.addBox(Box::fromMinMax(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1)));
  roi.addBox(Box::fromMinMax(Eigen::Vector3d(2, -1, 0.5), Eigen::Vector3d(3, 0, 2)));
  EXPECT_TRUE(roi.contains(Eigen::Vector3d(0.5, 0.5, 0.5)));
  EXPECT_TRUE(roi.contains(Eigen::Vector3d(2.5, -0.5, 1.5)));
  EXPECT_FALSE(roi.contains(Eigen::Vector3d(1.5, 0.5, 0.5))); // between the boxes
  const Box bb = roi.boundingBox();
  EXPECT_TRUE(bb.min().isApprox(Eigen::Vector3d(0, -1, 0)));
  EXPECT_TRUE(bb.max().isApprox(Eigen::Vector3d(3, 1, 2)));
}
