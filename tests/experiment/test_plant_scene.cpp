// The plant scene of the experiments: the plant on its support over a floor.
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/plant_scene.h>
#include <plantnbv/plant/plant_model.h>

using namespace plantnbv;

namespace {

/// A vertical 0.4 x 0.4 m square at x = 0, 0.2 m up, labelled stem.
TriangleMesh verticalQuad()
{
  TriangleMesh mesh;
  mesh.vertices = {
      {0.0f, -0.2f, 0.0f}, {0.0f, 0.2f, 0.0f}, {0.0f, 0.2f, 0.4f}, {0.0f, -0.2f, 0.4f}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  mesh.labels = {PartLabel::stem, PartLabel::stem};
  return mesh;
}

std::vector<Eigen::Vector3f> gridPoints(int n, float s)
{
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      points.emplace_back(0.0f, (i - 0.5f * (n - 1)) * s, (j - 0.5f * (n - 1)) * s);
  return points;
}

} // namespace

TEST(PlantScene, HasFloorAndSupportByDefault)
{
  Plant plant = plantFromMesh(verticalQuad(), "quad");
  posePlant(plant, Eigen::Vector3d(1.0, 0.0, 0.8), 0.0);
  SensorScene::Ptr scene = makePlantScene(plant);
  EXPECT_TRUE(scene->isCommitted());
  EXPECT_EQ(scene->geometryCount(), 3u);
  EXPECT_EQ(scene->triangleCount(), 2u + 2u + 12u);

  const std::vector<TriangleMesh> background = plantSceneBackground(plant);
  ASSERT_EQ(background.size(), 2u); // floor, then support
  EXPECT_EQ(background[0].size(), 2u);
  EXPECT_EQ(background[1].size(), 12u);
  for (const TriangleMesh& part : background)
    for (PartLabel label : part.labels)
      EXPECT_EQ(label, PartLabel::background);

  PlantSceneConfig bare;
  bare.floor = false;
  bare.support = false;
  EXPECT_EQ(makePlantScene(plant, bare)->geometryCount(), 1u);
  EXPECT_TRUE(plantSceneBackground(plant, bare).empty());

  PlantSceneConfig bad;
  bad.floor_half_size_m = -1.0;
  EXPECT_THROW(makePlantScene(plant, bad), InvalidArgumentError);
  bad = PlantSceneConfig();
  bad.surfels.spacing_neighbours = 0;
  EXPECT_THROW(plantSceneBackground(plant, bad), InvalidArgumentError);
  EXPECT_THROW(makePlantScene(Plant()), InvalidArgumentError);

  // A scan plant becomes surfels.
  Plant scan = plantFromScan(gridPoints(10, 0.005f), {}, "scan");
  posePlant(scan, Eigen::Vector3d(1.0, 0.0, 0.8), 0.0);
  SensorScene::Ptr scan_scene = makePlantScene(scan, bare);
  EXPECT_EQ(scan_scene->surfelCount(), 100u);
  EXPECT_EQ(scan_scene->triangleCount(), 0u);
}

TEST(PlantScene, NeighboursStandOnTheirOwnSupportsAsBackground)
{
  Plant plant = plantFromMesh(verticalQuad(), "quad");
  posePlant(plant, Eigen::Vector3d(1.0, 0.0, 0.8), 0.0);
  auto left = std::make_shared<Plant>(plantFromMesh(verticalQuad(), "left"));
  posePlant(*left, Eigen::Vector3d(1.0, 0.4, 0.8), 0.0);
  auto right = std::make_shared<Plant>(plantFromMesh(verticalQuad(), "right"));
  posePlant(*right, Eigen::Vector3d(1.0, -0.4, 0.8), 0.0);
  const NeighbourPlants neighbours{left, right};

  const std::vector<TriangleMesh> background =
      plantSceneBackground(plant, {}, neighbours);
  // Floor, the plant's support, then each neighbour and its support.
  ASSERT_EQ(background.size(), 6u);
  EXPECT_EQ(background[2].size(), 2u);
  EXPECT_EQ(background[2].vertices, left->mesh.vertices);
  EXPECT_EQ(background[3].size(), 12u);
  for (const TriangleMesh& part : background)
    for (PartLabel label : part.labels)
      EXPECT_EQ(label, PartLabel::background);
  // The neighbour itself keeps its labels: the scene copies it.
  EXPECT_EQ(left->mesh.labels[0], PartLabel::stem);
  EXPECT_EQ(makePlantScene(plant, {}, 1, neighbours)->triangleCount(),
            2u + 2u + 12u + 2 * (2u + 12u));

  // A scan cannot stand beside it: the sensor scene takes meshes as neighbours.
  auto scan = std::make_shared<Plant>(plantFromScan(gridPoints(3, 0.01f), {}, "scan"));
  EXPECT_THROW(plantSceneBackground(plant, {}, {scan}), InvalidArgumentError);
}
