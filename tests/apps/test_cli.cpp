// The plantnbv tool as a user runs it: exit codes, one-line errors, and results.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <octomap/OcTree.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/io/cloud_io.h>
#include <plantnbv/io/frames_folder.h>
#include <plantnbv/io/mesh_io.h>
#include <plantnbv/io/roi_io.h>
#include <plantnbv/octree/octree_conversion.h>

#include "cli_fixture.h"
#include "read_csv.h"

namespace fs = std::filesystem;

using plantnbv::test::CliTest;
using plantnbv::test::expectOneLineError;
using plantnbv::test::kFixtures;
using plantnbv::test::kTool;
using plantnbv::test::readCsv;
using plantnbv::test::slurp;
using plantnbv::test::ToolRun;

TEST_F(CliTest, HelpAndVersionExitZero)
{
  const ToolRun help = run("--help");
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("sample"), std::string::npos);
  EXPECT_NE(help.out.find("eval"), std::string::npos);
  EXPECT_EQ(run("eval --help").code, 0);
  // The version and the commit the tool was built from (this checkout's).
  const ToolRun version = run("--version");
  EXPECT_EQ(version.code, 0);
  EXPECT_TRUE(std::regex_match(version.out,
                               std::regex("plantnbv [0-9]+\\.[0-9]+\\.[0-9]+ \\(commit "
                                          "([0-9a-f]{12}(\\+dirty)?|unknown)\\)\n")))
      << version.out;
  const std::string head =
      plantnbv::test::commandOutput("git -C " + std::string(PLANTNBV_DATA_DIR) +
                                    " rev-parse --short=12 HEAD 2>/dev/null");
  if (!head.empty()) { // a git checkout
    EXPECT_NE(version.out.find("(commit " + head.substr(0, 12)), std::string::npos)
        << version.out << " at " << head << " (built before the last commit? rebuild)";
  }
}

TEST_F(CliTest, SampleWritesTheRequestedPointsSeeded)
{
  const std::string mesh = kFixtures + "/plant_like.ply";
  ASSERT_EQ(
      run("sample --mesh " + mesh + " --points 5000 --seed 3 -o " + path("a.pcd")).code,
      0);
  ASSERT_EQ(run("sample --mesh " + mesh + " --points 5000 --seed 3 --labels -o " +
                path("b.ply"))
                .code,
            0);
  pcl::PointCloud<pcl::PointXYZ> a;
  pcl::PointCloud<pcl::PointXYZL> b;
  plantnbv::io::loadCloud(path("a.pcd"), a);
  plantnbv::io::loadCloud(path("b.ply"), b);
  ASSERT_EQ(a.size(), 5000u);
  ASSERT_EQ(b.size(), 5000u);
  bool labelled = false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].getVector3fMap(), b[i].getVector3fMap()); // same seed, same points
    labelled = labelled || b[i].label != 0;
  }
  EXPECT_TRUE(labelled);
}

TEST_F(CliTest, EvalOfAShiftedCloudGivesTheShiftAsChamferAndJson)
{
  // Every point of B is 1/256 m from its twin in A and farther from the others: the
  // Chamfer distance is 2/256 m; rho 5 mm counts all, rho = 1/256 m none (strict <).
  writeLattice("a.pcd", 0.0f);
  writeLattice("b.pcd", 1.0f / 256);
  ToolRun r = run("eval --json --reference " + path("a.pcd") + " --reconstruction " +
                  path("b.pcd") + " --rho 0.005");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"f1\": 1.0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"reference_points\": 16"), std::string::npos) << r.out;
  const auto at = r.out.find("\"chamfer\": ");
  ASSERT_NE(at, std::string::npos);
  EXPECT_EQ(std::stod(r.out.substr(at + 11)), 2.0 / 256);
  r = run("eval --json --reference " + path("a.pcd") + " --reconstruction " +
          path("b.pcd") + " --rho 0.00390625");
  ASSERT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("\"f1\": 0.0"), std::string::npos) << r.out;
  r = run("eval --reference " + path("a.pcd") + " --reconstruction " + path("b.pcd"));
  ASSERT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("F1"), std::string::npos);
}

TEST_F(CliTest, EvalReadsMeshesAndOctreesAndCropsToAnRoi)
{
  const std::string mesh = kFixtures + "/plant_like.ply";
  // A mesh against itself (same seed): identical ground truth, a perfect score.
  ToolRun r = run("eval --json --reference " + mesh + " --reconstruction " + mesh);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"f1\": 1.0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"chamfer\": 0.0"), std::string::npos) << r.out;

  // The lattice as an octree at 1 cm: 16 distinct voxels whose centres lie within 6.2 mm
  // of their points, so within rho = 1 cm.
  writeLattice("a.pcd", 0.0f);
  pcl::PointCloud<pcl::PointXYZ> a;
  plantnbv::io::loadCloud(path("a.pcd"), a);
  plantnbv::writeOcTree(path("a.bt"), *plantnbv::cloudToOcTree(a, 0.01));
  r = run("eval --json --reference " + path("a.pcd") + " --reconstruction " +
          path("a.bt") + " --rho 0.01");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"reconstruction_points\": 16"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"f1\": 1.0"), std::string::npos) << r.out;

  // An ROI holding the first lattice row only (x = 1/512 m): 4 points each.
  write("row.yaml",
        "boxes:\n  - center: [0.002, 0.025, 1.0]\n    size: [0.002, 0.06, 0.01]\n");
  r = run("eval --json --reference " + path("a.pcd") + " --reconstruction " +
          path("a.pcd") + " --roi " + path("row.yaml"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"reference_points\": 4"), std::string::npos) << r.out;
  // An ROI that holds nothing: a defined result and a warning, not a failure.
  write("far.yaml", "boxes:\n  - center: [5, 5, 5]\n    size: [0.1, 0.1, 0.1]\n");
  r = run("eval --json --reference " + path("a.pcd") + " --reconstruction " +
          path("a.pcd") + " --roi " + path("far.yaml"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"valid\": false"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"chamfer\": null"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("warning"), std::string::npos);
}

