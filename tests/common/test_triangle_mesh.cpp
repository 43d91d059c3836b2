#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/triangle_mesh.h>

using plantnbv::PartLabel;
using plantnbv::TriangleMesh;

namespace {
TriangleMesh unitTriangle(const std::string& node)
{
  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}};
  m.node_ids = {0};
  m.node_names = {node};
  return m;
}
} // namespace

TEST(TriangleMesh, AreaBoundsAndValidate)
{
  TriangleMesh m = unitTriangle("a");
  EXPECT_DOUBLE_EQ(m.triangleArea(0), 0.5);
  Eigen::Vector3f lo, hi;
  m.bounds(lo, hi);
  EXPECT_EQ(hi, Eigen::Vector3f(1, 1, 0));
  EXPECT_NO_THROW(m.validate());
  m.triangles.push_back({0, 1, 3});
  EXPECT_THROW(m.validate(), plantnbv::FormatError);
}

TEST(TriangleMesh, AppendKeepsPerTriangleArraysComplete)
{
  TriangleMesh a = unitTriangle("stem");
  a.labels = {PartLabel::stem};
  TriangleMesh b; // no labels, no names
  b.vertices = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  b.triangles = {{0, 1, 2}};
  a.append(b);
  a.append(unitTriangle("leaf"));
  ASSERT_EQ(a.size(), 3u);
  EXPECT_EQ(a.triangles[1][0], 3u);
  EXPECT_EQ(a.labels, (std::vector<PartLabel>{PartLabel::stem, PartLabel::unknown,
                                              PartLabel::unknown}));
  ASSERT_EQ(a.node_ids.size(), 3u);
  EXPECT_EQ(a.node_names[a.node_ids[0]], "stem");
  EXPECT_EQ(a.node_names[a.node_ids[1]], "");
  EXPECT_EQ(a.node_names[a.node_ids[2]], "leaf");
  EXPECT_NO_THROW(a.validate());
}

TEST(PartLabel, NamesRoundTripAndUnknownNamesThrow)
{
  for (auto l :
       {PartLabel::stem, PartLabel::leaflet, PartLabel::fruit, PartLabel::background})
    EXPECT_EQ(plantnbv::partLabelFromName(plantnbv::partLabelName(l)), l);
  EXPECT_THROW(plantnbv::partLabelFromName("trunk"), plantnbv::InvalidArgumentError);
}
