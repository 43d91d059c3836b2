#include <cmath>
#include <limits>
#include <sstream>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/scenario/placed_plant.h>

#include "scenario_test_util.h"

using namespace plantnbv;
using namespace plantnbv::scenario;
using plantnbv::test::errorOf;
using plantnbv::test::ScenarioFiles;

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

TEST_F(ScenarioFiles, AScansLabelsBeyondOursAreBackgroundWithAWarning)
{
  // Labels 0-6 are ours; a data set's 7 and 9 are read as background, and said so.
  std::string pcd = "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z label\nSIZE 4 4 4 4\n"
                    "TYPE F F F U\nCOUNT 1 1 1 1\nWIDTH 4\nHEIGHT 1\n"
                    "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n";
  for (const int label : {1, 7, 3, 9})
    pcd += "0 0 " + std::to_string(0.1 * label) + " " + std::to_string(label) + "\n";
  PlantSource source;
  source.model = write("scan.pcd", pcd);
  const PlacedPlant placed = makePlacedPlant(source);
  ASSERT_EQ(placed.warnings.size(), 1u);
  EXPECT_EQ(placed.warnings[0],
            "2 points of '" + source.model +
                "' have a label above 6 (ours: 0 unknown to 6 "
                "background; docs/plants.md) and are read as background");
  std::vector<PartLabel> expected = {PartLabel::stem, PartLabel::background,
                                     PartLabel::leaflet, PartLabel::background};
  EXPECT_EQ(placed.plant.scan_labels, expected);
}

TEST_F(ScenarioFiles, APlantSplitIntoSeveralMeshFilesIsOneMeshLabelledByFileName)
{
  // A stem and a leaf in two PLY files (no node names: each file's name stands for its
  // triangles), and an OBJ whose groups name its triangles.
  const auto ply = [](double x0) {
    std::ostringstream s;
    s << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
         "end_header\n"
      << x0 << " 0 0\n"
      << x0 + 0.01 << " 0 0\n"
      << x0 << " 0 0.3\n3 0 1 2\n";
    return s.str();
  };
  PlantSource source;
  source.model = write("stem.ply", ply(0.0));
  source.model_parts = {write("leaf.ply", ply(0.1)),
                        std::string(PLANTNBV_DATA_DIR) + "/fixtures/two_groups.obj"};
  source.labels = "stem=stem,leaflet=leaf";
  source.keep_frame = true;
  const PlacedPlant placed = makePlacedPlant(source);
  const TriangleMesh& mesh = placed.plant.mesh;
  ASSERT_GE(mesh.size(), 3u);
  EXPECT_EQ(mesh.labels[0], PartLabel::stem);
  EXPECT_EQ(mesh.labels[1], PartLabel::leaflet);
  for (std::size_t t = 2; t < mesh.size(); ++t) // the OBJ's groups match no rule
    EXPECT_EQ(mesh.labels[t], PartLabel::unknown);
  EXPECT_EQ(placed.plant.name, "stem");
  EXPECT_NE(placed.description.find("and 2 more files"), std::string::npos);
  EXPECT_TRUE(placed.warnings.empty());

  // A scan cannot be one of several files; parts need a model.
  PlantSource scan = source;
  scan.model_parts = {write("scan.pcd",
                            "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 "
                            "4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 1\nHEIGHT 1\n"
                            "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA "
                            "ascii\n0 0 0\n")};
  EXPECT_NE(errorOf([&] { makePlacedPlant(scan); }).find("scan.pcd"), std::string::npos);
  PlantSource parts_only;
  parts_only.model_parts = {source.model};
  EXPECT_THROW(makePlacedPlant(parts_only), InvalidArgumentError);
}