TEST_F(CliTest, PlantWritesMeshAnatomyAndRoisInTheWorldFrame)
{
  const ToolRun r = run("plant --seed 2 --yaw-deg 90 -o " + path("p"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("tomato_seed2"), std::string::npos) << r.out;
  const plantnbv::TriangleMesh mesh = plantnbv::io::loadMesh(path("p/plant.ply"));
  ASSERT_EQ(mesh.labels.size(), mesh.size());
  Eigen::Vector3f lo, hi;
  mesh.bounds(lo, hi);
  EXPECT_NEAR(lo.z(), 0.8f, 1e-4f); // the paper's base height
  const plantnbv::Roi all = plantnbv::io::loadRoi(path("p/rois.yaml"));
  const plantnbv::Roi stem = plantnbv::io::loadRoi(path("p/roi_main_stem.yaml"));
  const plantnbv::Roi nodes = plantnbv::io::loadRoi(path("p/roi_leaf_nodes.yaml"));
  ASSERT_EQ(stem.size(), 1u);
  EXPECT_EQ(nodes.size(), 3u);
  EXPECT_GE(all.size(), 5u);
  EXPECT_NEAR(stem.boxes()[0].center.z(), 1.15, 1e-9); // Table 1: 0.35 m above the base
  EXPECT_NE(slurp(path("p/anatomy.json")).find("\"plantnbv-anatomy\""),
            std::string::npos);
}

TEST_F(CliTest, PlantLoadsAModelInCentimetresAndLabelsItByName)
{
  const ToolRun r =
      run("plant --model " + kFixtures +
          "/plant_cm_zup.dae --labels stem=Stem,leaflet=Leaf.* -o " + path("m"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("height 0.500 m"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("stem 12, leaflet 4"), std::string::npos) << r.out;
  const plantnbv::TriangleMesh mesh = plantnbv::io::loadMesh(path("m/plant.ply"));
  Eigen::Vector3f lo, hi;
  mesh.bounds(lo, hi);
  EXPECT_NEAR(hi.z() - lo.z(), 0.5f, 1e-5f);
  EXPECT_NEAR(lo.z(), 0.8f, 1e-6f);
}

TEST_F(CliTest, PlantKeepsAScannedCloudAsPoints)
{
  // A labelled scan: samples of the fixture mesh, then placed and turned like a plant.
  ASSERT_EQ(run("sample --mesh " + kFixtures +
                "/plant_like.ply --points 3000 --labels -o " + path("scan.ply"))
                .code,
            0);
  const ToolRun r =
      run("plant --model " + path("scan.ply") + " --yaw-deg 30 -o " + path("s"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("3000 scan points"), std::string::npos) << r.out;
  pcl::PointCloud<pcl::PointXYZL> placed;
  plantnbv::io::loadCloud(path("s/plant.pcd"), placed);
  ASSERT_EQ(placed.size(), 3000u);
  float min_z = placed[0].z;
  for (const auto& p : placed)
    min_z = std::min(min_z, p.z);
  EXPECT_NEAR(min_z, 0.8f, 1e-5f);
  expectOneLineError(
      run("plant --model " + path("scan.ply") + " --labels stem=.* -o " + path("t")), 1,
      "node names");
}

TEST_F(CliTest, PlantSnapshotIsAPortraitPngEvenWithoutADisplay)
{
  // ctest runs without DISPLAY: the tool re-runs itself under xvfb-run.
  const ToolRun r =
      run("plant --seed 0 -o " + path("p") + " --snapshot " + path("p.png"));
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream png(path("p.png"), std::ios::binary);
  unsigned char header[24] = {};
  png.read(reinterpret_cast<char*>(header), sizeof header);
  ASSERT_TRUE(png.good());
  EXPECT_EQ(std::string(reinterpret_cast<char*>(header) + 1, 3), "PNG");
  const auto be32 = [&](int at) {
    return (header[at] << 24) | (header[at + 1] << 16) | (header[at + 2] << 8) |
           header[at + 3];
  };
  EXPECT_EQ(be32(16), 900);  // width
  EXPECT_EQ(be32(20), 1200); // height
  // A blank image compresses to a few kB; a rendered plant does not.
  EXPECT_GT(fs::file_size(path("p.png")), 50000u);
}

TEST_F(CliTest, CaptureWritesTheViewItsDepthAndAMap)
{
  // A small custom camera keeps the test fast; the plant seen from the paper's v0.
  const ToolRun r = run(
      "capture --plant 2 --intrinsics 160x120:114.25,114.25,79.5,59.5 -o " +
      path("view.pcd") + " --depth " + path("depth.png") + " --map " + path("map.bt"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, ""); // nothing from OctoMap's writer either
  pcl::PointCloud<pcl::PointXYZL> view;
  plantnbv::io::loadCloud(path("view.pcd"), view);
  ASSERT_EQ(view.width, 160u);
  ASSERT_EQ(view.height, 120u);
  std::size_t plant = 0, background = 0, none = 0;
  for (const auto& p : view) {
    if (!std::isfinite(p.x))
      ++none;
    else if (p.label == 6) // background: floor and support
      ++background;
    else
      ++plant;
  }
  EXPECT_GT(plant, 0u);
  EXPECT_GT(background, 0u);
  EXPECT_GT(none, 0u); // above the horizon
  EXPECT_NE(r.out.find(std::to_string(plant) + " on the plant"), std::string::npos)
      << r.out;

  // The PNG: 16-bit grey of the camera's size (IHDR at byte 16: width, height, depth 16,
  // colour type 0).
  const std::string png = slurp(path("depth.png"));
  ASSERT_GT(png.size(), 26u);
  auto be32 = [&](std::size_t at) {
    return (std::uint32_t(std::uint8_t(png[at])) << 24) |
           (std::uint32_t(std::uint8_t(png[at + 1])) << 16) |
           (std::uint32_t(std::uint8_t(png[at + 2])) << 8) | std::uint8_t(png[at + 3]);
  };
  EXPECT_EQ(be32(16), 160u);
  EXPECT_EQ(be32(20), 120u);
  EXPECT_EQ(png[24], 16);
  EXPECT_EQ(png[25], 0);

  // The map has the plant's points within its range (0.75 m from v0) as occupied
  // voxels, and nothing at those beyond.
  const auto tree = plantnbv::readOcTree(path("map.bt"));
  ASSERT_TRUE(tree);
  EXPECT_DOUBLE_EQ(tree->getResolution(), 0.003);
  const Eigen::Vector3f v0(0.646f, 0.353f, 1.383f);
  std::size_t in_range = 0, occupied = 0, far_known = 0;
  for (const auto& p : view)
    if (std::isfinite(p.x) && p.label != 6) {
      const auto* node = tree->search(p.x, p.y, p.z);
      if ((p.getVector3fMap() - v0).norm() <= 0.75f) {
        ++in_range;
        occupied += node && tree->isNodeOccupied(node);
      } else {
        far_known += node != nullptr;
      }
    }
  EXPECT_GT(in_range, plant / 2);
  EXPECT_EQ(far_known, 0u);
  EXPECT_EQ(occupied, in_range);
}

namespace {

/// A fast trial config: a 160 x 120 camera with the L515's field of view, 32 x 24 rays.
const char* kSmallTrial = "camera: 160x120:114.25,114.25,79.5,59.5\n"
                          "gain: {rays_x: 32, rays_y: 24}\n";

} // namespace

TEST_F(CliTest, ReconstructWritesStepsSummaryMapAndReconstruction)
{
  write("small.yaml", kSmallTrial);
  const ToolRun r =
      run("reconstruct --plant 0 --planner nbv --attention leaf-nodes --views 3 "
          "--config " +
          path("small.yaml") + " -o " + path("t"));
  ASSERT_EQ(r.code, 0) << r.err;
  // A title, one line per view, views to reach F1 0.8 / 0.9, what was written.
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 6) << r.out;
  EXPECT_NE(r.out.find("views to reach F1 0.8 / 0.9: whole_plant "), std::string::npos);
  EXPECT_NE(r.out.find("view  2"), std::string::npos) << r.out;

  const auto rows = readCsv(slurp(path("t/steps.csv")));
  ASSERT_EQ(rows.size(), 4u);
  const std::vector<std::string>& header = rows[0];
  for (const char* column :
       {"view", "gain", "plan_ms", "capture_ms", "insert_ms", "whole_plant_precision",
        "whole_plant_recall", "whole_plant_f1", "whole_plant_chamfer", "main_stem_f1",
        "leaf_nodes_f1"})
    EXPECT_NE(std::find(header.begin(), header.end(), column), header.end()) << column;
  for (std::size_t i = 1; i < rows.size(); ++i)
    ASSERT_EQ(rows[i].size(), header.size()) << i;
  EXPECT_EQ(rows[1][0], "0");
  EXPECT_EQ(rows[1][8], ""); // no gain for v0
  EXPECT_GT(std::stod(rows[3][8]), 0.0);

  const auto summary = nlohmann::json::parse(slurp(path("t/summary.json")));
  EXPECT_EQ(summary["config"]["planner"], "nbv");
  EXPECT_EQ(summary["config"]["candidates"], 27);
  EXPECT_EQ(summary["totals"]["views"], 3);
  ASSERT_TRUE(summary["levels"].contains("leaf_nodes"));
  EXPECT_TRUE(summary["levels"]["leaf_nodes"].contains("views_to_f1_0.8"));
  const std::string f1 =
      rows[3][std::find(header.begin(), header.end(), "whole_plant_f1") - header.begin()];
  EXPECT_DOUBLE_EQ(summary["levels"]["whole_plant"]["final_f1"].get<double>(),
                   std::stod(f1));

  pcl::PointCloud<pcl::PointXYZ> reconstruction;
  plantnbv::io::loadCloud(path("t/reconstruction.pcd"), reconstruction);
  EXPECT_EQ(std::to_string(reconstruction.size()), rows[3][15]); // occupied_voxels
  const auto tree = plantnbv::readOcTree(path("t/map.bt"));
  ASSERT_TRUE(tree);
}

TEST_F(CliTest, ReconstructIsTheSameOnOneAndTwoThreads)
{
  write("small.yaml", kSmallTrial);
  const std::string common =
      "reconstruct --plant 1 --yaw-deg 60 --planner random --seed 5 "
      "--views 3 --config " +
      path("small.yaml");
  ASSERT_EQ(run(common + " --threads 1 -o " + path("a")).code, 0);
  ASSERT_EQ(run(common + " --threads 2 -o " + path("b")).code, 0);
  auto a = readCsv(slurp(path("a/steps.csv")));
  auto b = readCsv(slurp(path("b/steps.csv")));
  ASSERT_EQ(a.size(), 4u);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t col = 0; col < a[0].size(); ++col)
      if (a[0][col].find("_ms") == std::string::npos) { // timings may differ
        EXPECT_EQ(a[i][col], b[i][col]) << a[0][col] << " row " << i;
      }
}

TEST_F(CliTest, ReconstructSectorFollowsALoadedModel)
{
  write("small.yaml", kSmallTrial);
  const std::string model = "reconstruct --model " + kFixtures +
                            "/plant_cm_zup.dae --views 1 --config " + path("small.yaml");
  ASSERT_EQ(run(model + " -o " + path("m")).code, 0);
  ASSERT_EQ(run("plant --model " + kFixtures + "/plant_cm_zup.dae -o " + path("p")).code,
            0);
  plantnbv::TriangleMesh placed = plantnbv::io::loadMesh(path("p/plant.ply"));
  Eigen::Vector3f lo, hi;
  placed.bounds(lo, hi);
  auto summary = nlohmann::json::parse(slurp(path("m/summary.json")));
  EXPECT_NEAR(summary["config"]["sector"]["height"].get<double>(), hi.z() - 0.8, 1e-6);
  ASSERT_EQ(run(model + " --sector-height 0.5 --sector-radius 0.55 -o " + path("n")).code,
            0);
  summary = nlohmann::json::parse(slurp(path("n/summary.json")));
  EXPECT_EQ(summary["config"]["sector"]["height"].get<double>(), 0.5);
  EXPECT_EQ(summary["config"]["sector"]["radius"].get<double>(), 0.55);
  // The file's unit replaced: 50 units tall, 2 mm each.
  ASSERT_EQ(run(model + " --model-scale 0.002 -o " + path("s")).code, 0);
  summary = nlohmann::json::parse(slurp(path("s/summary.json")));
  EXPECT_NEAR(summary["config"]["sector"]["height"].get<double>(), 0.1, 1e-6);
  EXPECT_NE(run(model + " --sector-radius -1 -o " + path("e")).code, 0);
  // The file's up axis replaced: its y extent (1 m in centimetres) stands up.
  write("y_up.obj", "v 0 0 0\nv 0 100 0\nv 0 0 10\nf 1 2 3\n");
  const std::string y_up =
      "plant --model " + path("y_up.obj") + " --model-scale 0.01 --model-up-axis ";
  ASSERT_EQ(run(y_up + "y -o " + path("y")).code, 0);
  placed = plantnbv::io::loadMesh(path("y/plant.ply"));
  placed.bounds(lo, hi);
  EXPECT_NEAR(hi.z() - lo.z(), 1.0, 1e-6);
  const ToolRun bad = run(y_up + "Y_UP -o " + path("b"));
  EXPECT_EQ(bad.code, 1);
  EXPECT_NE(bad.err.find("--model-up-axis: expected file, y or z, got 'Y_UP'"),
            std::string::npos)
      << bad.err;
}

TEST_F(CliTest, ReconstructInARowMapsTheNeighboursButScoresThePlantAlone)
{
  write("small.yaml", kSmallTrial);
  const std::string cmd = "reconstruct --plant 3 --views 2 --config " +
                          path("small.yaml") + " --row-spacing ";
  ASSERT_EQ(run(cmd + "0 -o " + path("alone")).code, 0);
  const auto row_run = run(cmd + "0.25 -o " + path("row"));
  ASSERT_EQ(row_run.code, 0) << row_run.err;
  EXPECT_NE(row_run.out.find("in a row with a neighbour 0.25 m away on each side"),
            std::string::npos)
      << row_run.out;
  const auto alone = nlohmann::json::parse(slurp(path("alone/summary.json")));
  const auto row = nlohmann::json::parse(slurp(path("row/summary.json")));
  EXPECT_EQ(row["plant"]["row_spacing"].get<double>(), 0.25);
  // The neighbours fill the map; the ground truth is the plant's alone.
  EXPECT_GT(row["totals"]["occupied_voxels"].get<double>(),
            alone["totals"]["occupied_voxels"].get<double>());
  EXPECT_EQ(row["levels"]["whole_plant"]["reference_voxels"],
            alone["levels"]["whole_plant"]["reference_voxels"]);
  EXPECT_NE(run(cmd + "-0.1 -o " + path("bad")).code, 0);
}

TEST_F(CliTest, SnapshotNamesItsPngInEveryCommand)
{
  // The same option in plant, capture and reconstruct: the PNG to write, beside the
  // results or anywhere else.
  write("small.yaml", kSmallTrial);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"plant --seed 0 -o " + path("p") + " --snapshot " + path("p.png"), "p.png"},
      {"capture --plant 0 --intrinsics l515-320 --snapshot " + path("c.png"), "c.png"},
      {"reconstruct --plant 0 --views 2 --config " + path("small.yaml") + " -o " +
           path("s") + " --snapshot " + path("s/snapshot.png"),
       "s/snapshot.png"},
  };
  for (const auto& [args, png_file] : cases) {
    SCOPED_TRACE(args);
    const ToolRun r = run(args);
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string png = slurp(path(png_file));
    ASSERT_GT(png.size(), 24u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
    EXPECT_GT(png.size(), 30000u); // not blank
  }
  const std::string png = slurp(path("s/snapshot.png"));
  EXPECT_EQ(std::uint8_t(png[18]) * 256 + std::uint8_t(png[19]), 1200); // width
  EXPECT_EQ(std::uint8_t(png[22]) * 256 + std::uint8_t(png[23]), 1200); // height
}

TEST_F(CliTest, APlantSplitIntoSeveralFilesIsGivenByRepeatingModel)
{
  // One triangle per file; PLY names no node, so each file's name labels its triangle.
  const auto ply = [](const char* x0) {
    return std::string("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                       "property float y\nproperty float z\nelement face 1\n"
                       "property list uchar int vertex_indices\nend_header\n") +
           x0 + " 0 0\n" + x0 + " 0.01 0\n" + x0 + " 0 0.3\n3 0 1 2\n";
  };
  write("stem.ply", ply("0"));
  write("leaf.ply", ply("0.1"));
  const ToolRun r =
      run("plant --model " + path("stem.ply") + " --model " + path("leaf.ply") +
          " --labels stem=stem,leaflet=leaf -o " + path("p"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_NE(r.out.find("and 1 more file, labelled by name"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("2 triangles (stem 1, leaflet 1)"), std::string::npos) << r.out;
}

TEST_F(CliTest, ReconstructTakesTheSensorOptionsOfCapture)
{
  write("small.yaml", kSmallTrial);
  const ToolRun r =
      run("reconstruct --plant 0 --views 2 --config " + path("small.yaml") +
          " --intrinsics 320x240:229,229,159.5,119.5 --noise --no-background -o " +
          path("t"));
  ASSERT_EQ(r.code, 0) << r.err;
  const auto summary = nlohmann::json::parse(slurp(path("t/summary.json")));
  const auto& camera = summary["config"]["camera"];
  EXPECT_EQ(camera["width"], 320);
  EXPECT_EQ(camera["height"], 240);
  EXPECT_EQ(camera["fx"], 229.0);
  EXPECT_EQ(camera["cy"], 119.5);
  EXPECT_EQ(summary["config"]["noise"], true);
  EXPECT_EQ(summary["config"]["background"], false);
  // Without them: the config's camera, no noise, the floor and the support.
  ASSERT_EQ(run("reconstruct --plant 0 --views 2 --config " + path("small.yaml") +
                " -o " + path("u"))
                .code,
            0);
  const auto plain = nlohmann::json::parse(slurp(path("u/summary.json")));
  EXPECT_EQ(plain["config"]["camera"]["width"], 160);
  EXPECT_EQ(plain["config"]["noise"], false);
  EXPECT_EQ(plain["config"]["background"], true);
}

TEST_F(CliTest, ReconstructAttendsToANoisyRoiAndSaysWhichBoxes)
{
  write("small.yaml", kSmallTrial);
  const std::string trial =
      "reconstruct --plant 0 --views 3 --attention leaf_nodes --config " +
      path("small.yaml");
  ASSERT_EQ(run(trial + " -o " + path("oracle")).code, 0);
  const ToolRun zero = run(trial + " --roi-source noisy -o " + path("zero"));
  ASSERT_EQ(zero.code, 0) << zero.err;
  const ToolRun moved = run(
      trial + " --roi-source noisy --roi-sigma 0.02 --roi-scale 1.5 -o " + path("moved"));
  ASSERT_EQ(moved.code, 0) << moved.err;

  const auto oracle = nlohmann::json::parse(slurp(path("oracle/summary.json")));
  const auto noisy = nlohmann::json::parse(slurp(path("moved/summary.json")));
  EXPECT_EQ(oracle["config"]["roi_source"]["type"], "oracle");
  EXPECT_EQ(noisy["config"]["roi_source"]["type"], "noisy");
  EXPECT_EQ(noisy["config"]["roi_source"]["sigma"], 0.02);
  EXPECT_EQ(noisy["config"]["roi_source"]["scale"], 1.5);
  const auto& truth = oracle["attended_roi"];
  const auto& attended = noisy["attended_roi"];
  ASSERT_GT(truth.size(), 0u);
  ASSERT_EQ(attended.size(), truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    EXPECT_EQ(attended[i]["name"], truth[i]["name"]);
    EXPECT_NE(attended[i]["center"], truth[i]["center"]);
    for (int axis = 0; axis < 3; ++axis)
      EXPECT_DOUBLE_EQ(attended[i]["size"][axis].get<double>(),
                       1.5 * truth[i]["size"][axis].get<double>());
  }
  // Sigma 0 is the oracle, step for step (steps.csv's timing columns aside).
  auto withoutTimings = [](const std::string& csv) {
    std::istringstream in(csv);
    std::string line, out;
    while (std::getline(in, line)) {
      std::vector<std::string> cells;
      std::stringstream cell_stream(line);
      for (std::string cell; std::getline(cell_stream, cell, ',');)
        cells.push_back(cell);
      for (std::size_t c = 0; c < cells.size(); ++c)
        if (c < 11 || c > 14) // plan_ms, capture_ms, insert_ms, eval_ms
          out += cells[c] + ",";
      out += "\n";
    }
    return out;
  };
  EXPECT_EQ(withoutTimings(slurp(path("zero/steps.csv"))),
            withoutTimings(slurp(path("oracle/steps.csv"))));
  EXPECT_EQ(nlohmann::json::parse(slurp(path("zero/summary.json")))["attended_roi"],
            truth);
}

namespace {

/// A tiny campaign: one generated plant, three yaws, NBV, two pre-defined patterns and
/// random, 3 views, the small camera and ray grid of kSmallTrial: 12 trials.
std::string tinyCampaign(const std::string& extra_plants = "")
{
  return "name: tiny\n"
         "seed: 11\n"
         "plants:\n"
         "  - seed: 0\n" +
         extra_plants +
         "yaws_deg: [0, 120, 240]\n"
         "views: 3\n"
         "levels: [whole_plant, leaf_nodes]\n"
         "trial:\n"
         "  camera: 160x120:114.25,114.25,79.5,59.5\n"
         "  gain: {rays_x: 32, rays_y: 24}\n"
         "studies:\n"
         "  - name: main\n"
         "    planners:\n"
         "      - {type: nbv, attention: leaf-nodes}\n"
         "      - {type: predefined, patterns: [1, 2]}\n"
         "      - {type: random}\n";
}

/// The result files of a campaign directory (not the temporary files), by name.
std::map<std::string, nlohmann::json> trialFiles(const fs::path& dir)
{
  std::map<std::string, nlohmann::json> files;
  for (const auto& entry : fs::directory_iterator(dir / "trials")) {
    const std::string name = entry.path().filename().string();
    if (name[0] != '.')
      files[name] = nlohmann::json::parse(slurp(entry.path()));
  }
  return files;
}

/// Drops the timing keys (ending in _ms) everywhere.
nlohmann::json withoutTimings(nlohmann::json j)
{
  if (j.is_object()) {
    nlohmann::json out = nlohmann::json::object();
    for (auto it = j.begin(); it != j.end(); ++it) {
      const std::string& key = it.key();
      if (key.size() < 3 || key.compare(key.size() - 3, 3, "_ms") != 0)
        out[key] = withoutTimings(it.value());
    }
    return out;
  }
  if (j.is_array())
    for (auto& e : j)
      e = withoutTimings(e);
  return j;
}

} // namespace

TEST_F(CliTest, CampaignBadFilesAreOneLineErrorsNamingTheKeyPath)
{
  const std::string out = " -o " + path("c");
  auto bad = [&](const std::string& name, const std::string& text,
                 const std::string& needle) {
    write(name, text);
    expectOneLineError(run("campaign run " + path(name) + out), 1, needle);
  };
  const std::string base = tinyCampaign();
  bad("unknown.yaml", base + "    candidats: [9]\n", "studies[0].candidats: unknown key");
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string text = base;
    return text.replace(text.find(from), from.size(), to);
  };
  bad("type.yaml", replaced("views: 3\n", "views: ten\n"),
      "views: 'ten' is not an integer");
  bad("twice.yaml", base + "seed: 12\n",
      "(line 17): key 'seed' appears twice (first on line 2)");
  bad("zero.yaml", base + "    candidates: [9, 10]\n",
      "studies[0].candidates[1] 10: expected a multiple of the 9 grid cells");
  bad("roi.yaml",
      base.substr(0, base.find("      - {type: nbv")) +
          "      - {type: nbv, attention: stems}\n",
      "'" + path("roi.yaml") + "' studies[0].planners[0].attention: unknown ROI 'stems'");
  bad("pattern.yaml",
      base.substr(0, base.find("      - {type: nbv")) +
          "      - {type: predefined, patterns: [1, 5]}\n",
      "studies[0].planners[0].patterns[1]: 5 is not a pattern 1-4");
  bad("trialviews.yaml", replaced("trial:\n", "trial:\n  views: 3\n"),
      "trial.views: set by the campaign");
  bad("trialunknown.yaml",
      base.substr(0, base.find("  gain:")) + "  gain: {rays: 32}\n" +
          base.substr(base.find("studies:")),
      "trial.gain.rays: unknown key");
  bad("noviews.yaml",
      base.substr(0, base.find("views: 3")) + "views: 0\n" +
          base.substr(base.find("levels:")),
      "views: 0, expected >= 1");
  bad("level.yaml",
      base.substr(0, base.find("levels:")) + "levels: [leaves]\n" +
          base.substr(base.find("trial:")),
      "levels[0]: unknown level 'leaves'");
  expectOneLineError(run("campaign run " + path("none.yaml") + out), 1, "none.yaml");
  expectOneLineError(run("campaign status " + path("nowhere")), 1, "nowhere");
  expectOneLineError(run("campaign run " + path("unknown.yaml")), 2, "--output");
}

TEST_F(CliTest, CampaignKilledRunResumesWithEveryTrialDoneOnce)
{
  write("tiny.yaml", tinyCampaign());
  // Reference: an uninterrupted run on two workers.
  const auto ref_start = std::chrono::steady_clock::now();
  const ToolRun ref =
      run("campaign run " + path("tiny.yaml") + " -o " + path("ref") + " -j 2");
  const double ref_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - ref_start).count();
  ASSERT_EQ(ref.code, 0) << ref.err;
  EXPECT_NE(ref.out.find("12 of 12 trials done"), std::string::npos) << ref.out;
  // Not a terminal: one plain line per finished trial.
  EXPECT_NE(ref.out.find("[12/12] "), std::string::npos) << ref.out;
  // Not a terminal: each trial's line carries the failures, the time and the ETA.
  EXPECT_TRUE(std::regex_search(
      ref.out, std::regex("\\[1/12\\] [^\n]+ done in [0-9.]+ s; 0 failed, "
                          "[0-9]+:[0-9]{2} elapsed, ETA [0-9]+:[0-9]{2}\n")))
      << ref.out;
  EXPECT_TRUE(std::regex_search(
      ref.out, std::regex("\\[12/12\\] [^\n]+ done in [0-9.]+ s; 0 failed, "
                          "[0-9]+:[0-9]{2} elapsed\n")))
      << ref.out; // nothing left: no ETA

  // Kill -9 the run at random points, several times (the first time only once a result
  // exists): every finished trial must survive each kill unchanged, and every result
  // file must be complete (written to a temporary file, then renamed).
  const fs::path trials = dir_ / "run" / "trials";
  std::mt19937 rng(20261123);
  std::map<std::string, std::string> finished; // name -> bytes, as first seen
  int kills = 0;
  for (; kills < 5 && finished.size() < 12; ++kills) {
    const std::string cmd = kTool + " campaign run " + path("tiny.yaml") + " -o " +
                            path("run") + " -j 2 >" + path("killed.out") +
                            " 2>&1 </dev/null & echo $! >" + path("pid");
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    if (kills == 0) { // wait for the first result file, up to 60 s
      bool seen = false;
      for (int i = 0; i < 6000 && !seen; ++i) {
        std::error_code ec;
        for (const auto& entry : fs::directory_iterator(trials, ec))
          seen = seen || entry.path().filename().string()[0] != '.';
        if (!seen)
          std::system("sleep 0.01");
      }
      ASSERT_TRUE(seen) << slurp(path("killed.out"));
    }
    // Somewhere in the next 10-40 % of the uninterrupted run's time (a fixed delay
    // would outlast a whole run on a fast machine): before, during or after a trial's
    // writing.
    const double delay_s = std::uniform_real_distribution<double>(0.1, 0.4)(rng) * ref_s;
    std::system(("sleep " + std::to_string(delay_s)).c_str());
    std::string pid = slurp(path("pid"));
    pid.erase(pid.find_last_not_of(" \n") + 1);
    ASSERT_FALSE(pid.empty());
    // Wait until it is gone (or a zombie nobody reaps), at most 10 s.
    std::system(("kill -9 " + pid +
                 " 2>/dev/null; i=0; while [ $i -lt 1000 ] && [ -d /proc/" + pid +
                 " ] && ! grep -q ') Z' /proc/" + pid +
                 "/stat 2>/dev/null; do sleep 0.01; " + "i=$((i+1)); done")
                    .c_str());
    for (const auto& entry : fs::directory_iterator(trials)) {
      const std::string name = entry.path().filename().string();
      if (name[0] == '.')
        continue; // a temporary file of the killed write: never read as a result
      const std::string bytes = slurp(entry.path());
      const auto j = nlohmann::json::parse(bytes, nullptr, false);
      ASSERT_FALSE(j.is_discarded())
          << name << " is not complete JSON after kill " << kills;
      EXPECT_EQ(j["status"], "done") << name;
      const auto before = finished.find(name);
      if (before == finished.end())
        finished[name] = bytes;
      else
        EXPECT_EQ(before->second, bytes) << name << " changed after kill " << kills;
    }
  }
  EXPECT_GE(kills, 2) << "the run finished before it could be killed twice";
  std::cout << "killed " << kills << " times; " << finished.size()
            << " of 12 trials finished before the last kill, all kept unchanged\n";
  const std::size_t after_kill = trialFiles(dir_ / "run").size();
  EXPECT_EQ(after_kill, finished.size());

  const ToolRun resumed =
      run("campaign run " + path("tiny.yaml") + " -o " + path("run") + " -j 2");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find(std::to_string(after_kill) + " already done"),
            std::string::npos)
      << resumed.out;
  const ToolRun status = run("campaign status " + path("run"));
  ASSERT_EQ(status.code, 0) << status.err;
  EXPECT_NE(status.out.find("12 trials, 12 done, 0 failed, 0 missing\n"),
            std::string::npos)
      << status.out;                         // nothing left: no ETA
  for (const auto& [name, bytes] : finished) // kept as they were: none run twice
    EXPECT_EQ(slurp(trials / name), bytes) << name;

  // Every trial once, and the same results as the uninterrupted run apart from timings.
  const auto a = trialFiles(dir_ / "ref");
  const auto b = trialFiles(dir_ / "run");
  ASSERT_EQ(a.size(), 12u);
  ASSERT_EQ(b.size(), 12u);
  for (const auto& [name, j] : a) {
    ASSERT_EQ(b.count(name), 1u) << name;
    EXPECT_EQ(j["status"], "done") << name;
    EXPECT_EQ(withoutTimings(j), withoutTimings(b.at(name))) << name;
  }
  // Byte for byte apart from the timing lines.
  auto dropTimings = [](const std::string& text) {
    std::istringstream lines(text);
    std::string line, out;
    while (std::getline(lines, line))
      if (line.find("_ms\"") == std::string::npos)
        out += line + "\n";
    return out;
  };
  for (const auto& entry : fs::directory_iterator(dir_ / "ref" / "trials"))
    EXPECT_EQ(dropTimings(slurp(entry.path())),
              dropTimings(slurp(dir_ / "run" / "trials" / entry.path().filename())));

  // The report of the resumed run: one curve row per planner, level and view.
  const ToolRun report = run("campaign report " + path("run") + " -o " + path("report"));
  ASSERT_EQ(report.code, 0) << report.err;
  EXPECT_EQ(report.out.find("roi_error"), std::string::npos)
      << report.out; // no noisy ROI
  const auto rows = readCsv(slurp(path("report/curves.csv")));
  ASSERT_EQ(rows.size(), 1u + 3u * 2u * 3u);
  EXPECT_EQ(rows[0][5], "f1_mean");
  const std::string summary = slurp(path("report/summary.md"));
  EXPECT_NE(summary.find("12 trials done, 0 failed"), std::string::npos) << summary;
  // ... and it equals the uninterrupted run's report.
  const ToolRun ref_report = run("campaign report " + path("ref") + " -o " +
                                 path("ref-report") + " --no-figures");
  ASSERT_EQ(ref_report.code, 0) << ref_report.err;
  EXPECT_EQ(slurp(path("ref-report/curves.csv")), slurp(path("report/curves.csv")));
  EXPECT_EQ(slurp(path("ref-report/summary.md")), summary);
  EXPECT_NE(summary.find("| nbv-leaf-nodes | predefined |"), std::string::npos)
      << summary;
  // The paper's rows for the planners and levels that ran (10 of 30), no sensitivity
  // section (there is no such study).
  EXPECT_NE(summary.find("\n20 of the paper's 30 rows have no trial in this campaign"),
            std::string::npos)
      << summary;
  EXPECT_NE(summary.find("| leaf_nodes | nbv-leaf-nodes | views to F1 0.8 | 3 | "),
            std::string::npos)
      << summary;
  EXPECT_EQ(summary.find("not run"), std::string::npos) << summary;
  EXPECT_EQ(summary.find("| main_stem |"), std::string::npos) << summary;
  EXPECT_EQ(summary.find("## Sensitivity studies"), std::string::npos) << summary;
  // The figures: PNGs 1200 px wide (the IHDR chunk's width, big-endian, at byte 16).
  for (const char* png : {"f1_main.png", "chamfer_main.png"}) {
    const std::string bytes = slurp(path(std::string("report/") + png));
    ASSERT_GT(bytes.size(), 24u) << png;
    EXPECT_EQ(bytes.substr(1, 3), "PNG") << png;
    const auto byte = [&](int i) { return static_cast<unsigned char>(bytes[i]); };
    EXPECT_EQ((byte(18) << 8) | byte(19), 1200) << png;
  }
}

TEST_F(CliTest, ACampaignOfNoisyRoisReportsF1AgainstTheRoiError)
{
  write("noisy.yaml", "name: noisy\nseed: 3\nplants: [{seed: 0}]\nyaws_deg: [0]\n"
                      "views: 3\nlevels: [whole_plant, leaf_nodes]\ntrial:\n"
                      "  camera: 160x120:114.25,114.25,79.5,59.5\n"
                      "  gain: {rays_x: 32, rays_y: 24}\n"
                      "studies:\n  - name: main\n    planners:\n"
                      "      - {type: nbv, attention: leaf-nodes, roi_source: noisy}\n"
                      "      - {type: nbv, attention: leaf-nodes, roi_source: noisy, "
                      "roi_sigma: 0.02}\n"
                      "      - {type: random}\n");
  const ToolRun r = run("campaign run " + path("noisy.yaml") + " -o " + path("run"));
  ASSERT_EQ(r.code, 0) << r.err;
  const auto trials = trialFiles(path("run"));
  EXPECT_EQ(trials.count("main+nbv-leaf-nodes-noisy20mm+plant00+yaw000+rep0.json"), 1u);
  const ToolRun report = run("campaign report " + path("run") + " -o " + path("report"));
  ASSERT_EQ(report.code, 0) << report.err;
  EXPECT_NE(report.out.find("roi_error_main.png"), std::string::npos) << report.out;
  const std::string bytes = slurp(path("report/roi_error_main.png"));
  ASSERT_GT(bytes.size(), 24u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  // The gains over random, per sigma, in summary.md.
  const std::string summary = slurp(path("report/summary.md"));
  EXPECT_NE(summary.find("| nbv-leaf-nodes-noisy0mm | random |"), std::string::npos)
      << summary;
  EXPECT_NE(summary.find("| nbv-leaf-nodes-noisy20mm | random |"), std::string::npos)
      << summary;
  // Without two sigmas of one ROI there is no such figure.
  ASSERT_EQ(run("campaign report " + path("run") + " -o " + path("report")).code, 0);
}

TEST_F(CliTest, ARowStudyRunsItsSpacingsAsVariantsAndDrawsThemApart)
{
  write("row.yaml", "name: row\nseed: 3\nplants: [{seed: 0}]\nyaws_deg: [0]\n"
                    "views: 2\nlevels: [whole_plant]\ntrial:\n"
                    "  camera: 160x120:114.25,114.25,79.5,59.5\n"
                    "  gain: {rays_x: 32, rays_y: 24}\n"
                    "studies:\n  - name: row\n    row_spacings: [0, 0.3]\n"
                    "    planners: [{type: random}]\n");
  const ToolRun r = run("campaign run " + path("row.yaml") + " -o " + path("run"));
  ASSERT_EQ(r.code, 0) << r.err;
  const auto trials = trialFiles(path("run"));
  ASSERT_EQ(trials.size(), 2u);
  const auto& alone = trials.at("row+random+alone+plant00+yaw000+rep0.json");
  const auto& row = trials.at("row+random+row30cm+plant00+yaw000+rep0.json");
  // The neighbours hide part of the plant from v0 (the same view in both).
  EXPECT_LT(row["views"][0]["levels"]["whole_plant"]["recall"].get<double>(),
            alone["views"][0]["levels"]["whole_plant"]["recall"].get<double>());
  // One study of two variants: its figure compares them; there is no main study to
  // draw planner against planner (its curves would join the variants into one line).
  const ToolRun report = run("campaign report " + path("run") + " -o " + path("report"));
  ASSERT_EQ(report.code, 0) << report.err;
  EXPECT_TRUE(fs::exists(path("report/f1_row.png"))) << report.out;
  EXPECT_FALSE(fs::exists(path("report/chamfer_row.png"))) << report.out;
}

TEST_F(CliTest, CampaignStatusGivesTheEtaFromTheDoneTrialsTimes)
{
  // Half the trials (a chunk), then status: the other 6 at the done trials' mean time,
  // by the rule of the run's own progress lines, for the trials at a time given.
  write("tiny.yaml", tinyCampaign());
  const ToolRun half = run("campaign run-chunk " + path("tiny.yaml") + " -o " +
                           path("c") + " --chunk 0 --chunks 2 -j 2");
  ASSERT_EQ(half.code, 0) << half.err;
  double sum_s = 0.0;
  for (const auto& [name, j] : trialFiles(dir_ / "c"))
    sum_s += j["total_ms"].get<double>() / 1000.0;
  auto clock = [](double seconds) {
    const long s = std::lround(seconds);
    char text[32];
    std::snprintf(text, sizeof(text), "%ld:%02ld", s / 60, s % 60);
    return std::string(text);
  };
  char mean[32];
  std::snprintf(mean, sizeof(mean), "%.1f", sum_s / 6);
  for (const int jobs : {1, 2, 4}) {
    const ToolRun status =
        run("campaign status " + path("c") + " -j " + std::to_string(jobs));
    ASSERT_EQ(status.code, 0) << status.err;
    // 6 left at `jobs` at a time: 6 * (mean / jobs) = sum / jobs.
    EXPECT_NE(status.out.find("12 trials, 6 done, 0 failed, 6 missing, ETA " +
                              clock(sum_s / jobs) + " at " + std::to_string(jobs) +
                              (jobs == 1 ? " trial" : " trials") +
                              " at a time (a trial took " + mean + " s on average)\n"),
              std::string::npos)
        << status.out;
  }
  // The default: as many at a time as `campaign run` takes (all cores).
  const ToolRun status = run("campaign status " + path("c"));
  ASSERT_EQ(status.code, 0) << status.err;
  EXPECT_TRUE(std::regex_search(
      status.out, std::regex("6 missing, ETA [0-9]+:[0-9]{2} at [0-9]+ trials? at a "
                             "time \\(a trial took [0-9]+\\.[0-9] s on average\\)\n")))
      << status.out;

  // --timing: each planner's mean times over its done trials, from their files.
  std::map<std::string, std::vector<double>> sums; // planner: trials, setup .. total
  for (const auto& [name, j] : trialFiles(dir_ / "c")) {
    std::vector<double>& sum = sums[j["spec"]["planner"].get<std::string>()];
    sum.resize(7, 0.0);
    sum[0] += 1.0;
    sum[1] += j["setup_ms"].get<double>();
    for (const auto& view : j["views"]) {
      sum[2] += view["plan_ms"].get<double>();
      sum[3] += view["capture_ms"].get<double>();
      sum[4] += view["insert_ms"].get<double>();
      sum[5] += view["eval_ms"].get<double>();
    }
    sum[6] += j["total_ms"].get<double>();
  }
  ASSERT_EQ(sums.size(), 3u);
  const ToolRun timing = run("campaign status " + path("c") + " --timing");
  ASSERT_EQ(timing.code, 0) << timing.err;
  EXPECT_NE(
      timing.out.find("where the time goes (6 done trials; mean ms a trial, each on "
                      "one worker):\n| study | variant | planner | trials | setup | "
                      "plan | capture | insert | evaluate | total | share |\n"),
      std::string::npos)
      << timing.out;
  for (const auto& [planner, sum] : sums) {
    std::ostringstream row;
    row << std::fixed << std::setprecision(0) << "| main |  | " << planner << " | "
        << sum[0];
    for (int k = 1; k < 7; ++k)
      row << " | " << sum[k] / sum[0];
    EXPECT_NE(timing.out.find(row.str() + " | "), std::string::npos) << row.str() << "\n"
                                                                     << timing.out;
  }
}

TEST_F(CliTest, CampaignTrialThatThrowsIsRecordedAndTheOthersFinish)
{
  // A model plant whose file disappears before the run.
  fs::copy_file(kFixtures + "/plant_cm_zup.dae", path("gone.dae"));
  write("fail.yaml", tinyCampaign("  - {model: gone.dae}\n"));
  fs::remove(path("gone.dae"));
  const ToolRun r =
      run("campaign run " + path("fail.yaml") + " -o " + path("c") + " -j 2");
  expectOneLineError(r, 1, "12 of 24 trials failed");
  EXPECT_NE(r.out.find("12 of 24 trials done, 12 failed"), std::string::npos) << r.out;
  const auto files = trialFiles(dir_ / "c");
  ASSERT_EQ(files.size(), 24u);
  int failed = 0;
  for (const auto& [name, j] : files)
    if (name.find("+gone+") != std::string::npos) {
      EXPECT_EQ(j["status"], "failed") << name;
      EXPECT_NE(j["error"].get<std::string>().find("gone.dae"), std::string::npos) << j;
      ++failed;
    } else {
      EXPECT_EQ(j["status"], "done") << name;
    }
  EXPECT_EQ(failed, 12);
  const ToolRun status = run("campaign status " + path("c"));
  ASSERT_EQ(status.code, 0) << status.err;
  EXPECT_NE(status.out.find("24 trials, 12 done, 12 failed, 0 missing"),
            std::string::npos)
      << status.out;
  EXPECT_NE(status.out.find("failed: main/nbv-leaf-nodes/gone/yaw000/rep0: "),
            std::string::npos)
      << status.out;
  // Another definition in the same directory is refused.
  write("other.yaml", tinyCampaign() + "    candidates: [9]\n");
  expectOneLineError(run("campaign run " + path("other.yaml") + " -o " + path("c")), 1,
                     "another campaign");
}

TEST_F(CliTest, CampaignTrialsOverTheirTimeLimitAreRecordedAsFailed)
{
  // Every trial is over a microsecond's limit after its setup: all fail, with the reason.
  std::string text = tinyCampaign();
  text.replace(text.find("trial:\n"), 7, "trial:\n  time_limit_s: 0.000001\n");
  write("slow.yaml", text);
  const ToolRun r =
      run("campaign run " + path("slow.yaml") + " -o " + path("c") + " -j 2");
  expectOneLineError(r, 1, "12 of 12 trials failed");
  for (const auto& [name, j] : trialFiles(dir_ / "c")) {
    EXPECT_EQ(j["status"], "failed") << name;
    EXPECT_NE(j["error"].get<std::string>().find("trial time limit of 1e-06 s passed"),
              std::string::npos)
        << j;
  }
}

namespace {

/// The submit directories `campaign submit` wrote under DIR/slurm, oldest first.
std::vector<fs::path> submitDirs(const fs::path& campaign_dir)
{
  std::vector<fs::path> dirs;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(campaign_dir / "slurm", ec))
    if (entry.path().filename().string().rfind("submit-", 0) == 0)
      dirs.push_back(entry.path());
  std::sort(dirs.begin(), dirs.end());
  return dirs;
}

/// The trial ids of a task file, by task.
std::map<int, std::vector<std::string>> taskFileIds(const fs::path& file)
{
  std::map<int, std::vector<std::string>> tasks;
  std::istringstream lines(slurp(file));
  std::string line;
  while (std::getline(lines, line))
    if (!line.empty() && line[0] != '#')
      tasks[std::stoi(line.substr(0, line.find('\t')))].push_back(
          line.substr(line.find('\t') + 1));
  return tasks;
}

} // namespace

TEST_F(CliTest, CampaignReportReadsResultsOfTheFirstRelease)
{
  // data/fixtures/campaign-0.1.0: a campaign directory written by plantnbv 0.1.0 (its
  // campaign.yaml spells the attention leaf-nodes), with its report beside it. Read
  // today, the report is the same, byte for byte: curves.csv as that release wrote it,
  // summary.md as the layout is now (no empty section, only the paper's rows that ran;
  // the numbers are that release's).
  const fs::path fixture = fs::path(kFixtures) / "campaign-0.1.0";
  const fs::path dir = path("old");
  fs::create_directories(dir);
  fs::copy(fixture / "campaign.yaml", dir / "campaign.yaml");
  fs::copy(fixture / "trials", dir / "trials");
  const ToolRun status = run("campaign status " + dir.string());
  ASSERT_EQ(status.code, 0) << status.err;
  EXPECT_NE(status.out.find("8 trials, 8 done, 0 failed, 0 missing"), std::string::npos)
      << status.out;
  const ToolRun report =
      run("campaign report " + dir.string() + " --no-figures -o " + path("report"));
  ASSERT_EQ(report.code, 0) << report.err;
  EXPECT_EQ(slurp(path("report") + "/curves.csv"), slurp(fixture / "report-curves.csv"));
  EXPECT_EQ(slurp(path("report") + "/summary.md"), slurp(fixture / "report-summary.md"));
}

TEST_F(CliTest, CampaignSubmitBadInputsAreOneLineErrors)
{
  write("tiny.yaml", tinyCampaign());
  const std::string submit = "campaign submit " + path("tiny.yaml") + " -o " + path("c");
  expectOneLineError(run(submit + " --trials-per-task 0 --dry-run"), 1,
                     "--trials-per-task 0");
  expectOneLineError(run(submit + " --trials-per-task -3 --dry-run"), 1,
                     "--trials-per-task -3");
  expectOneLineError(run(submit + " --max-parallel 0 --dry-run"), 1, "--max-parallel 0");
  expectOneLineError(run(submit + " --time-limit 2h --dry-run"), 1, "--time-limit '2h'");
  EXPECT_FALSE(fs::exists(path("c"))) << "a bad option wrote the campaign directory";
  expectOneLineError(run(submit + " --trials-per-task many"), 2, "--trials-per-task");
  expectOneLineError(run("campaign submit " + path("tiny.yaml")), 2, "--output");
  expectOneLineError(run("campaign submit " + path("none.yaml") + " -o " + path("c")), 1,
                     "none.yaml");
  // A directory that holds another campaign (written by a dry run here, as by a run).
  ASSERT_EQ(run(submit + " --dry-run").code, 0);
  write("other.yaml", tinyCampaign() + "    candidates: [9]\n");
  expectOneLineError(
      run("campaign submit " + path("other.yaml") + " -o " + path("c") + " --dry-run"), 1,
      "another campaign");
  // No sbatch on the PATH: one line that says so, and nothing recorded as submitted.
  fs::create_directories(path("nobin"));
  const int status = std::system(("PATH=" + path("nobin") + " " + kTool + " " + submit +
                                  " >" + path("stdout") + " 2>" + path("stderr"))
                                     .c_str());
  ToolRun nosbatch;
  nosbatch.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  nosbatch.err = slurp(path("stderr"));
  expectOneLineError(nosbatch, 1, "sbatch not found");
  EXPECT_EQ(submitDirs(path("c")).size(), 1u); // the dry run's only

  // run-chunk: one of the two modes, and a task the task file has.
  expectOneLineError(run("campaign run-chunk " + path("tiny.yaml") + " -o " + path("c")),
                     2, "--task-file");
  expectOneLineError(run("campaign run-chunk " + path("tiny.yaml") + " -o " + path("c") +
                         " --task-file " + path("t.txt")),
                     2, "--task");
  const fs::path tasks = submitDirs(path("c")).at(0) / "tasks.txt";
  expectOneLineError(run("campaign run-chunk " + path("tiny.yaml") + " -o " + path("c") +
                         " --task-file " + tasks.string() + " --task 9"),
                     1, "--task 9");
}

TEST_F(CliTest, CampaignSubmitDryRunWritesAnArrayThatCoversOnlyTheMissingTrials)
{
  write("tiny.yaml", tinyCampaign());
  const std::string submit = "campaign submit " + path("tiny.yaml") + " -o " + path("c") +
                             " --trials-per-task 5 --dry-run";
  const ToolRun first = run(submit + " --max-parallel 2 --partition short");
  ASSERT_EQ(first.code, 0) << first.err;
  EXPECT_NE(first.out.find("3 array tasks of up to 5 trials (12 trials)"),
            std::string::npos)
      << first.out;
  ASSERT_EQ(submitDirs(path("c")).size(), 1u);
  const fs::path submitted = submitDirs(path("c"))[0];
  const std::string script = slurp(submitted / "job.sbatch");
  EXPECT_NE(script.find("\n#SBATCH --array=0-2%2\n"), std::string::npos) << script;
  EXPECT_NE(script.find("\n#SBATCH --partition=short\n"), std::string::npos) << script;
  EXPECT_NE(script.find("\n#SBATCH --job-name=plantnbv-tiny\n"), std::string::npos)
      << script;
  EXPECT_NE(script.find("\n#SBATCH --output=" + submitted.string() + "/task-%A_%a.out\n"),
            std::string::npos)
      << script;
  EXPECT_NE(script.find("exec '" + fs::canonical(kTool).string() +
                        "' campaign run-chunk '" + path("c") + "/campaign.yaml' -o '" +
                        path("c") + "'"),
            std::string::npos)
      << script;
  const auto tasks = taskFileIds(submitted / "tasks.txt");
  ASSERT_EQ(tasks.size(), 3u);
  EXPECT_EQ(tasks.at(0).size() + tasks.at(1).size() + tasks.at(2).size(), 12u);
  const ToolRun listed = run("campaign status " + path("c"));
  EXPECT_NE(listed.out.find("slurm " + submitted.filename().string() + ": not submitted"),
            std::string::npos)
      << listed.out;

  // Run task 0 as Slurm would; a second submit then lists only the other trials.
  const std::string task0 = "cd " + path("") + " && SLURM_ARRAY_TASK_ID=0 bash " +
                            (submitted / "job.sbatch").string() + " >" +
                            path("task0.out") + " 2>&1";
  ASSERT_EQ(std::system(task0.c_str()), 0) << slurp(path("task0.out"));
  const ToolRun second = run(submit);
  ASSERT_EQ(second.code, 0) << second.err;
  EXPECT_NE(second.out.find("12 trials, 4 done, 0 failed, 8 missing"), std::string::npos)
      << second.out;
  ASSERT_EQ(submitDirs(path("c")).size(), 2u);
  const fs::path resubmitted = submitDirs(path("c"))[1];
  const auto rest = taskFileIds(resubmitted / "tasks.txt");
  ASSERT_EQ(rest.size(), 2u);
  std::set<std::string> rest_ids;
  for (const auto& [task, ids] : rest)
    rest_ids.insert(ids.begin(), ids.end());
  EXPECT_EQ(rest_ids.size(), 8u);
  for (const std::string& id : tasks.at(0))
    EXPECT_EQ(rest_ids.count(id), 0u) << id << " was done and is listed again";

  // Its two tasks finish the campaign; nothing is left to submit.
  for (int task = 0; task < 2; ++task) {
    const ToolRun r =
        run("campaign run-chunk " + path("c") + "/campaign.yaml -o " + path("c") +
            " --task-file " + (resubmitted / "tasks.txt").string() + " --task " +
            std::to_string(task) + " -j 1");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("array task " + std::to_string(task) + " of 2: 4 trials"),
              std::string::npos)
        << r.out;
  }
  const ToolRun status = run("campaign status " + path("c"));
  EXPECT_NE(status.out.find("12 trials, 12 done, 0 failed, 0 missing"), std::string::npos)
      << status.out;
  const ToolRun none = run(submit);
  ASSERT_EQ(none.code, 0) << none.err;
  EXPECT_NE(none.out.find("nothing to submit"), std::string::npos) << none.out;
  EXPECT_EQ(submitDirs(path("c")).size(), 2u);
}

// --- the real-robot loop: frames folders, integrate, plan (docs/real-robot.md) ---------

namespace {

/// Frames folders and maps of the real-robot loop.
class RealRobotCliTest : public CliTest {
protected:
  /// One frame of plant 1 from the paper's v0 appended to FRAMES (`extra`: more options).
  void capture(const std::string& frames, const std::string& extra = "") const
  {
    const ToolRun r = run("capture --plant 1 --frames-out " + path(frames) + " " + extra);
    ASSERT_EQ(r.code, 0) << r.err;
  }
  void integrate(const std::string& frames, const std::string& map) const
  {
    const ToolRun r = run("integrate " + path(frames) + " -o " + path(map));
    ASSERT_EQ(r.code, 0) << r.err;
  }
  /// plan's JSON.
  nlohmann::json planJson(const std::string& args) const
  {
    const ToolRun r = run("plan " + args + " --json");
    EXPECT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out, nullptr, false);
    EXPECT_FALSE(j.is_discarded()) << r.out;
    return j;
  }
};

/// The 7 numbers of a pose array; fails unless it is one.
std::vector<double> poseNumbers(const nlohmann::json& pose)
{
  std::vector<double> v;
  EXPECT_TRUE(pose.is_array()) << pose;
  if (!pose.is_array())
    return v;
  EXPECT_EQ(pose.size(), 7u) << pose;
  for (const auto& x : pose) {
    EXPECT_TRUE(x.is_number()) << pose;
    v.push_back(x.is_number() ? x.get<double>() : NAN);
  }
  return v;
}

} // namespace

