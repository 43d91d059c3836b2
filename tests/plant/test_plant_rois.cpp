#include <string>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/plant/plant_rois.h>

#include "plant_test_util.h"

using plantnbv::Box;
using plantnbv::kDefaultPlantCount;
using plantnbv::PartLabel;
using plantnbv::Plant;
using plantnbv::RoiKind;
using plantnbv::Roi;
using plantnbv::test::defaultPlant;

namespace {

/// Whether a vertex of a triangle labelled `label` lies in the box.
bool touches(const Plant& plant, const Box& box, PartLabel label)
{
  const auto& m = plant.mesh;
  for (std::size_t t = 0; t < m.size(); ++t)
    if (m.labels[t] == label)
      for (auto v : m.triangles[t])
        if (box.contains(m.vertices[v].x(), m.vertices[v].y(), m.vertices[v].z()))
          return true;
  return false;
}

} // namespace

TEST(PlantRois, WholePlantAndMainStemAreThePapersBoxesOnTheStemAxis)
{
  for (int i = 0; i < kDefaultPlantCount; ++i) {
    SCOPED_TRACE("plant " + std::to_string(i));
    const Plant& plant = defaultPlant(i);
    const Roi whole = plantnbv::wholePlantRoi(plant);
    const Roi stem = plantnbv::mainStemRoi(plant);
    ASSERT_EQ(whole.size(), 1u);
    ASSERT_EQ(stem.size(), 1u);
    EXPECT_EQ(whole.boxes()[0].name, "whole_plant");
    EXPECT_EQ(stem.boxes()[0].name, "main_stem");
    EXPECT_TRUE(whole.boxes()[0].size.isApprox(Eigen::Vector3d(0.3, 0.3, 0.7)));
    EXPECT_TRUE(stem.boxes()[0].size.isApprox(Eigen::Vector3d(0.05, 0.05, 0.7)));
    const Eigen::Vector3d axis_point = plant.stemPointAtHeight(0.35);
    for (const Roi* roi : {&whole, &stem}) {
      const Eigen::Vector3d c = roi->boxes()[0].center;
      EXPECT_DOUBLE_EQ(c.z(), 0.35);
      EXPECT_NEAR(c.x(), axis_point.x(), 1e-12);
      EXPECT_NEAR(c.y(), axis_point.y(), 1e-12);
      // The slightly curved stem stays near the vertical through the base.
      EXPECT_LT(c.head<2>().norm(), 0.01);
    }
    // Both hold every stem vertex: the stem is inside the paper's ROIs.
    const auto& m = plant.mesh;
    for (std::size_t t = 0; t < m.size(); ++t) {
      if (m.labels[t] != PartLabel::stem)
        continue;
      for (auto v : m.triangles[t]) {
        const auto& p = m.vertices[v];
        ASSERT_TRUE(stem.contains(p.x(), p.y(), p.z())) << p.transpose();
        ASSERT_TRUE(whole.contains(p.x(), p.y(), p.z()));
      }
    }
  }
}

TEST(PlantRois, DefaultLeafNodesAreLowMiddleAndHigh)
{
  for (int i = 0; i < kDefaultPlantCount; ++i) {
    const Plant& plant = defaultPlant(i);
    const auto idx = plantnbv::defaultLeafNodeIndices(plant);
    ASSERT_EQ(idx.size(), 3u);
    EXPECT_LT(idx[0], idx[1]);
    EXPECT_LT(idx[1], idx[2]);
    const int n = static_cast<int>(plant.leafNodeCount());
    EXPECT_LT(idx[0], n / 3);
    EXPECT_GE(idx[1], n / 3);
    EXPECT_LT(idx[1], 2 * n / 3);
    EXPECT_GE(idx[2], 2 * n / 3);
    EXPECT_LT(idx[2], n - 1); // not the crowded apex
  }
  Plant tiny;
  tiny.anatomy.leaves.resize(2);
  EXPECT_EQ(plantnbv::defaultLeafNodeIndices(tiny), (std::vector<int>{0, 1}));
}

