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

TEST(Box, OverlapsTriangleOnEverySeparatingAxis)
{
  // The cube [-0.5, 0.5]^3, moved so that its centre is not the origin.
  const Eigen::Vector3d o(2.0, -1.0, 0.5);
  const Box cube(o, Eigen::Vector3d::Ones());
  auto overlaps = [&](Eigen::Vector3d a, Eigen::Vector3d b, Eigen::Vector3d c) {
    // Every order and winding of the vertices gives the same answer.
    const bool first = cube.overlapsTriangle(o + a, o + b, o + c);
    EXPECT_EQ(cube.overlapsTriangle(o + c, o + b, o + a), first);
    EXPECT_EQ(cube.overlapsTriangle(o + b, o + c, o + a), first);
    return first;
  };
  using V = Eigen::Vector3d;
  // Inside; beyond a face (the face axes); on a face (closed box).
  EXPECT_TRUE(overlaps(V(0, 0, 0), V(0.1, 0, 0), V(0, 0.1, 0)));
  EXPECT_FALSE(overlaps(V(0.6, 0, 0), V(0.9, 0, 0), V(0.6, 0.3, 0)));
  EXPECT_TRUE(overlaps(V(-2, -2, 0.5), V(2, -2, 0.5), V(0, 2, 0.5)));
  EXPECT_FALSE(overlaps(V(-2, -2, 0.5001), V(2, -2, 0.5001), V(0, 2, 0.5001)));
  // A large triangle through the cube, every vertex outside it.
  EXPECT_TRUE(overlaps(V(-5, -5, 0.2), V(5, -5, 0.2), V(0, 5, 0.2)));
  // Its plane separates (x + y + z = 1.6 passes the corner at 1.5), not its box.
  EXPECT_FALSE(overlaps(V(1.6, 0, 0), V(0, 1.6, 0), V(0, 0, 1.6)));
  EXPECT_TRUE(overlaps(V(1.4, 0, 0), V(0, 1.4, 0), V(0, 0, 1.4)));
  // Only an edge's cross product separates: in the plane z = 0, beyond the corner
  // (0.5, 0.5) along x + y; touching it at x + y = 1 overlaps.
  EXPECT_FALSE(overlaps(V(1.2, 0, 0), V(0, 1.2, 0), V(1.2, 1.2, 0)));
  EXPECT_TRUE(overlaps(V(1, 0, 0), V(0, 1, 0), V(1, 1, 0)));
  // A degenerate triangle (a segment) through the cube, and one past it.
  EXPECT_TRUE(overlaps(V(-1, 0, 0), V(1, 0, 0), V(0, 0, 0)));
  EXPECT_FALSE(overlaps(V(-1, 1, 0.8), V(1, 1, 0.8), V(0, 1, 0.8)));
}