TEST_F(RealRobotCliTest, ReconstructFramesReplayToTheTrialsMapBitForBit)
{
  const ToolRun r = run("reconstruct --plant 1 --views 3 --threads 2 --frames-out " +
                        path("F") + " -o " + path("D"));
  ASSERT_EQ(r.code, 0) << r.err;
  const plantnbv::io::FramesFolder folder(path("F"));
  ASSERT_EQ(folder.frames().size(), 3u);
  for (std::size_t i = 0; i < 3; ++i)
    EXPECT_EQ(folder.frames()[i].stamp_s, double(i));
  EXPECT_EQ(folder.camera().depth_scale, 1000.0);
  EXPECT_NE(slurp(path("F/camera.yaml")).find("\ndepth_scale: 1000\n"),
            std::string::npos);

  integrate("F", "m.bt");
  const std::string replayed = slurp(path("m.bt")), trial = slurp(path("D/map.bt"));
  EXPECT_GT(trial.size(), 1000u);
  EXPECT_EQ(replayed.size(), trial.size());
  EXPECT_TRUE(replayed == trial) << "the replayed map differs from the trial's";
}

TEST_F(RealRobotCliTest, ATrialsDetectionsReplayToItsRoiAndThePlanUsesIt)
{
  // A trial attending to its simulated detector's finds writes them beside its frames;
  // `integrate --roi-out` fuses them into the boxes the trial attended to at its end.
  const ToolRun r = run("reconstruct --plant 1 --views 3 --attention leaf_nodes "
                        "--roi-source detections --detector-recall 0.8 "
                        "--detector-mask-dilation 1 --frames-out " +
                        path("F") + " -o " + path("D"));
  ASSERT_EQ(r.code, 0) << r.err;
  const plantnbv::io::FramesFolder folder(path("F"));
  ASSERT_EQ(folder.frames().size(), 3u);
  std::size_t found = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    ASSERT_FALSE(folder.frames()[i].detections_path.empty()) << i;
    std::vector<plantnbv::Detection> detections;
    folder.loadDetections(i, detections);
    for (const plantnbv::Detection& d : detections) {
      EXPECT_EQ(d.class_name, "leaf_node");
      EXPECT_EQ(d.mask.size(), 640u * 480u);
    }
    found += detections.size();
  }
  EXPECT_GT(found, 0u);
  const auto summary = nlohmann::json::parse(slurp(path("D/summary.json")));
  EXPECT_EQ(summary["config"]["roi_source"]["type"], "detections");
  EXPECT_EQ(summary["config"]["roi_source"]["detector_recall"], 0.8);
  EXPECT_EQ(summary["config"]["roi_source"]["detector_masks"], true);
  EXPECT_EQ(summary["config"]["roi_source"]["detector_mask_dilation"], 1);
  const auto& attended = summary["attended_roi"];
  ASSERT_GT(attended.size(), 0u);

  const ToolRun replay = run("integrate " + path("F") + " -o " + path("m.ot") +
                             " --roi-out " + path("nodes.yaml"));
  ASSERT_EQ(replay.code, 0) << replay.err;
  EXPECT_NE(replay.out.find("'leaf_node' instances"), std::string::npos) << replay.out;
  const plantnbv::Roi fused = plantnbv::io::loadRoi(path("nodes.yaml"));
  ASSERT_EQ(fused.size(), attended.size());
  for (std::size_t k = 0; k < fused.size(); ++k) {
    const plantnbv::Box& b = fused.boxes()[k];
    EXPECT_EQ(b.name, attended[k]["name"]);
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_DOUBLE_EQ(b.center[axis], attended[k]["center"][axis].get<double>());
      EXPECT_DOUBLE_EQ(b.size[axis], attended[k]["size"][axis].get<double>());
    }
  }
  const nlohmann::json plan =
      planJson("--map " + path("m.ot") + " --roi " + path("nodes.yaml"));
  EXPECT_EQ(plan["roi_meets_map"], true);
  EXPECT_EQ(plan["all_gains_zero"], false);
  EXPECT_EQ(plan["explored"], false);

  // Detections alone explore while at most one view was taken (--visited): the best
  // view is the whole plant's.
  std::istringstream trajectory(slurp(path("F/groundtruth.txt")));
  std::string line;
  while (std::getline(trajectory, line) && line.rfind("#", 0) == 0) {
  }
  std::ofstream(path("first.txt")) << line << "\n";
  const std::string detections = "--map " + path("m.ot") + " --roi " +
                                 path("nodes.yaml") + " --roi-source detections";
  const nlohmann::json first = planJson(detections + " --visited " + path("first.txt"));
  EXPECT_EQ(first["explored"], true);
  EXPECT_EQ(first["best"]["index"], planJson("--map " + path("m.ot") + " --visited " +
                                             path("first.txt"))["best"]["index"]);
  EXPECT_EQ(planJson(detections + " --visited " + path("F/groundtruth.txt"))["explored"],
            false);

  // Another class finds nothing: no ROI file (an earlier one is removed), a warning.
  fs::copy_file(path("nodes.yaml"), path("fruit.yaml"));
  const ToolRun fruit = run("integrate " + path("F") + " -o " + path("m2.ot") +
                            " --roi-out " + path("fruit.yaml") + " --roi-class fruit");
  ASSERT_EQ(fruit.code, 0) << fruit.err;
  EXPECT_FALSE(fs::exists(path("fruit.yaml")));
  EXPECT_NE(fruit.err.find("warning: no 'fruit' found in"), std::string::npos)
      << fruit.err;
  EXPECT_NE(fruit.err.find("(an earlier run's file removed)"), std::string::npos);
}