TEST(PlantRois, EveryLeafNodeBoxHoldsItsNodeAndTouchesTheStem)
{
  for (int i = 0; i < kDefaultPlantCount; ++i) {
    SCOPED_TRACE("plant " + std::to_string(i));
    const Plant& plant = defaultPlant(i);
    std::vector<int> all(plant.leafNodeCount());
    for (std::size_t k = 0; k < all.size(); ++k)
      all[k] = static_cast<int>(k);
    const Roi roi = plantnbv::leafNodeRoi(plant, all);
    ASSERT_EQ(roi.size(), all.size());
    for (std::size_t k = 0; k < all.size(); ++k) {
      const Box& box = roi.boxes()[k];
      const auto& node = plant.anatomy.leaves[k].node;
      EXPECT_EQ(box.name, "leaf_node_" + std::to_string(k));
      EXPECT_TRUE(box.size.isApprox(Eigen::Vector3d(0.03, 0.03, 0.05)));
      EXPECT_TRUE(box.contains(node.position));
      EXPECT_TRUE(box.contains(node.stem_point));
      EXPECT_TRUE(touches(plant, box, PartLabel::stem)) << "leaf node " << k;
      EXPECT_TRUE(touches(plant, box, PartLabel::petiole)) << "leaf node " << k;
    }
    // The default ROI is the three default nodes.
    const Roi def = plantnbv::leafNodeRoi(plant);
    const auto idx = plantnbv::defaultLeafNodeIndices(plant);
    ASSERT_EQ(def.size(), 3u);
    for (int j = 0; j < 3; ++j)
      EXPECT_EQ(def.boxes()[j].center, plant.anatomy.leaves[idx[j]].node.position);
  }
  EXPECT_THROW(plantnbv::leafNodeRoi(defaultPlant(0), {0, 99}),
               plantnbv::InvalidArgumentError);
  EXPECT_THROW(plantnbv::leafNodeRoi(defaultPlant(0), {-1}),
               plantnbv::InvalidArgumentError);
}

TEST(PlantRois, FruitBoxesHoldTheirTrussFruits)
{
  for (int i = 0; i < kDefaultPlantCount; ++i) {
    SCOPED_TRACE("plant " + std::to_string(i));
    const Plant& plant = defaultPlant(i);
    const Roi roi = plantnbv::fruitRoi(plant);
    ASSERT_EQ(roi.size(), plant.anatomy.trusses.size());
    const auto& m = plant.mesh;
    std::size_t checked = 0;
    for (std::size_t t = 0; t < m.size(); ++t) {
      if (m.labels[t] != PartLabel::fruit)
        continue;
      // Part names are "truss_<t>_fruit_<i>".
      const std::string& name = m.node_names[m.node_ids[t]];
      const std::size_t truss = std::stoul(name.substr(6, name.find('_', 6) - 6));
      ASSERT_LT(truss, roi.size());
      for (auto v : m.triangles[t]) {
        ASSERT_TRUE(roi.boxes()[truss].contains(m.vertices[v].x(), m.vertices[v].y(),
                                                m.vertices[v].z()))
            << name;
      }
      ++checked;
    }
    EXPECT_GT(checked, 0u);
    // The margin grows every side.
    const Roi wide = plantnbv::fruitRoi(plant, 0.01);
    EXPECT_TRUE(wide.boxes()[0].size.isApprox(roi.boxes()[0].size +
                                              Eigen::Vector3d::Constant(0.02)));
  }
  EXPECT_THROW(plantnbv::fruitRoi(defaultPlant(0), -0.01),
               plantnbv::InvalidArgumentError);
  EXPECT_TRUE(plantnbv::fruitRoi(Plant()).empty());
}

TEST(PlantRois, EveryKindHasItsRoi)
{
  const Plant& plant = defaultPlant(5);
  EXPECT_EQ(plantnbv::plantRoi(plant, RoiKind::leaf_nodes).size(), 3u);
  EXPECT_EQ(plantnbv::plantRoi(plant, RoiKind::main_stem).boxes()[0].center,
            plantnbv::mainStemRoi(plant).boxes()[0].center);
  EXPECT_EQ(plantnbv::plantRoi(plant, RoiKind::fruit).size(),
            plant.anatomy.trusses.size());
  EXPECT_THROW(plantnbv::wholePlantRoi(Plant()), plantnbv::InvalidArgumentError);
}
