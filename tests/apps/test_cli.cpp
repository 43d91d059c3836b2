// The plantnbv tool as a user runs it: exit codes, one-line errors, and results.

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <sys/wait.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <octomap/OcTree.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/io/cloud_io.h>
#include <plantnbv/io/mesh_io.h>
#include <plantnbv/io/roi_io.h>
#include <plantnbv/octree/octree_conversion.h>

#include "read_csv.h"

namespace fs = std::filesystem;

using plantnbv::test::readCsv;

namespace {

const std::string kTool = std::string(PLANTNBV_BINARY_DIR) + "/bin/plantnbv";
const std::string kFixtures = std::string(PLANTNBV_DATA_DIR) + "/fixtures";

struct ToolRun {
  int code = -1;
  std::string out, err;
};

std::string slurp(const fs::path& p)
{
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class CliTest : public ::testing::Test {
protected:
  void SetUp() override
  {
    dir_ = fs::temp_directory_path() /
           ("plantnbv_cli_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  ToolRun run(const std::string& args) const
  {
    const std::string cmd = kTool + " " + args + " >" + path("stdout") + " 2>" +
                            path("stderr") + " </dev/null";
    const int status = std::system(cmd.c_str());
    ToolRun r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = slurp(path("stdout"));
    r.err = slurp(path("stderr"));
    return r;
  }

  void write(const std::string& name, const std::string& text) const
  {
    std::ofstream(path(name)) << text;
  }

  /// A 4 x 4 x 1 lattice of points 1/64 m apart from (1, 1, 513) / 512 m, shifted by `dx`
  /// along x. Powers of two keep every coordinate and distance exact in float.
  void writeLattice(const std::string& name, float dx) const
  {
    pcl::PointCloud<pcl::PointXYZ> cloud;
    const float origin = 1.0f / 512, spacing = 1.0f / 64;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        cloud.push_back(pcl::PointXYZ(origin + spacing * i + dx, origin + spacing * j,
                                      1.0f + origin));
    plantnbv::io::saveCloud(path(name), cloud);
  }

  fs::path dir_;
};

/// Errors are one line on stderr that starts with "plantnbv".
void expectOneLineError(const ToolRun& r, int code, const std::string& needle)
{
  EXPECT_EQ(r.code, code) << r.err;
  EXPECT_EQ(r.err.rfind("plantnbv", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos)
      << "'" << needle << "' not in: " << r.err;
}

} // namespace

TEST_F(CliTest, HelpAndVersionExitZero)
{
  const ToolRun help = run("--help");
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("sample"), std::string::npos);
  EXPECT_NE(help.out.find("eval"), std::string::npos);
  EXPECT_EQ(run("eval --help").code, 0);
  EXPECT_EQ(run("--version").code, 0);
}

TEST_F(CliTest, UsageErrorsExitTwo)
{
  expectOneLineError(run(""), 2, "subcommand");
  expectOneLineError(run("frobnicate"), 2, "frobnicate");
  expectOneLineError(run("eval --reference a.pcd"), 2, "--reconstruction");
  expectOneLineError(run("eval --reference a.pcd --reconstruction b.pcd --bogus"), 2,
                     "--bogus");
  expectOneLineError(run("sample --mesh m.ply --points many -o x.pcd"), 2, "--points");
  expectOneLineError(run("eval --reference a.pcd --reconstruction b.pcd --rho"), 2,
                     "--rho");
}

TEST_F(CliTest, BadInputsExitOneWithTheFileOrValueNamed)
{
  writeLattice("a.pcd", 0.0f);
  write("empty.obj", "# no faces\nv 0 0 0\n");
  write("garbage.ply", "this is not a ply file\n");
  write("nan.pcd",
        "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
        "WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\nnan nan nan\n"
        "nan 1 nan\n");
  write("negative.yaml", "boxes:\n  - center: [0, 0, 0]\n    size: [0.1, -0.1, 0.1]\n");
  write("cloud.xyz", "0 0 0\n");
  const std::string a = path("a.pcd");

  expectOneLineError(
      run("eval --reference " + path("missing.pcd") + " --reconstruction " + a), 1,
      "missing.pcd");
  expectOneLineError(
      run("eval --reference " + a + " --reconstruction " + path("empty.obj")), 1,
      "empty.obj");
  expectOneLineError(
      run("eval --reference " + path("garbage.ply") + " --reconstruction " + a), 1,
      "garbage.ply");
  expectOneLineError(
      run("eval --reference " + path("nan.pcd") + " --reconstruction " + a), 1,
      "no finite point");
  expectOneLineError(run("eval --reference " + a + " --reconstruction " + a + " --rho 0"),
                     1, "--rho");
  expectOneLineError(
      run("eval --reference " + a + " --reconstruction " + a + " --rho -1"), 1, "--rho");
  expectOneLineError(
      run("eval --reference " + a + " --reconstruction " + a + " --resolution 0"), 1,
      "--resolution");
  expectOneLineError(
      run("eval --reference " + path("cloud.xyz") + " --reconstruction " + a), 1, ".xyz");
  expectOneLineError(run("eval --reference " + a + " --reconstruction " + a + " --roi " +
                         path("negative.yaml")),
                     1, "negative.yaml");
  expectOneLineError(run("sample --mesh " + path("missing.obj") + " -o " + path("o.pcd")),
                     1, "missing.obj");
  expectOneLineError(run("sample --mesh " + kFixtures + "/plant_like.ply --points 0 -o " +
                         path("o.pcd")),
                     1, "--points");
  expectOneLineError(
      run("sample --mesh " + kFixtures + "/plant_like.ply -o " + path("o.txt")), 1,
      "o.txt");
  expectOneLineError(run("sample --mesh " + kFixtures +
                         "/plant_like.ply --voxel -0.1 -o " + path("o.pcd")),
                     1, "--voxel");
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

TEST_F(CliTest, PlantBadArgumentsAreOneLineErrors)
{
  expectOneLineError(run("plant --seed 1 --stage -1 -o " + path("x")), 1, "growth_stage");
  expectOneLineError(run("plant --model " + kFixtures +
                         "/plant_cm_zup.dae --labels trunk=.* -o " + path("x")),
                     1, "trunk");
  expectOneLineError(run("plant --model " + path("nothing.dae") + " -o " + path("x")), 1,
                     "nothing.dae");
  expectOneLineError(run("plant -o " + path("x")), 1, "--seed");
  expectOneLineError(run("plant --seed 1 --base 1,2 -o " + path("x")), 1, "--base");
  expectOneLineError(run("plant --seed 1 --model m.dae -o " + path("x")), 2, "excludes");
  expectOneLineError(run("plant --seed 1 --labels stem=.* -o " + path("x")), 2,
                     "--model");
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
  const ToolRun r = run("capture --plant 2 --intrinsics 160x120:114.25,114.25,79.5,59.5 -o " +
                        path("view.pcd") + " --depth " + path("depth.png") + " --map " +
                        path("map.bt"));
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
  EXPECT_NE(r.out.find(std::to_string(plant) + " on the plant"), std::string::npos) << r.out;

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

TEST_F(CliTest, CaptureBadArgumentsAreOneLineErrors)
{
  const std::string out = " -o " + path("v.pcd");
  expectOneLineError(run("capture" + out), 1, "--plant");
  expectOneLineError(run("capture --plant 1 --pose 1,2,3" + out), 2, "--pose");
  expectOneLineError(run("capture --plant 1 --pose 1,2,3,0,0,0,0" + out), 1, "quaternion");
  expectOneLineError(run("capture --plant 1 --intrinsics l516" + out), 1, "l516");
  expectOneLineError(run("capture --plant 1 --noise-seed 3" + out), 2, "--noise");
  expectOneLineError(run("capture --plant 1 --resolution -1 --map " + path("m.bt") + out),
                     1, "resolution");
  expectOneLineError(run("capture --plant 1 -o " + path("v.xyz")), 1, "v.xyz");
  expectOneLineError(run("capture --plant 1 --map " + path("m.vdb") + out), 1, "m.vdb");
}

namespace {

/// A fast trial config: a 160 x 120 camera with the L515's field of view, 32 x 24 rays.
const char* kSmallTrial = "camera: 160x120:114.25,114.25,79.5,59.5\n"
                          "gain: {rays_x: 32, rays_y: 24}\n";

} // namespace

TEST_F(CliTest, ReconstructWritesStepsSummaryMapAndReconstruction)
{
  write("small.yaml", kSmallTrial);
  const ToolRun r = run("reconstruct --plant 0 --planner nbv --attention leaf-nodes --views 3 "
                        "--config " + path("small.yaml") + " -o " + path("t"));
  ASSERT_EQ(r.code, 0) << r.err;
  // A title, one line per view, views to reach F1 0.8 / 0.9, what was written.
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 6) << r.out;
  EXPECT_NE(r.out.find("views to reach F1 0.8 / 0.9: whole_plant "), std::string::npos);
  EXPECT_NE(r.out.find("view  2"), std::string::npos) << r.out;

  const auto rows = readCsv(slurp(path("t/steps.csv")));
  ASSERT_EQ(rows.size(), 4u);
  const std::vector<std::string>& header = rows[0];
  for (const char* column : {"view", "gain", "plan_ms", "capture_ms", "insert_ms",
                             "whole_plant_precision", "whole_plant_recall", "whole_plant_f1",
                             "whole_plant_chamfer", "main_stem_f1", "leaf_nodes_f1"})
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
  const std::string f1 = rows[3][std::find(header.begin(), header.end(), "whole_plant_f1") -
                                 header.begin()];
  EXPECT_DOUBLE_EQ(summary["levels"]["whole_plant"]["final_f1"].get<double>(), std::stod(f1));

  pcl::PointCloud<pcl::PointXYZ> reconstruction;
  plantnbv::io::loadCloud(path("t/reconstruction.pcd"), reconstruction);
  EXPECT_EQ(std::to_string(reconstruction.size()), rows[3][14]); // occupied_voxels
  const auto tree = plantnbv::readOcTree(path("t/map.bt"));
  ASSERT_TRUE(tree);
}

TEST_F(CliTest, ReconstructIsTheSameOnOneAndTwoThreads)
{
  write("small.yaml", kSmallTrial);
  const std::string common = "reconstruct --plant 1 --yaw-deg 60 --planner random --seed 5 "
                             "--views 3 --config " + path("small.yaml");
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
  ASSERT_EQ(run("plant --model " + kFixtures + "/plant_cm_zup.dae -o " + path("p")).code, 0);
  plantnbv::TriangleMesh placed = plantnbv::io::loadMesh(path("p/plant.ply"));
  Eigen::Vector3f lo, hi;
  placed.bounds(lo, hi);
  auto summary = nlohmann::json::parse(slurp(path("m/summary.json")));
  EXPECT_NEAR(summary["config"]["sector"]["height"].get<double>(), hi.z() - 0.8, 1e-6);
  ASSERT_EQ(run(model + " --sector-height 0.5 -o " + path("n")).code, 0);
  summary = nlohmann::json::parse(slurp(path("n/summary.json")));
  EXPECT_EQ(summary["config"]["sector"]["height"].get<double>(), 0.5);
}

TEST_F(CliTest, ReconstructBadArgumentsAreOneLineErrors)
{
  const std::string out = " -o " + path("x");
  expectOneLineError(run("reconstruct --plant 1 --planner greedy" + out), 1, "greedy");
  expectOneLineError(run("reconstruct --plant 1 --candidates 10" + out), 1, "--candidates");
  expectOneLineError(run("reconstruct --plant 1 --pattern 5 --planner predefined" + out), 1,
                     "pattern");
  expectOneLineError(run("reconstruct --plant 1 --views 0" + out), 1, "views");
  expectOneLineError(run("reconstruct --plant 1 --attention stems" + out), 1, "stems");
  expectOneLineError(run("reconstruct --model " + kFixtures +
                         "/plant_cm_zup.dae --attention leaf-nodes" + out),
                     1, "leaf_nodes");
  write("bad.yaml", "sector: {radius: 0.4, hieght: 0.7}\n");
  expectOneLineError(run("reconstruct --plant 1 --config " + path("bad.yaml") + out), 1,
                     "hieght");
  write("bad2.yaml", "views: ten\n");
  expectOneLineError(run("reconstruct --plant 1 --config " + path("bad2.yaml") + out), 1,
                     "views");
  expectOneLineError(run("reconstruct --plant 1 --config " + path("none.yaml") + out), 1,
                     "none.yaml");
  expectOneLineError(run("reconstruct --plant 1"), 2, "--output");
}

TEST_F(CliTest, ReconstructSnapshotShowsTheTrial)
{
  write("small.yaml", kSmallTrial);
  const ToolRun r = run("reconstruct --plant 0 --views 2 --config " + path("small.yaml") +
                        " -o " + path("s") + " --snapshot");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string png = slurp(path("s/snapshot.png"));
  ASSERT_GT(png.size(), 24u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_EQ(std::uint8_t(png[18]) * 256 + std::uint8_t(png[19]), 1200); // width
  EXPECT_EQ(std::uint8_t(png[22]) * 256 + std::uint8_t(png[23]), 1200); // height
  EXPECT_GT(png.size(), 50000u); // not blank
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
  auto bad = [&](const std::string& name, const std::string& text, const std::string& needle) {
    write(name, text);
    expectOneLineError(run("campaign run " + path(name) + out), 1, needle);
  };
  const std::string base = tinyCampaign();
  bad("unknown.yaml", base + "    candidats: [9]\n", "studies[0].candidats: unknown key");
  bad("type.yaml", "views: ten\n" + base.substr(base.find("plants")),
      "views: 'ten' is not an integer");
  bad("zero.yaml", base + "    candidates: [9, 10]\n",
      "studies[0].candidates[1]: 10 is not a multiple of the 9 grid cells");
  bad("roi.yaml",
      base.substr(0, base.find("      - {type: nbv")) +
          "      - {type: nbv, attention: stems}\n",
      "'" + path("roi.yaml") + "' studies[0].planners[0].attention: unknown ROI 'stems'");
  bad("pattern.yaml",
      base.substr(0, base.find("      - {type: nbv")) +
          "      - {type: predefined, patterns: [1, 5]}\n",
      "studies[0].planners[0].patterns[1]: 5 is not a pattern 1-4");
  bad("trialviews.yaml", "trial: {views: 3}\n" + base.substr(base.find("name:")),
      "trial.views: set by the campaign");
  bad("trialunknown.yaml",
      base.substr(0, base.find("  gain:")) + "  gain: {rays: 32}\n" +
          base.substr(base.find("studies:")),
      "trial.gain.rays: unknown key");
  bad("noviews.yaml", base.substr(0, base.find("views: 3")) + "views: 0\n" +
                          base.substr(base.find("levels:")),
      "views: 0, expected >= 1");
  bad("level.yaml", base.substr(0, base.find("levels:")) + "levels: [leaves]\n" +
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
  const ToolRun ref = run("campaign run " + path("tiny.yaml") + " -o " + path("ref") + " -j 2");
  ASSERT_EQ(ref.code, 0) << ref.err;
  EXPECT_NE(ref.out.find("12 of 12 trials done"), std::string::npos) << ref.out;
  // Not a terminal: one plain line per finished trial.
  EXPECT_NE(ref.out.find("[12/12] "), std::string::npos) << ref.out;

  // Start on one worker, kill -9 after the first result file appears.
  const std::string cmd = kTool + " campaign run " + path("tiny.yaml") + " -o " + path("run") +
                          " -j 1 >" + path("first.out") + " 2>&1 </dev/null & echo $! >" +
                          path("pid");
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const fs::path trials = dir_ / "run" / "trials";
  bool seen = false;
  for (int i = 0; i < 6000 && !seen; ++i) { // up to 60 s
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(trials, ec))
      seen = seen || entry.path().filename().string()[0] != '.';
    if (!seen)
      std::system("sleep 0.01");
  }
  ASSERT_TRUE(seen) << slurp(path("first.out"));
  std::string pid = slurp(path("pid"));
  pid.erase(pid.find_last_not_of(" \n") + 1);
  ASSERT_FALSE(pid.empty());
  // Wait until it is gone (or a zombie nobody reaps), at most 10 s.
  std::system(("kill -9 " + pid + " 2>/dev/null; i=0; while [ $i -lt 1000 ] && [ -d /proc/" +
               pid + " ] && ! grep -q ') Z' /proc/" + pid + "/stat 2>/dev/null; do sleep 0.01; " +
               "i=$((i+1)); done")
                  .c_str());
  const std::size_t after_kill = trialFiles(dir_ / "run").size();
  EXPECT_GE(after_kill, 1u);

  const ToolRun resumed = run("campaign run " + path("tiny.yaml") + " -o " + path("run") + " -j 2");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find(std::to_string(after_kill) + " already done"), std::string::npos)
      << resumed.out;
  const ToolRun status = run("campaign status " + path("run"));
  ASSERT_EQ(status.code, 0) << status.err;
  EXPECT_NE(status.out.find("12 trials, 12 done, 0 failed, 0 missing"), std::string::npos)
      << status.out;

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
  const auto rows = readCsv(slurp(path("report/curves.csv")));
  ASSERT_EQ(rows.size(), 1u + 3u * 2u * 3u);
  EXPECT_EQ(rows[0][5], "f1_mean");
  const std::string summary = slurp(path("report/summary.md"));
  EXPECT_NE(summary.find("12 trials done, 0 failed"), std::string::npos) << summary;
  EXPECT_NE(summary.find("| nbv-leaf-nodes | predefined |"), std::string::npos) << summary;
}

TEST_F(CliTest, CampaignTrialThatThrowsIsRecordedAndTheOthersFinish)
{
  // A model plant whose file disappears before the run.
  fs::copy_file(kFixtures + "/plant_cm_zup.dae", path("gone.dae"));
  write("fail.yaml", tinyCampaign("  - {model: gone.dae}\n"));
  fs::remove(path("gone.dae"));
  const ToolRun r = run("campaign run " + path("fail.yaml") + " -o " + path("c") + " -j 2");
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
  EXPECT_NE(status.out.find("24 trials, 12 done, 12 failed, 0 missing"), std::string::npos)
      << status.out;
  EXPECT_NE(status.out.find("failed: main/nbv-leaf-nodes/gone/yaw000/rep0: "), std::string::npos)
      << status.out;
  // Another definition in the same directory is refused.
  write("other.yaml", tinyCampaign() + "    candidates: [9]\n");
  expectOneLineError(run("campaign run " + path("other.yaml") + " -o " + path("c")), 1,
                     "another campaign");
}