TEST_F(RealRobotCliTest, ABoxesOnlyDetectorsJitterMovesTheRoiAndReplays)
{
  // A YOLO-like detector: boxes without masks, the fusion takes each box's nearest
  // depth cluster; its boxes' jitter moves the fused ROI, and the frames replay to it.
  const std::string trial = "reconstruct --plant 1 --views 2 --attention leaf_nodes "
                            "--roi-source detections --detector-masks false ";
  const ToolRun exact = run(trial + "-o " + path("exact"));
  const ToolRun off = run(trial + "--detector-box-jitter 4 --frames-out " + path("F") +
                          " -o " + path("off"));
  ASSERT_EQ(exact.code, 0) << exact.err;
  ASSERT_EQ(off.code, 0) << off.err;
  const auto summary = nlohmann::json::parse(slurp(path("off/summary.json")));
  EXPECT_EQ(summary["config"]["roi_source"]["detector_masks"], false);
  EXPECT_EQ(summary["config"]["roi_source"]["detector_box_jitter"], 4.0);
  const auto& attended = summary["attended_roi"];
  ASSERT_GT(attended.size(), 0u);
  EXPECT_NE(attended,
            nlohmann::json::parse(slurp(path("exact/summary.json")))["attended_roi"]);
  const plantnbv::io::FramesFolder folder(path("F"));
  for (std::size_t i = 0; i < folder.frames().size(); ++i) {
    std::vector<plantnbv::Detection> detections;
    folder.loadDetections(i, detections);
    for (const plantnbv::Detection& d : detections)
      EXPECT_TRUE(d.mask.empty()) << i;
  }
  const ToolRun replay = run("integrate " + path("F") + " -o " + path("m.ot") +
                             " --roi-out " + path("nodes.yaml"));
  ASSERT_EQ(replay.code, 0) << replay.err;
  const plantnbv::Roi fused = plantnbv::io::loadRoi(path("nodes.yaml"));
  ASSERT_EQ(fused.size(), attended.size());
  for (std::size_t k = 0; k < fused.size(); ++k)
    for (int axis = 0; axis < 3; ++axis)
      EXPECT_DOUBLE_EQ(fused.boxes()[k].center[axis],
                       attended[k]["center"][axis].get<double>());
}

