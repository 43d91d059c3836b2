#include <cmath>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/plant/plant_rois.h>

#include "plant_test_util.h"

using plantnbv::kDefaultPlantCount;
using plantnbv::PartLabel;
using plantnbv::Plant;
using plantnbv::posePlant;
using plantnbv::Roi;
using plantnbv::test::defaultPlant;

namespace {

const Eigen::Vector3d kPaperBase(1.0, 0.0, 0.8); // Table 1

/// (x, y, z) turned 90 deg about z, then moved to the base: (-y, x, z) + base.
Eigen::Vector3d quarterTurn(const Eigen::Vector3d& p)
{
  return Eigen::Vector3d(-p.y(), p.x(), p.z()) + kPaperBase;
}

} // namespace

TEST(PosePlant, QuarterTurnMovesMeshAnatomyTogether)
{
  const Plant& original = defaultPlant(7);
  Plant posed = original;
  posePlant(posed, kPaperBase, M_PI / 2);
  EXPECT_EQ(posed.base_position, kPaperBase);
  EXPECT_DOUBLE_EQ(posed.yaw_rad, M_PI / 2);

  for (std::size_t k = 0; k < original.anatomy.leaves.size(); ++k) {
    const auto& a = original.anatomy.leaves[k].node;
    const auto& b = posed.anatomy.leaves[k].node;
    EXPECT_NEAR((b.position - quarterTurn(a.position)).norm(), 0.0, 1e-12);
    EXPECT_NEAR((b.stem_point - quarterTurn(a.stem_point)).norm(), 0.0, 1e-12);
    const Eigen::Vector3d d(-a.petiole_direction.y(), a.petiole_direction.x(),
                            a.petiole_direction.z());
    EXPECT_NEAR((b.petiole_direction - d).norm(), 0.0, 1e-12);
    EXPECT_NEAR((posed.anatomy.leaves[k].axis.back() -
                 quarterTurn(original.anatomy.leaves[k].axis.back()))
                    .norm(),
                0.0, 1e-12);
  }
  for (std::size_t t = 0; t < original.anatomy.trusses.size(); ++t)
    for (std::size_t f = 0; f < original.anatomy.trusses[t].fruits.size(); ++f)
      EXPECT_NEAR((posed.anatomy.trusses[t].fruits[f].center -
                   quarterTurn(original.anatomy.trusses[t].fruits[f].center))
                      .norm(),
                  0.0, 1e-12);
  EXPECT_NEAR((posed.anatomy.stem_axis.front() - kPaperBase).norm(), 0.0, 1e-15);

  ASSERT_EQ(posed.mesh.vertices.size(), original.mesh.vertices.size());
  EXPECT_EQ(posed.mesh.triangles, original.mesh.triangles);
  EXPECT_EQ(posed.mesh.labels, original.mesh.labels);
  double worst = 0.0;
  for (std::size_t v = 0; v < original.mesh.vertices.size(); ++v)
    worst = std::max(worst, (posed.mesh.vertices[v].cast<double>() -
                             quarterTurn(original.mesh.vertices[v].cast<double>()))
                                .norm());
  EXPECT_LT(worst, 2e-7); // float rounding only
}

