#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/scenario/placed_plant.h>

#include "scenario_test_util.h"

using namespace plantnbv;
using namespace plantnbv::scenario;
using plantnbv::test::errorOf;

TEST(PlacedPlant, AGeneratedPlantStandsAtItsBaseWithItsRois)
{
  PlantSource source;
  source.seed = 3;
  source.yaw_deg = 30.0;
  source.base = Eigen::Vector3d(1.2, -0.1, 0.5);
  const PlacedPlant placed = makePlacedPlant(source);
  EXPECT_EQ(placed.plant.base_position, source.base);
  EXPECT_NEAR(placed.plant.yaw_rad, M_PI / 6.0, 1e-15);
  EXPECT_EQ(placed.source.seed, 3u);
  EXPECT_NE(placed.description.find("seed 3"), std::string::npos);
  ASSERT_NE(placed.roi(RoiKind::whole_plant), nullptr);
  ASSERT_NE(placed.roi(RoiKind::leaf_nodes), nullptr);
  EXPECT_EQ(placed.roi(RoiKind::leaf_nodes)->size(), 3u);
  // The whole-plant box is centred on the stem 0.35 m above the base.
  EXPECT_NEAR(placed.roi(RoiKind::whole_plant)->boxes()[0].center.z(), 0.85, 1e-12);
  EXPECT_TRUE(placed.model_rois.empty());
}

TEST(PlacedPlant, AModelGetsItsBoundingBoxAndItsRoiFile)
{
  PlantSource source;
  source.model = std::string(PLANTNBV_DATA_DIR) + "/fixtures/plant_cm_zup.dae";
  source.rois = std::string(PLANTNBV_DATA_DIR) + "/fixtures/rois.yaml";
  const PlacedPlant placed = makePlacedPlant(source);
  EXPECT_EQ(placed.rois.size(), 1u); // whole_plant only
  ASSERT_NE(placed.roi(RoiKind::whole_plant), nullptr);
  EXPECT_EQ(placed.roi(RoiKind::main_stem), nullptr);
  EXPECT_EQ(placed.model_rois.size(), 3u);
  EXPECT_EQ(placed.plant.base_position, source.base);
}

TEST(PlacedPlant, BadSourcesAreRefusedNamingTheField)
{
  EXPECT_EQ(errorOf([] { makePlacedPlant(PlantSource()); }),
            "plant source: give a seed or a model file");
  PlantSource both;
  both.seed = 1;
  both.model = "x.dae";
  EXPECT_EQ(errorOf([&] { makePlacedPlant(both); }),
            "plant source: a seed and a model file; give one");
  PlantSource labels;
  labels.seed = 1;
  labels.labels = "stem=.*";
  EXPECT_NE(errorOf([&] { makePlacedPlant(labels); }).find("belong to a model file"),
            std::string::npos);
  // The user's own boxes go with a generated plant too: the level model_rois.
  PlantSource own_boxes;
  own_boxes.seed = 1;
  own_boxes.rois = std::string(PLANTNBV_DATA_DIR) + "/fixtures/rois.yaml";
  EXPECT_EQ(makePlacedPlant(own_boxes).model_rois.size(), 3u);
  PlantSource staged;
  staged.model = "x.dae";
  staged.stage = 0.5;
  EXPECT_NE(errorOf([&] { makePlacedPlant(staged); }).find("belong to a generated plant"),
            std::string::npos);
  PlantSource far;
  far.seed = 1;
  far.base.y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(errorOf([&] { makePlacedPlant(far); }).find("base"), std::string::npos);
  PlantSource turned;
  turned.seed = 1;
  turned.yaw_deg = std::numeric_limits<double>::infinity();
  EXPECT_NE(errorOf([&] { makePlacedPlant(turned); }).find("yaw"), std::string::npos);
  PlantSource missing;
  missing.model = "/nonexistent/plant.dae";
  EXPECT_THROW(makePlacedPlant(missing), Error);
}