TEST_F(RealRobotCliTest, PlanAttendsToANoisyRoiDrawnFromItsSeed)
{
  capture("F");
  integrate("F", "m.ot");
  const std::string args = "--map " + path("m.ot") + " --roi main_stem --seed 4";
  const nlohmann::json oracle = planJson(args);
  const nlohmann::json zero = planJson(args + " --roi-source noisy");
  const nlohmann::json moved = planJson(args + " --roi-source noisy --roi-sigma 0.05");
  EXPECT_EQ(oracle["roi_source"], "oracle");
  EXPECT_EQ(moved["roi_source"], "noisy");
  EXPECT_EQ(zero["candidates"], oracle["candidates"]);
  ASSERT_EQ(moved["candidates"].size(), oracle["candidates"].size());
  std::map<std::size_t, double> gains;
  for (const auto& c : oracle["candidates"])
    gains[c["index"].get<std::size_t>()] = c["gain"].get<double>();
  bool other_gain = false;
  for (const auto& c : moved["candidates"])
    other_gain =
        other_gain || c["gain"].get<double>() != gains[c["index"].get<std::size_t>()];
  EXPECT_TRUE(other_gain);
  EXPECT_EQ(planJson(args + " --roi-source noisy --roi-sigma 0.05")["candidates"],
            moved["candidates"]); // seeded
}