TEST(PosePlant, RoisMoveWithThePose)
{
  const Plant& original = defaultPlant(8);
  Plant posed = original;
  posePlant(posed, kPaperBase, M_PI / 2);

  // The paper's boxes: centre 0.35 m above the base on the stem axis, (1.0, 0, 1.15) for
  // a straight stem.
  for (const auto& [before, after] :
       {std::make_pair(plantnbv::wholePlantRoi(original), plantnbv::wholePlantRoi(posed)),
        std::make_pair(plantnbv::mainStemRoi(original), plantnbv::mainStemRoi(posed))}) {
    const Eigen::Vector3d c = after.boxes()[0].center;
    EXPECT_NEAR((c - quarterTurn(before.boxes()[0].center)).norm(), 0.0, 1e-9);
    EXPECT_NEAR(c.z(), 1.15, 1e-12);
    EXPECT_LT((c - Eigen::Vector3d(1.0, 0.0, 1.15)).norm(), 0.01);
  }
  const Roi nodes_before = plantnbv::leafNodeRoi(original);
  const Roi nodes_after = plantnbv::leafNodeRoi(posed);
  ASSERT_EQ(nodes_after.size(), nodes_before.size());
  for (std::size_t b = 0; b < nodes_before.size(); ++b) {
    EXPECT_EQ(nodes_after.boxes()[b].name, nodes_before.boxes()[b].name);
    EXPECT_NEAR(
        (nodes_after.boxes()[b].center - quarterTurn(nodes_before.boxes()[b].center))
            .norm(),
        0.0, 1e-12);
  }
  // A quarter turn maps the fruits' bounding box onto the turned box: x and y swap.
  const Roi fruits_before = plantnbv::fruitRoi(original);
  const Roi fruits_after = plantnbv::fruitRoi(posed);
  ASSERT_EQ(fruits_after.size(), fruits_before.size());
  for (std::size_t b = 0; b < fruits_before.size(); ++b) {
    const auto& s0 = fruits_before.boxes()[b].size;
    const auto& s1 = fruits_after.boxes()[b].size;
    EXPECT_NEAR(
        (fruits_after.boxes()[b].center - quarterTurn(fruits_before.boxes()[b].center))
            .norm(),
        0.0, 1e-12);
    EXPECT_NEAR(s1.x(), s0.y(), 1e-12);
    EXPECT_NEAR(s1.y(), s0.x(), 1e-12);
    EXPECT_NEAR(s1.z(), s0.z(), 1e-12);
  }
}

TEST(PosePlant, PoseIsAbsoluteAndReversible)
{
  const Plant& original = defaultPlant(2);
  Plant twice = original, once = original;
  posePlant(twice, Eigen::Vector3d(0.3, -0.2, 0.1), 0.7);
  posePlant(twice, kPaperBase, M_PI / 2);
  posePlant(once, kPaperBase, M_PI / 2);
  for (std::size_t k = 0; k < once.anatomy.leaves.size(); ++k)
    EXPECT_NEAR(
        (twice.anatomy.leaves[k].node.position - once.anatomy.leaves[k].node.position)
            .norm(),
        0.0, 1e-12);
  double worst = 0.0;
  for (std::size_t v = 0; v < once.mesh.vertices.size(); ++v)
    worst = std::max(worst, static_cast<double>(
                                (twice.mesh.vertices[v] - once.mesh.vertices[v]).norm()));
  EXPECT_LT(worst, 5e-7);

  posePlant(twice, Eigen::Vector3d::Zero(), 0.0);
  for (std::size_t k = 0; k < original.anatomy.leaves.size(); ++k)
    EXPECT_NEAR(
        (twice.anatomy.leaves[k].node.position - original.anatomy.leaves[k].node.position)
            .norm(),
        0.0, 1e-12);
}

TEST(PosePlant, ThePapersTwelveYawsKeepTheStemInItsRoi)
{
  const Plant& original = defaultPlant(9);
  for (int step = 0; step < 12; ++step) {
    Plant posed = original;
    posePlant(posed, kPaperBase, step * 30.0 * M_PI / 180.0);
    const Roi stem = plantnbv::mainStemRoi(posed);
    const auto& m = posed.mesh;
    for (std::size_t t = 0; t < m.size(); ++t) {
      if (m.labels[t] != PartLabel::stem)
        continue;
      for (auto v : m.triangles[t]) {
        ASSERT_TRUE(
            stem.contains(m.vertices[v].x(), m.vertices[v].y(), m.vertices[v].z()))
            << "yaw step " << step;
      }
    }
    // Heights do not change with yaw.
    for (std::size_t k = 0; k < posed.anatomy.leaves.size(); ++k)
      EXPECT_NEAR(posed.anatomy.leaves[k].node.position.z(),
                  original.anatomy.leaves[k].node.position.z() + 0.8, 1e-12);
  }
}

TEST(PosePlant, RejectsNonFiniteValues)
{
  Plant p = defaultPlant(0);
  EXPECT_THROW(posePlant(p, Eigen::Vector3d(NAN, 0, 0), 0.0),
               plantnbv::InvalidArgumentError);
  EXPECT_THROW(posePlant(p, Eigen::Vector3d::Zero(), INFINITY),
               plantnbv::InvalidArgumentError);
  EXPECT_EQ(p.base_position, Eigen::Vector3d::Zero());
}
