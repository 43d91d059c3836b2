#include <cmath>
#include <limits>
#include <sstream>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/scenario/placed_plant.h>

#include "collada_text.h"
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
  // Labels 0-7 are ours; a data set's 8 and 9 are read as background, and said so.
  std::string pcd = "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z label\nSIZE 4 4 4 4\n"
                    "TYPE F F F U\nCOUNT 1 1 1 1\nWIDTH 4\nHEIGHT 1\n"
                    "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 4\nDATA ascii\n";
  for (const int label : {1, 8, 3, 9})
    pcd += "0 0 " + std::to_string(0.1 * label) + " " + std::to_string(label) + "\n";
  PlantSource source;
  source.model = write("scan.pcd", pcd);
  const PlacedPlant placed = makePlacedPlant(source);
  ASSERT_EQ(placed.warnings.size(), 1u);
  EXPECT_EQ(placed.warnings[0], "2 points of '" + source.model +
                                    "' have a label above 7 (ours: 0 unknown to 7 "
                                    "flower; docs/plants.md) and are read as background");
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

TEST_F(ScenarioFiles, AForeignModelGetsFlowerLabelsFruitBoxesAndWarnings)
{
  // A Gazebo-style tomato in centimetres, without <unit>: a stem triangle, a flower
  // told apart only by its material, and two fruits (each two triangles sharing an edge,
  // written as separate vertices, as exporters do).
  const std::string obj = "o Branch_0\n"
                          "v 0 0 0\nv 1 0 0\nv 0 0 100\n"
                          "f 1 2 3\n"
                          "o Plant_1\nusemtl Blossom_yellow\n"
                          "v 0 10 90\nv 2 10 90\nv 0 12 92\n"
                          "f 4 5 6\n"
                          "o Fruit_a\n"
                          "v 10 0 20\nv 14 0 20\nv 10 4 24\n"
                          "v 14 0 20\nv 10 4 24\nv 14 4 20\n"
                          "f 7 8 9\nf 10 11 12\n"
                          "o Fruit_b\n"
                          "v -10 0 50\nv -6 0 50\nv -10 4 54\n"
                          "f 13 14 15\n";
  PlantSource source;
  source.model = write("gazebo_tomato.obj", obj);
  source.labels = "stem=Branch.*,fruit=Fruit.*,flower=Blossom.*";
  source.scale = 0.01;
  source.keep_frame = true;
  // Boxes as the ROI viewpoint planner writes them: one on the plant, one 10 m away.
  source.rois =
      write("rois.yaml", "- {min: [-0.01, -0.01, 0.0], max: [0.01, 0.01, 1.0]}\n"
                         "- {name: far, min: [10, 10, 10], max: [11, 11, 11]}\n");
  const PlacedPlant placed = makePlacedPlant(source);
  const auto& labels = placed.plant.mesh.labels;
  EXPECT_EQ(labels,
            (std::vector<PartLabel>{PartLabel::stem, PartLabel::flower, PartLabel::fruit,
                                    PartLabel::fruit, PartLabel::fruit}));
  // One box per fruit, lowest first, 1 um beyond its triangles; metres from the scale.
  const Roi* fruit = placed.roi(RoiKind::fruit);
  ASSERT_NE(fruit, nullptr);
  ASSERT_EQ(fruit->size(), 2u);
  const Box& a = fruit->boxes()[0];
  EXPECT_EQ(a.name, "fruit_0");
  EXPECT_NEAR(a.min().x(), 0.10 - 1e-6, 3e-8);
  EXPECT_NEAR(a.max().x(), 0.14 + 1e-6, 3e-8);
  EXPECT_NEAR(a.min().z(), 0.20 - 1e-6, 3e-8);
  EXPECT_NEAR(a.max().z(), 0.24 + 1e-6, 3e-8);
  EXPECT_EQ(fruit->boxes()[1].name, "fruit_1");
  EXPECT_NEAR(fruit->boxes()[1].center.x(), -0.08, 1e-7);
  // The far box is said; the scale was given, so no word on units.
  ASSERT_EQ(placed.warnings.size(), 1u);
  EXPECT_EQ(
      placed.warnings[0],
      "ROI box 1 'far' of '" + source.rois +
          "' does not overlap the plant: ROI files are in the world frame the plant "
          "stands in (boxes in a model file's own coordinates need --keep-frame)");

  // A Collada file without <unit> is read in metres, and said so.
  const std::string dae = plantnbv::test::colladaDocument(
      "<up_axis>Z_UP</up_axis>",
      plantnbv::test::colladaTriangleGeometry("id=\"g\"", "0 0 0  1 0 0  0 0 2"), "",
      R"(<node id="n" name="Stem"><instance_geometry url="#g"/></node>)");
  PlantSource bare;
  bare.model = write("bare.dae", dae);
  const PlacedPlant metres = makePlacedPlant(bare);
  ASSERT_EQ(metres.warnings.size(), 1u);
  EXPECT_EQ(metres.warnings[0], "'" + bare.model +
                                    "' declares no <unit>: read in metres (Collada's "
                                    "default); give the model's scale if it is in other "
                                    "units");
  EXPECT_NEAR(metres.plant.anatomy.top_height_m, 2.0, 1e-6);
  bare.scale = 0.01;
  const PlacedPlant centimetres = makePlacedPlant(bare);
  EXPECT_TRUE(centimetres.warnings.empty());
  EXPECT_NEAR(centimetres.plant.anatomy.top_height_m, 0.02, 1e-8);
  // No fruit labels, no fruit ROI.
  EXPECT_EQ(centimetres.roi(RoiKind::fruit), nullptr);

  PlantSource seeded;
  seeded.seed = 1;
  seeded.scale = 0.01;
  EXPECT_EQ(errorOf([&] { makePlacedPlant(seeded); }),
            "plant source: labels, scale, up axis and keep_frame belong to a model file");
  seeded.scale = 0.0;
  seeded.up_axis = io::MeshLoadOptions::UpAxis::y;
  EXPECT_EQ(errorOf([&] { makePlacedPlant(seeded); }),
            "plant source: labels, scale, up axis and keep_frame belong to a model file");
  bare.scale = -1.0;
  EXPECT_EQ(errorOf([&] { makePlacedPlant(bare); }),
            "plant source: the scale must be metres per file unit, a finite number > 0, "
            "or 0 for the file's own unit");
}

TEST_F(ScenarioFiles, AYUpModelOrScanStandsOnItsYAxis)
{
  // 1 m along y, 10 cm along z, in centimetres, as Blender exports OBJ by default.
  PlantSource source;
  source.model = write("y_up.obj", "o Stem\nv 0 0 0\nv 0 100 0\nv 0 0 10\nf 1 2 3\n");
  // Read in metres and z up, it is 10 m tall and 100 m across: said, with both remedies.
  const PlacedPlant wrong = makePlacedPlant(source);
  ASSERT_EQ(wrong.warnings.size(), 1u);
  EXPECT_EQ(
      wrong.warnings[0],
      "'" + source.model +
          "' is 10 m tall and 100 m across, larger than a plant: its unit may be "
          "wrong (read in its file's unit; give the model's scale, 0.01 for "
          "centimetres, 0.001 for millimetres); if it lies on its side, give its up "
          "axis too (y for an OBJ from Blender)");
  source.scale = 0.01;
  const PlacedPlant lying = makePlacedPlant(source);
  EXPECT_TRUE(lying.warnings.empty()); // a plausible size: nothing to say
  EXPECT_NEAR(lying.plant.anatomy.top_height_m, 0.1, 1e-7);
  source.up_axis = io::MeshLoadOptions::UpAxis::y;
  const PlacedPlant upright = makePlacedPlant(source);
  EXPECT_NEAR(upright.plant.anatomy.top_height_m, 1.0, 1e-6);
  // Millimetres given to a file in centimetres: 1 mm tall, and the scale is named.
  source.scale = 0.00001;
  const PlacedPlant tiny = makePlacedPlant(source);
  ASSERT_EQ(tiny.warnings.size(), 1u);
  EXPECT_NE(
      tiny.warnings[0].find("smaller than a plant: its unit may be wrong (scale 1e-05 "
                            "metres per file unit given)"),
      std::string::npos)
      << tiny.warnings[0];
  source.scale = 0.01;
  EXPECT_EQ(upright.description, "model " + source.model + ", y up");
  // A scan turns the same way: its file's y becomes our z, its z our -y.
  source.model =
      write("y_up.pcd", "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
                        "COUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 "
                        "0\nPOINTS 2\nDATA ascii\n0 0 0\n0 100 10\n");
  const PlacedPlant scan = makePlacedPlant(source);
  EXPECT_NEAR(scan.plant.anatomy.top_height_m, 1.0, 1e-6);
  ASSERT_EQ(scan.plant.scan_points.size(), 2u);
  EXPECT_NEAR(std::abs(scan.plant.scan_points[1].y() - scan.plant.scan_points[0].y()),
              0.1, 1e-6);
}

TEST(PlacedPlant, RowNeighboursStandAcrossTheFacingWithTheNextSeeds)
{
  PlantSource target;
  target.seed = 9;
  target.yaw_deg = 300.0;
  target.rois = std::string(PLANTNBV_DATA_DIR) + "/fixtures/rois.yaml";
  // The default sector faces the robot at the origin: azimuth pi from (1, 0, 0.8), so
  // the row runs along y.
  const std::vector<PlacedPlant> row = rowNeighbours(target, 0.25, M_PI);
  ASSERT_EQ(row.size(), 2u);
  EXPECT_EQ(*row[0].source.seed, 0u); // the default set, cyclically
  EXPECT_EQ(*row[1].source.seed, 1u);
  EXPECT_NEAR(row[0].plant.base_position.x(), 1.0, 1e-12);
  EXPECT_NEAR(row[0].plant.base_position.y(), 0.25, 1e-12);
  EXPECT_NEAR(row[1].plant.base_position.y(), -0.25, 1e-12);
  EXPECT_EQ(row[0].plant.base_position.z(), 0.8);
  EXPECT_EQ(row[0].source.yaw_deg, 60.0);   // 300 + 120, within +-360
  EXPECT_EQ(row[1].source.yaw_deg, -180.0); // 300 + 240 = 540, the same turn as -180
  EXPECT_TRUE(row[0].model_rois.empty());   // the target's boxes stay the target's

  // A model's neighbours are the same model.
  PlantSource model;
  model.model = std::string(PLANTNBV_DATA_DIR) + "/fixtures/plant_cm_zup.dae";
  const std::vector<PlacedPlant> models = rowNeighbours(model, 0.4, M_PI / 2);
  ASSERT_EQ(models.size(), 2u);
  EXPECT_EQ(models[1].plant.mesh.size(), makePlacedPlant(model).plant.mesh.size());
  EXPECT_NEAR(models[0].plant.base_position.x(), 1.4, 1e-12); // facing +y: row along x

  EXPECT_EQ(errorOf([&] { rowNeighbours(target, 0.0, M_PI); }),
            "row: the spacing must be a finite number of metres > 0");
  model.keep_frame = true;
  EXPECT_EQ(errorOf([&] { rowNeighbours(model, 0.4, M_PI); }),
            "row: a plant with its file frame kept has no base to place neighbours from");
}