TEST_F(RealRobotCliTest, PlanPredictsLeafNodesAlongTheStemAndAddsTheDetections)
{
  capture("F");
  integrate("F", "m.ot");
  // The prior alone: leaf-node boxes on the stem, from 0.088 m above the sector's base
  // (1, 0, 0.8) every 4 cm up to the plant's top in the map (under the sector's 0.7 m).
  const nlohmann::json prior = planJson("--map " + path("m.ot") + " --roi-source prior");
  EXPECT_EQ(prior["roi_source"], "prior");
  EXPECT_EQ(prior["roi"], "prior");
  EXPECT_EQ(prior["all_gains_zero"], false);
  const auto& predicted = prior["attended_roi"];
  ASSERT_GE(predicted.size(), 3u) << predicted;
  ASSERT_LE(predicted.size(), 16u) << predicted;
  for (std::size_t k = 0; k < predicted.size(); ++k) {
    const auto& c = predicted[k]["center"];
    EXPECT_EQ(predicted[k]["name"], "leaf_node_prior_" + std::to_string(k));
    EXPECT_NEAR(c[2].get<double>(), 0.888 + 0.04 * double(k), 1e-9) << k;
    EXPECT_LT(std::hypot(c[0].get<double>() - 1.0, c[1].get<double>()), 0.03) << k;
  }

  // Detected stem parts (--stem-roi): the same heights, on the stem through their
  // centres (one part: a vertical stem through it).
  std::ofstream(path("stem.yaml")) << "boxes:\n  - {name: main_stem_0, center: [1.0, "
                                      "0.05, 1.0], size: [0.02, 0.02, 0.2]}\n";
  const nlohmann::json stem = planJson(
      "--map " + path("m.ot") + " --roi-source prior --stem-roi " + path("stem.yaml"));
  ASSERT_EQ(stem["attended_roi"].size(), predicted.size());
  for (std::size_t k = 0; k < predicted.size(); ++k) {
    EXPECT_EQ(stem["attended_roi"][k]["center"][2], predicted[k]["center"][2]) << k;
    EXPECT_EQ(stem["attended_roi"][k]["center"][1], 0.05) << k;
  }

  // detections+prior: the detections' file first, then the same prediction; plain
  // detections: the file as it is, as the oracle takes it (attending from the first
  // plan; without --visited it would explore: no view taken).
  std::ofstream(path("nodes.yaml")) << "boxes:\n  - {name: node_a, center: [1.0, 0.0, "
                                       "1.05], size: [0.04, 0.04, 0.06]}\n";
  const std::string nodes = "--map " + path("m.ot") + " --roi " + path("nodes.yaml");
  const nlohmann::json both = planJson(nodes + " --roi-source detections+prior");
  const auto& attended = both["attended_roi"];
  ASSERT_EQ(attended.size(), 1u + predicted.size()) << attended;
  EXPECT_EQ(attended[0]["name"], "node_a");
  for (std::size_t k = 0; k < predicted.size(); ++k)
    EXPECT_EQ(attended[k + 1], predicted[k]) << k;
  const nlohmann::json found =
      planJson(nodes + " --roi-source detections --detections-explore-views 0");
  EXPECT_EQ(found["attended_roi"].size(), 1u);
  EXPECT_EQ(found["candidates"], planJson(nodes)["candidates"]);
  EXPECT_NE(found["candidates"], both["candidates"]);
}

