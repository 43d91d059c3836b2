#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/plant/plant_model.h>
#include <plantnbv/plant/plant_rois.h>

using namespace plantnbv;

namespace {
/// Two named boxes' worth of triangles: a "Branch_1" stem above (2, 3, 1) and "Leaf_A".
TriangleMesh namedMesh()
{
  TriangleMesh m;
  m.vertices = {{1.5f, 2.5f, 1}, {2.5f, 2.5f, 1}, {2, 3.5f, 1.5f}, {2, 3, 2}};
  m.triangles = {{0, 1, 2}, {1, 2, 3}, {0, 2, 3}};
  m.node_names = {"Branch_1", "Leaf_A", "Other"};
  m.node_ids = {0, 1, 2};
  return m;
}
} // namespace

TEST(PartLabelRules, ParseAndApplyFirstMatchWins)
{
  const auto rules = parsePartLabelRules("stem=Branch.*,leaflet=Leaf_.*,fruit=.*A");
  ASSERT_EQ(rules.size(), 3u);
  EXPECT_EQ(rules[1].label, PartLabel::leaflet);
  TriangleMesh m = namedMesh();
  const auto counts = applyPartLabelRules(m, rules);
  EXPECT_EQ(counts, (std::vector<std::size_t>{1, 1, 0})); // Leaf_A matched leaflet first
  EXPECT_EQ(m.labels, (std::vector<PartLabel>{PartLabel::stem, PartLabel::leaflet,
                                              PartLabel::unknown}));
  // Full match only: "Branch" alone does not match "Branch_1".
  TriangleMesh n = namedMesh();
  applyPartLabelRules(n, parsePartLabelRules("stem=Branch"));
  EXPECT_EQ(n.labels[0], PartLabel::unknown);
}

TEST(PartLabelRules, MatchGeometryAndMaterialNamesToo)
{
  // A 3ds Max export: one node "Plant", parts told apart by material; a Gazebo model's
  // blossoms by geometry name.
  TriangleMesh m = namedMesh();
  m.node_names = {"Plant", "Plant", "Plant"};
  m.geometry_names = {"mesh_0", "mesh_1", "Blossom_3"};
  m.material_names = {"Mat_Branch", "Mat_Leaf", "Mat_Yellow"};
  const auto counts = applyPartLabelRules(
      m, parsePartLabelRules("stem=Mat_Branch,leaflet=Mat_Leaf,flower=Blossom.*"));
  EXPECT_EQ(counts, (std::vector<std::size_t>{1, 1, 1}));
  EXPECT_EQ(m.labels, (std::vector<PartLabel>{PartLabel::stem, PartLabel::leaflet,
                                              PartLabel::flower}));
  // The node name is tried first, then the geometry's, then the material's, rule by
  // rule: the first rule any of them matches wins.
  TriangleMesh n = m;
  applyPartLabelRules(n, parsePartLabelRules("fruit=Mat_.*,stem=Plant"));
  EXPECT_EQ(n.labels, (std::vector<PartLabel>(3, PartLabel::fruit)));
  EXPECT_EQ(partLabelFromName("flower"), PartLabel::flower);
  EXPECT_STREQ(partLabelName(PartLabel::flower), "flower");
}

TEST(PartLabelRules, RejectsBadSpecs)
{
  EXPECT_THROW(parsePartLabelRules("trunk=Branch.*"), InvalidArgumentError);
  EXPECT_THROW(parsePartLabelRules("stem"), InvalidArgumentError);
  EXPECT_THROW(parsePartLabelRules("stem="), InvalidArgumentError);
  EXPECT_THROW(parsePartLabelRules("stem=Branch(("), InvalidArgumentError);
  EXPECT_THROW(parsePartLabelRules("stem=a,,leaflet=b"), InvalidArgumentError);
}

TEST(PlantFromMesh, PutsTheBottomCentreAtTheOriginUnlessTheFrameIsKept)
{
  const Plant p = plantFromMesh(namedMesh(), "model");
  Eigen::Vector3f lo, hi;
  p.mesh.bounds(lo, hi);
  EXPECT_EQ(lo, Eigen::Vector3f(-0.5f, -0.5f, 0.0f));
  EXPECT_EQ(hi, Eigen::Vector3f(0.5f, 0.5f, 1.0f));
  EXPECT_EQ(p.base_position, Eigen::Vector3d::Zero());
  EXPECT_DOUBLE_EQ(p.anatomy.top_height_m, 1.0);
  EXPECT_EQ(p.mesh.node_names, namedMesh().node_names);

  const Plant kept = plantFromMesh(namedMesh(), "model", true);
  EXPECT_EQ(kept.mesh.vertices, namedMesh().vertices);
  EXPECT_TRUE(kept.base_position.isApprox(Eigen::Vector3d(2, 3, 1)));
  const Box bb = boundingBoxRoi(kept).boxes().front();
  EXPECT_TRUE(bb.min().isApprox(Eigen::Vector3d(1.5, 2.5, 1)));
  EXPECT_EQ(bb.name, "whole_plant");

  // Posed like a generated plant: base to (1, 0, 0.8).
  Plant posed = plantFromMesh(namedMesh(), "model");
  posePlant(posed, Eigen::Vector3d(1, 0, 0.8), 0.0);
  posed.mesh.bounds(lo, hi);
  EXPECT_NEAR(lo.z(), 0.8f, 1e-6f);
  EXPECT_NEAR(0.5f * (lo.x() + hi.x()), 1.0f, 1e-6f);
  EXPECT_THROW(plantFromMesh(TriangleMesh(), "empty"), InvalidArgumentError);
}
