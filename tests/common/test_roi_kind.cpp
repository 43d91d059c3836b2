#include <gtest/gtest.h>

#include <plantnbv/common/roi_kind.h>

using plantnbv::RoiKind;

TEST(RoiKind, OneNameEachThatReadsBack)
{
  const char* names[] = {"whole_plant", "main_stem", "leaf_nodes", "fruit"};
  for (std::size_t i = 0; i < plantnbv::kRoiKinds.size(); ++i) {
    const RoiKind kind = plantnbv::kRoiKinds[i];
    EXPECT_STREQ(plantnbv::roiKindName(kind), names[i]);
    EXPECT_EQ(plantnbv::roiKindFromName(names[i]), kind);
  }
  EXPECT_EQ(plantnbv::roiKindNames(), "whole_plant, main_stem, leaf_nodes, fruit");
}

TEST(RoiKind, FormerSpellingsStillRead)
{
  // The CLI's and older campaign files' spellings, and the old name of the fruit ROI.
  EXPECT_EQ(plantnbv::roiKindFromName("whole-plant"), RoiKind::whole_plant);
  EXPECT_EQ(plantnbv::roiKindFromName("main-stem"), RoiKind::main_stem);
  EXPECT_EQ(plantnbv::roiKindFromName("leaf-nodes"), RoiKind::leaf_nodes);
  EXPECT_EQ(plantnbv::roiKindFromName("fruits"), RoiKind::fruit);
  for (const char* other : {"leaves", "", "Whole_plant", "leaf nodes", "fruit.yaml"})
    EXPECT_FALSE(plantnbv::roiKindFromName(other)) << other;
}

TEST(RoiKind, TitlesAndBoxScoring)
{
  EXPECT_STREQ(plantnbv::roiKindTitle(RoiKind::leaf_nodes), "Leaf nodes");
  EXPECT_STREQ(plantnbv::roiKindTitle(RoiKind::fruit), "Fruit");
  // Any spelling of a kind gives its title; any other name stays as it is.
  EXPECT_EQ(plantnbv::roiTitle("leaf-nodes"), "Leaf nodes");
  EXPECT_EQ(plantnbv::roiTitle("fruits"), "Fruit");
  EXPECT_EQ(plantnbv::roiTitle("model_rois"), "model_rois");
  EXPECT_EQ(plantnbv::roiTitle("nodes.yaml"), "nodes.yaml");
  EXPECT_FALSE(plantnbv::roiKindScoresBoxesApart(RoiKind::whole_plant));
  EXPECT_FALSE(plantnbv::roiKindScoresBoxesApart(RoiKind::main_stem));
  EXPECT_TRUE(plantnbv::roiKindScoresBoxesApart(RoiKind::leaf_nodes));
  EXPECT_TRUE(plantnbv::roiKindScoresBoxesApart(RoiKind::fruit));
}