TEST_F(RealRobotCliTest, PlanRanksTheCandidatesAsJsonAndPrintsThePoseAlone)
{
  capture("F");
  integrate("F", "m.ot");
  const nlohmann::json j = planJson("--map " + path("m.ot"));
  ASSERT_TRUE(j.contains("candidates") && j["candidates"].is_array()) << j;
  const nlohmann::json& c = j["candidates"];
  ASSERT_EQ(c.size(), 27u);
  EXPECT_EQ(j["best"], c[0]);
  EXPECT_EQ(j["all_gains_zero"], false);
  EXPECT_EQ(j["roi_meets_map"], true);
  std::set<std::size_t> indices;
  for (std::size_t i = 0; i < c.size(); ++i) {
    SCOPED_TRACE("candidate " + std::to_string(i));
    for (const char* key : {"index", "gain", "voxels_seen", "optical_pose", "viewpoint"})
      ASSERT_TRUE(c[i].contains(key)) << key << " missing in " << c[i];
    indices.insert(c[i]["index"].get<std::size_t>());
    EXPECT_GT(c[i]["gain"].get<double>(), 0.0);
    EXPECT_GT(c[i]["voxels_seen"].get<std::size_t>(), 0u);
    const std::vector<double> q = poseNumbers(c[i]["optical_pose"]);
    ASSERT_EQ(q.size(), 7u);
    EXPECT_NEAR(std::sqrt(q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6]), 1.0,
                1e-12);
    EXPECT_EQ(poseNumbers(c[i]["viewpoint"]).size(), 7u);
    if (i >= 2) { // non-increasing after the first
      EXPECT_GE(c[i - 1]["gain"].get<double>(), c[i]["gain"].get<double>());
    }
    EXPECT_GE(c[0]["gain"].get<double>(), c[i]["gain"].get<double>()); // no travel cost
  }
  EXPECT_EQ(indices.size(), 27u);
  EXPECT_EQ(*indices.rbegin(), 26u);

  const nlohmann::json top = planJson("--map " + path("m.ot") + " --top 2");
  ASSERT_EQ(top["candidates"].size(), 2u);
  EXPECT_EQ(top["candidates"][0], c[0]);
  EXPECT_EQ(top["candidates"][1], c[1]);

  // --pose-only: the 7 numbers of best.optical_pose, exactly (17 digits), one line.
  const ToolRun pose = run("plan --map " + path("m.ot") + " --pose-only");
  ASSERT_EQ(pose.code, 0) << pose.err;
  ASSERT_EQ(std::count(pose.out.begin(), pose.out.end(), '\n'), 1) << pose.out;
  ASSERT_EQ(pose.out.back(), '\n');
  std::vector<double> printed;
  std::istringstream fields(pose.out.substr(0, pose.out.size() - 1));
  for (std::string f; std::getline(fields, f, ',');) {
    std::size_t used = 0;
    printed.push_back(std::stod(f, &used));
    EXPECT_EQ(used, f.size()) << "'" << f << "' in " << pose.out;
  }
  EXPECT_EQ(printed, poseNumbers(j["best"]["optical_pose"])) << pose.out;
}

TEST_F(RealRobotCliTest, PlanKeepsItsViewAwayFromTheVisitedPositions)
{
  capture("F");
  integrate("F", "m.ot");
  const nlohmann::json free = planJson("--map " + path("m.ot"));
  const std::vector<double> best = poseNumbers(free["best"]["optical_pose"]);
  // A frame was taken at the best candidate: the next best view keeps 0.2 m from it.
  write("visited.txt", "1.0 " + std::to_string(best[0]) + " " + std::to_string(best[1]) +
                           " " + std::to_string(best[2]) + " 0 0 0 1\n");
  const nlohmann::json spaced =
      planJson("--map " + path("m.ot") + " --visited " + path("visited.txt"));
  const std::vector<double> other = poseNumbers(spaced["best"]["optical_pose"]);
  EXPECT_GE(std::hypot(other[0] - best[0], other[1] - best[1], other[2] - best[2]), 0.2);
  EXPECT_LT(spaced["best"]["gain"].get<double>(), free["best"]["gain"].get<double>());
  // The paper's planner has no spacing.
  write("paper.yaml", "view_spacing: 0\n");
  EXPECT_EQ(planJson("--map " + path("m.ot") + " --visited " + path("visited.txt") +
                     " --config " + path("paper.yaml"))["best"],
            free["best"]);
}

TEST_F(RealRobotCliTest, PlanOnAnRoiNoCandidateReachesSaysEveryGainIsZero)
{
  capture("F");
  integrate("F", "m.ot");
  write("far.yaml", "boxes:\n  - center: [50, 50, 50]\n    size: [0.1, 0.1, 0.1]\n"
                    "  - center: [50, 50, 50.5]\n    size: [0.2, 0.2, 0.2]\n");
  const std::string args = "--map " + path("m.ot") + " --roi " + path("far.yaml");
  const nlohmann::json j = planJson(args);
  EXPECT_EQ(j["all_gains_zero"], true);
  EXPECT_EQ(j["roi_meets_map"], false);
  EXPECT_EQ(j["best"]["index"], 0);
  ASSERT_EQ(j["candidates"].size(), 27u);
  for (const auto& c : j["candidates"]) {
    EXPECT_EQ(c["gain"], 0.0) << c;
    EXPECT_EQ(c["voxels_seen"], 0) << c;
  }
  const ToolRun text = run("plan " + args);
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("note: every candidate has gain 0"), std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("best view: candidate 0, gain 0.0 bits"), std::string::npos)
      << text.out;
}

TEST_F(RealRobotCliTest, PlanOnABtMapWarnsAndStillPlans)
{
  capture("F");
  integrate("F", "m.bt");
  const ToolRun r = run("plan --map " + path("m.bt") + " --top 1");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.rfind("warning: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("is a .bt map"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.out.find("best view: candidate "), std::string::npos) << r.out;
}

TEST_F(RealRobotCliTest, IntegrateThatFailsLeavesTheMapAsItWas)
{
  capture("F");
  capture("F");
  const ToolRun first = run("integrate " + path("F") + " --frames 0 -o " + path("m.ot"));
  ASSERT_EQ(first.code, 0) << first.err;
  const std::string before = slurp(path("m.ot"));
  ASSERT_GT(before.size(), 1000u);
  // The second frame's PNG is cut in half: frame 0 goes in, frame 1 fails.
  const fs::path png = dir_ / "F" / "depth" / "000001.png";
  const std::string bytes = slurp(png);
  std::ofstream(png, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  for (const std::string& map_in : {std::string(), " --map-in " + path("m.ot")}) {
    SCOPED_TRACE(map_in.empty() ? "a new map" : "--map-in");
    const ToolRun r = run("integrate " + path("F") + map_in + " -o " + path("m.ot"));
    expectOneLineError(r, 1, "F/depth/000001.png");
    EXPECT_NE(r.out.find("frame   0 "), std::string::npos) << r.out;
    EXPECT_TRUE(slurp(path("m.ot")) == before) << "m.ot changed";
    for (const auto& entry : fs::directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      EXPECT_TRUE(name == "m.ot" || name.rfind("m.ot", 0) != 0) << name << " left behind";
    }
  }
}

TEST_F(RealRobotCliTest, FramesOutAppendsToItsFolderAndRefusesAnother)
{
  capture("A", "--intrinsics l515-320");
  capture("A", "--intrinsics l515-320");
  {
    const plantnbv::io::FramesFolder folder(path("A"));
    ASSERT_EQ(folder.frames().size(), 2u);
    EXPECT_EQ(folder.frames()[0].stamp_s, 0.0);
    EXPECT_EQ(folder.frames()[1].stamp_s, 1.0);
    EXPECT_EQ(folder.camera().intrinsics.width, 320u);
  }
  const std::string list = slurp(path("A/depth.txt"));
  // Another camera (640 x 480, or another depth scale): refused, nothing appended.
  for (const char* other :
       {"--intrinsics l515-640", "--intrinsics l515-320 --depth-scale 4000"}) {
    SCOPED_TRACE(other);
    expectOneLineError(
        run("capture --plant 1 " + std::string(other) + " --frames-out " + path("A")), 1,
        "A/camera.yaml' describes another camera");
    EXPECT_EQ(slurp(path("A/depth.txt")), list);
    EXPECT_FALSE(fs::exists(path("A/depth/000002.png")));
  }
  // reconstruct writes a whole trial to a new folder: one that holds frames is refused.
  capture("B"); // the trial's camera (L515 at 640 x 480)
  const std::string b_list = slurp(path("B/depth.txt"));
  expectOneLineError(run("reconstruct --plant 1 --views 1 --frames-out " + path("B") +
                         " -o " + path("R")),
                     1, "already holds 1 frames");
  EXPECT_EQ(slurp(path("B/depth.txt")), b_list);
  expectOneLineError(run("reconstruct --plant 1 --views 1 --frames-out " + path("A") +
                         " -o " + path("R")),
                     1, "A/camera.yaml' describes another camera");
}

TEST_F(CliTest, TheReadmeGroundTruthRecipeGivesTheTrialsScore)
{
  // The README's `sample --voxel` with the trial's ground-truth seed, then `eval` on the
  // trial's reconstruction and the plant's whole-plant box: the trial's final F1, to the
  // last bit; `eval` of the mesh itself with that seed too.
  ASSERT_EQ(run("plant --seed 1 -o " + path("p")).code, 0);
  const ToolRun trial = run("reconstruct --plant 1 --views 2 -o " + path("t"));
  ASSERT_EQ(trial.code, 0) << trial.err;
  const auto summary = nlohmann::json::parse(slurp(path("t/summary.json")));
  const std::uint64_t seed = summary["ground_truth"]["seed"].get<std::uint64_t>();
  EXPECT_EQ(summary["ground_truth"]["voxel"], 0.003);
  const double trial_f1 = summary["levels"]["whole_plant"]["final_f1"].get<double>();
  const ToolRun sampled =
      run("sample --mesh " + path("p/plant.ply") + " --voxel 0.003 --labels --seed " +
          std::to_string(seed) + " -o " + path("gt.pcd"));
  ASSERT_EQ(sampled.code, 0) << sampled.err;
  EXPECT_NE(sampled.out.find(" voxel centres in "), std::string::npos) << sampled.out;
  const std::string scored = " --reconstruction " + path("t/reconstruction.pcd") +
                             " --roi " + path("p/roi_whole_plant.yaml") + " --json";
  for (const std::string& reference :
       {path("gt.pcd"), path("p/plant.ply") + " --seed " + std::to_string(seed)}) {
    SCOPED_TRACE(reference);
    const ToolRun eval = run("eval --reference " + reference + scored);
    ASSERT_EQ(eval.code, 0) << eval.err;
    EXPECT_EQ(eval.err, "");
    EXPECT_EQ(nlohmann::json::parse(eval.out)["f1"].get<double>(), trial_f1);
  }
  // Centroids (the old behaviour) are one flag away, and give another cloud.
  ASSERT_EQ(run("sample --mesh " + path("p/plant.ply") +
                " --voxel 0.003 --labels --centroids " + "--seed " +
                std::to_string(seed) + " -o " + path("centroids.pcd"))
                .code,
            0);
  EXPECT_NE(slurp(path("centroids.pcd")), slurp(path("gt.pcd")));
}

TEST_F(CliTest, ASecondRunInTheSameFolderLeavesOnlyItsOwnResults)
{
  // A run with a snapshot, then one without it in the same folder: the old picture goes.
  const std::string trial = "reconstruct --plant 1 --views 1 -o " + path("t");
  ASSERT_EQ(run(trial + " --snapshot " + path("t/snapshot.png")).code, 0);
  ASSERT_TRUE(fs::exists(path("t/snapshot.png")));
  // The second with the user's own boxes on the generated plant, scored as model_rois.
  const ToolRun again = run(trial + " --rois " + kFixtures + "/rois.yaml --yaw-deg 30");
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_FALSE(fs::exists(path("t/snapshot.png")));
  EXPECT_NE(again.out.find("removed an earlier run's snapshot.png"), std::string::npos)
      << again.out;
  const auto summary = nlohmann::json::parse(slurp(path("t/summary.json")));
  EXPECT_TRUE(summary["levels"].contains("model_rois")) << summary["levels"];
  // For people and programs: the camera as numbers, the angle rounded, the placement.
  EXPECT_EQ(summary["config"]["camera"]["width"], 640);
  EXPECT_EQ(summary["config"]["camera"]["fx"].get<double>(),
            plantnbv::CameraIntrinsics::l515(plantnbv::L515Mode::vga_640x480).fx);
  EXPECT_EQ(summary["config"]["sector"]["angle_deg"], 90.0);
  EXPECT_EQ(summary["plant"]["yaw_deg"], 30.0);
  EXPECT_EQ(summary["plant"]["base"], nlohmann::json::array({1.0, 0.0, 0.8}));
}

TEST_F(CliTest, InputsThatWouldGiveMeaninglessResultsAreWarnedAbout)
{
  // A label rule that labels nothing: named, the rest of the rules still apply.
  ToolRun r =
      run("plant --model " + kFixtures +
          "/plant_cm_zup.dae --labels stem=no_such_node,leaflet=.* -o " + path("p"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(
      r.err,
      "plantnbv: warning: label rule stem=no_such_node matches no triangle "
      "of '" +
          kFixtures +
          "/plant_cm_zup.dae' (rules match node, geometry and material names, or the "
          "file's name where it has none; the first that matches wins)\n");
  // A voxel as large as the ROIs: one warning per level whose boxes it cannot resolve.
  r = run("reconstruct --plant 1 --views 1 --resolution 0.02 -o " + path("coarse"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "plantnbv: warning: the map's resolution 0.02 m gives fewer than 2 "
                   "voxels across the 0.03 m side of a box of level leaf_nodes: its "
                   "scores say little (the paper's is 0.003 m)\n");
  // Attention on empty space: one box 4 m away; two boxes either side of the plant, whose
  // union spans it while neither meets it. One warning line each.
  const std::pair<std::string, std::string> off_plant[] = {
      {"boxes:\n  - center: [5, 0, 1]\n    size: [0.1, 0.1, 0.1]\n",
       "(4.95, -0.05, 0.95) to (5.05, 0.05, 1.05)"},
      {"boxes:\n  - center: [0.5, 0, 1]\n    size: [0.05, 0.05, 0.05]\n"
       "  - center: [1.5, 0, 1]\n    size: [0.05, 0.05, 0.05]\n",
       "(0.475, -0.025, 0.975) to (1.52, 0.025, 1.02)"}};
  for (const auto& [boxes, extent] : off_plant) {
    write("off.yaml", boxes);
    r = run("reconstruct --plant 1 --views 1 --attention " + path("off.yaml") + " -o " +
            path("off"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err.rfind("plantnbv: warning: the attention ROI, " + extent +
                              ", does not meet the plant, (",
                          0),
              0u)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  // eval of clouds that hardly overlap (another frame), and of clouds that do.
  writeLattice("a.pcd", 0.0f);
  writeLattice("b.pcd", 0.04f); // 1/64 m lattice, 0.047 m wide: moved by most of it
  r = run("eval --reference " + path("a.pcd") + " --reconstruction " + path("b.pcd"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("plantnbv: warning: the bounding boxes of the reference and the "
                       "reconstruction overlap by "),
            std::string::npos)
      << r.err;
  EXPECT_NE(
      r.err.find("% of the smaller one (less than 50%): are they in the same frame"),
      std::string::npos)
      << r.err;
  r = run("eval --reference " + path("a.pcd") + " --reconstruction " + path("a.pcd"));
  EXPECT_EQ(r.err, "");
  // The paper's settings warn about nothing.
  r = run("reconstruct --plant 1 --views 1 -o " + path("paper"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "");
}

TEST_F(CliTest, ThreadsOverTheCoresAreLoweredToThemWithAWarning)
{
  const unsigned cores = std::thread::hardware_concurrency();
  const ToolRun r = run("reconstruct --plant 1 --views 1 --threads " +
                        std::to_string(cores + 1000) + " -o " + path("t"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: --threads " + std::to_string(cores + 1000) +
                       " is more than the " + std::to_string(cores) +
                       " cores of this machine; using " + std::to_string(cores)),
            std::string::npos)
      << r.err;
  expectOneLineError(
      run("plan --map " + path("m.ot") + " --threads -2"), 2,
      "--threads: expected 0 (all cores) or a number of threads, got '-2'");
}

// --- a full disk: every command that writes fails naming the file, keeps what was ------

namespace {

/// Every regular file under `dir` (relative name -> bytes).
std::map<std::string, std::string> filesUnder(const fs::path& dir)
{
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file())
      files[fs::relative(e.path(), dir).string()] = slurp(e.path());
  return files;
}

} // namespace

TEST_F(CliTest, AFullDiskFailsTheCommandNamingTheFileAndKeepsThePreviousFiles)
{
  write("small.yaml", kSmallTrial);
  // Three levels: a report over the limit below (summary.md, about 1.2 KiB).
  write("one.yaml", "name: one\nseed: 1\nplants: [{seed: 0}]\nyaws_deg: [0]\nviews: 2\n"
                    "levels: [whole_plant, main_stem, leaf_nodes]\ntrial:\n"
                    "  camera: 160x120:114.25,114.25,79.5,59.5\n"
                    "  gain: {rays_x: 32, rays_y: 24}\n"
                    "studies:\n  - name: main\n    planners: [{type: random}]\n");
  // 24 trials: a Slurm script over the limit.
  write("many.yaml", "name: many\nplants: [{seed: 0}, {seed: 1}]\n"
                     "yaws_deg: [0, 30, 60, 90, 120, 150, 180, 210, 240, 270, 300, 330]\n"
                     "studies:\n  - name: main\n    planners: [{type: random}]\n");
  const std::string mesh = kFixtures + "/plant_like.ply";
  struct Case {
    std::string args;  ///< run once as it is, then again on a "full disk"
    std::string kept;  ///< the output (file or folder) whose files must stay as they were
    std::string named; ///< the file the error must name
  };
  const std::vector<Case> cases = {
      {"sample --mesh " + mesh + " --points 20000 -o " + path("s.pcd"), "s.pcd", "s.pcd"},
      {"sample --mesh " + mesh + " --points 20000 -o " + path("s.ply"), "s.ply", "s.ply"},
      {"plant --seed 0 -o " + path("p"), "p", "plant.ply"},
      {"capture --plant 1 -o " + path("c/v.pcd"), "c", "v.pcd"},
      {"capture --plant 1 --depth " + path("d/v.png") + " -o " + path("d/v.ply"), "d",
       "v."},
      {"capture --plant 1 --map " + path("m/v.bt") + " -o " + path("m/v.pcd"), "m", "v."},
      {"capture --plant 1 --frames-out " + path("F"), "F", "F/depth/000001.png"},
      {"integrate " + path("F") + " -o " + path("i/m.ot"), "i", "m.ot"},
      {"reconstruct --plant 0 --views 2 --config " + path("small.yaml") + " -o " +
           path("t"),
       "t", path("t/")},
      {"campaign run " + path("one.yaml") + " -o " + path("r"), "r/campaign.yaml", ""},
      {"campaign report " + path("r") + " --no-figures -o " + path("rep"), "rep",
       path("rep/")},
      // The writers behind the snapshot, the frames of a trial and Slurm's files: each
      // command fails at its first file over the limit, whichever it is.
      {"plant --seed 0 --snapshot " + path("ps/plant.png") + " -o " + path("ps"), "ps",
       path("ps/")},
      {"reconstruct --plant 0 --views 2 --config " + path("small.yaml") + " --snapshot " +
           path("ts/snapshot.png") + " -o " + path("ts"),
       "ts", path("t")},
      {"campaign submit " + path("many.yaml") + " -o " + path("sub") + " --dry-run",
       "sub", "job.sbatch"},
  };
  for (const char* folder : {"c", "d", "m", "i"})
    fs::create_directories(path(folder));
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const ToolRun first = run(c.args);
    ASSERT_EQ(first.code, 0) << first.err;
    const std::map<std::string, std::string> before =
        fs::is_directory(path(c.kept))
            ? filesUnder(path(c.kept))
            : std::map<std::string, std::string>{{c.kept, slurp(path(c.kept))}};
    // 1 KiB for the process's files (its stdout and stderr files included), SIGXFSZ
    // ignored: writes past it fail with EFBIG, as on a full disk.
    // A snapshot's X server is started outside the limit (Xvfb cannot start under it),
    // with -noreset as the tool starts its own (display.cpp says why).
    const std::string display =
        c.args.find("--snapshot") != std::string::npos ? "xvfb-run -a -s -noreset " : "";
    const std::string cmd = display + "bash -c \"trap '' XFSZ; ulimit -f 1; exec " +
                            kTool + " " + c.args + "\" >" + path("stdout") + " 2>" +
                            path("stderr");
    const int status = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
    const std::string err = slurp(path("stderr")), out = slurp(path("stdout"));
    if (c.named.empty()) { // campaign run: the trial's error is its progress line
      EXPECT_EQ(WEXITSTATUS(status), 0) << err;
    } else {
      EXPECT_EQ(WEXITSTATUS(status), 1) << err;
      EXPECT_NE(err.find("File too large"), std::string::npos) << err;
      EXPECT_NE(err.find(c.named), std::string::npos) << err;
    }
    const std::map<std::string, std::string> after =
        fs::is_directory(path(c.kept))
            ? filesUnder(path(c.kept))
            : std::map<std::string, std::string>{{c.kept, slurp(path(c.kept))}};
    EXPECT_EQ(after.size(), before.size());
    for (const auto& [name, bytes] : before)
      EXPECT_TRUE(after.count(name) && after.at(name) == bytes) << name << " changed";
    for (const auto& e : fs::recursive_directory_iterator(dir_))
      EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos)
          << e.path();
  }
  // A campaign whose results cannot be stored: the trial fails naming its file, nothing
  // half-written is left, and a later run does it.
  fs::remove_all(path("r/trials"));
  const std::string cmd = "bash -c \"trap '' XFSZ; ulimit -f 1; exec " + kTool +
                          " campaign run " + path("one.yaml") + " -o " + path("r") +
                          "\" >/dev/null 2>" + path("stderr");
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 1);
  const std::map<std::string, nlohmann::json> stored = trialFiles(path("r"));
  ASSERT_EQ(stored.size(), 1u); // the failure, which is short enough to be stored
  const nlohmann::json& failure = stored.begin()->second;
  EXPECT_EQ(failure["status"], "failed");
  EXPECT_NE(failure["error"].get<std::string>().find(stored.begin()->first +
                                                     "': File too large"),
            std::string::npos)
      << failure["error"];
  EXPECT_EQ(run("campaign run " + path("one.yaml") + " -o " + path("r")).code, 0);
  EXPECT_NE(run("campaign status " + path("r")).out.find("1 done"), std::string::npos);
  // Standard output that cannot be written: exit 1, not 0.
  const int full =
      std::system((kTool + " eval --json --reference " + mesh + " --reconstruction " +
                   mesh + " >/dev/full 2>" + path("stderr"))
                      .c_str());
  EXPECT_EQ(WEXITSTATUS(full), 1);
  EXPECT_NE(slurp(path("stderr")).find("cannot write standard output: No space left"),
            std::string::npos)
      << slurp(path("stderr"));
}
