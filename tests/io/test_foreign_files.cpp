// Files as other tools write them: CRLF line endings (Windows editors, SketchUp, Blender
// on Windows), Collada units whose name and value disagree, nested Collada transforms,
// VRML coordinates shared through DEF/USE.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <plantnbv/common/box.h>
#include <plantnbv/common/triangle_mesh.h>
#include <plantnbv/io/depth_image_io.h>
#include <plantnbv/io/detections_io.h>
#include <plantnbv/io/frames_folder.h>
#include <plantnbv/io/mesh_io.h>
#include <plantnbv/io/roi_io.h>

#include "collada_text.h"
#include "io_test_util.h"

using plantnbv::Detection;
using plantnbv::Pose;
using plantnbv::Roi;
using plantnbv::TriangleMesh;
using plantnbv::io::CameraInfo;
using plantnbv::io::FramesFolder;
using plantnbv::io::loadMesh;
using plantnbv::io::loadRoi;
using plantnbv::io::readCameraInfo;
using plantnbv::io::readDetections;
using plantnbv::io::readTumFileList;
using plantnbv::io::readTumTrajectory;
using plantnbv::io::saveMaskPng;
using plantnbv::test::fixture;
using plantnbv::test::readBytes;
using plantnbv::test::TempDir;

namespace fs = std::filesystem;

namespace {

/// `text` with every "\n" replaced by "\r\n".
std::string crlf(const std::string& text)
{
  std::string out;
  for (char c : text) {
    if (c == '\n')
      out += '\r';
    out += c;
  }
  return out;
}

/// Writes `text` as `name` (LF) and as `crlf_<name>` (CRLF) and returns both paths.
std::pair<std::string, std::string> writeBoth(const TempDir& dir, const std::string& name,
                                              const std::string& text)
{
  EXPECT_EQ(text.find('\r'), std::string::npos) << name << " is not LF already";
  return {dir.write(name, text), dir.write("crlf_" + name, crlf(text))};
}

void expectSameRoi(const Roi& a, const Roi& b)
{
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.boxes()[i].name, b.boxes()[i].name) << i;
    EXPECT_EQ(a.boxes()[i].center, b.boxes()[i].center) << i;
    EXPECT_EQ(a.boxes()[i].size, b.boxes()[i].size) << i;
  }
}

/// Vertices, triangles, labels and node names equal to the last bit.
void expectSameMesh(const TriangleMesh& a, const TriangleMesh& b)
{
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  for (std::size_t i = 0; i < a.vertices.size(); ++i)
    EXPECT_EQ(a.vertices[i], b.vertices[i]) << "vertex " << i;
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.labels, b.labels);
  EXPECT_EQ(a.node_ids, b.node_ids);
  EXPECT_EQ(a.node_names, b.node_names);
}

/// A fixture loaded as it is and converted to CRLF: the same mesh.
void expectCrlfFixtureLoadsTheSame(const std::string& name)
{
  SCOPED_TRACE(name);
  TempDir dir;
  const std::string text = readBytes(fixture(name));
  ASSERT_FALSE(text.empty());
  const auto [lf, cr] = writeBoth(dir, name, text);
  const TriangleMesh a = loadMesh(lf);
  const TriangleMesh b = loadMesh(cr);
  EXPECT_FALSE(a.empty());
  expectSameMesh(a, b);
}

/// The one triangle (0,0,0), (1,0,0), (0,2,0) of geometry "tri", with `asset` and the
/// visual scene's content.
std::string triangleCollada(const std::string& asset, const std::string& scene)
{
  return plantnbv::test::colladaDocument(asset, plantnbv::test::colladaTriangleGeometry(),
                                         "", scene);
}

/// The three corners of triangle t.
std::vector<Eigen::Vector3f> corners(const TriangleMesh& m, std::size_t t)
{
  std::vector<Eigen::Vector3f> out;
  for (std::uint32_t v : m.triangles.at(t))
    out.push_back(m.vertices.at(v));
  return out;
}

void expectNear(const std::vector<Eigen::Vector3f>& got,
                const std::vector<Eigen::Vector3f>& expected, double tol)
{
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < got.size(); ++i)
    EXPECT_LE((got[i] - expected[i]).norm(), tol)
        << "corner " << i << ": got " << got[i].transpose() << ", expected "
        << expected[i].transpose();
}

} // namespace

TEST(ForeignFiles, CrlfRoiFilesOfBothForms)
{
  TempDir dir;
  const std::string centre_size = "# ROIs\n"
                                  "boxes:\n"
                                  "  - name: main_stem\n"
                                  "    center: [1.0, 0.0, 1.15]\n"
                                  "    size: [0.05, 0.05, 0.7]\n"
                                  "  - name: \"quoted name\"\n"
                                  "    min: [0.5, -0.25, 1.0]\n"
                                  "    max: [1.5, 0.25, 2.0]\n";
  const std::string list = "- {min: [0.5, -0.25, 1.0], max: [1.5, 0.25, 2.0]}\n"
                           "- name: leaf\n"
                           "  min: [-2, 0.125, -1]\n"
                           "  max: [-1, 0.375, 3]\n";
  for (const std::string& text : {centre_size, list}) {
    const auto [lf, cr] = writeBoth(dir, "rois.yaml", text);
    const Roi a = loadRoi(lf);
    const Roi b = loadRoi(cr);
    EXPECT_EQ(a.size(), 2u);
    expectSameRoi(a, b);
  }
  // The names carry no '\r'.
  EXPECT_EQ(loadRoi(dir.write("n.yaml", crlf(centre_size))).boxes()[1].name,
            "quoted name");
  EXPECT_EQ(loadRoi(dir.write("l.yaml", crlf(list))).boxes()[1].name, "leaf");
}

TEST(ForeignFiles, CrlfCollada)
{
  TempDir dir;
  const auto [lf, cr] = writeBoth(
      dir, "tri.dae",
      triangleCollada("<unit name=\"meter\" meter=\"1\"/>\n<up_axis>Z_UP</up_axis>",
                      "<node id=\"n\" name=\"Leaf_1\">\n"
                      "  <translate>0 0 5</translate>\n"
                      "  <instance_geometry url=\"#tri\"/>\n"
                      "</node>"));
  const TriangleMesh a = loadMesh(lf);
  ASSERT_EQ(a.size(), 1u);
  expectNear(corners(a, 0), {{0, 0, 5}, {1, 0, 5}, {0, 2, 5}}, 0.0);
  expectSameMesh(a, loadMesh(cr));
  expectCrlfFixtureLoadsTheSame("plant_cm_zup.dae");
  expectCrlfFixtureLoadsTheSame("plant_cm_yup.dae");
}

TEST(ForeignFiles, CrlfVrml)
{
  expectCrlfFixtureLoadsTheSame("plant_yup.wrl");
}

TEST(ForeignFiles, CrlfObjAndAsciiStl)
{
  expectCrlfFixtureLoadsTheSame("two_groups.obj");
  expectCrlfFixtureLoadsTheSame("two_objects.obj");
  expectCrlfFixtureLoadsTheSame("tetra_ascii.stl");
}

TEST(ForeignFiles, CrlfCameraInfoAndTumFiles)
{
  TempDir dir;
  const std::string camera = "image_width: 8\n"
                             "image_height: 6\n"
                             "camera_name: narrow_stereo\n"
                             "camera_matrix:\n"
                             "  rows: 3\n"
                             "  cols: 3\n"
                             "  data: [10.5, 0., 4.25, 0., 11.25, 2.5,\n"
                             "         0., 0., 1.]\n"
                             "distortion_model: plumb_bob\n"
                             "distortion_coefficients:\n"
                             "  rows: 1\n"
                             "  cols: 5\n"
                             "  data: [0., 0., 0., 0., 0.]\n"
                             "depth_scale: 5000\n";
  const auto [cam_lf, cam_cr] = writeBoth(dir, "camera.yaml", camera);
  const CameraInfo a = readCameraInfo(cam_lf);
  const CameraInfo b = readCameraInfo(cam_cr);
  EXPECT_EQ(a.intrinsics.width, 8u);
  EXPECT_EQ(b.intrinsics.width, a.intrinsics.width);
  EXPECT_EQ(b.intrinsics.height, a.intrinsics.height);
  EXPECT_EQ(b.intrinsics.fx, a.intrinsics.fx);
  EXPECT_EQ(b.intrinsics.fy, a.intrinsics.fy);
  EXPECT_EQ(b.intrinsics.cx, a.intrinsics.cx);
  EXPECT_EQ(b.intrinsics.cy, a.intrinsics.cy);
  EXPECT_EQ(b.depth_scale, a.depth_scale);
  EXPECT_EQ(b.distortion_model, "plumb_bob");

  const auto [list_lf, list_cr] =
      writeBoth(dir, "depth.txt",
                "# depth images\n"
                "1305031102.175304 depth/1305031102.175304.png\n"
                "\n"
                "1305031102.211214 depth/1305031102.211214.png\n");
  const auto files_lf = readTumFileList(list_lf);
  const auto files_cr = readTumFileList(list_cr);
  ASSERT_EQ(files_lf.size(), 2u);
  ASSERT_EQ(files_cr.size(), files_lf.size());
  for (std::size_t i = 0; i < files_lf.size(); ++i) {
    EXPECT_EQ(files_cr[i].stamp_s, files_lf[i].stamp_s) << i;
    EXPECT_EQ(files_cr[i].file, files_lf[i].file) << i;
    EXPECT_EQ(files_cr[i].line, files_lf[i].line) << i;
  }
  EXPECT_EQ(files_cr[1].file, "depth/1305031102.211214.png");

  const auto [traj_lf, traj_cr] =
      writeBoth(dir, "groundtruth.txt",
                "# timestamp tx ty tz qx qy qz qw\n"
                "1305031102.1758 1.3405 0.6266 1.6575 0.6574 0.6126 -0.2949 -0.3248\n"
                "1305031102.2112 1.5 -0.25 2 0 0 0 1\n");
  const auto poses_lf = readTumTrajectory(traj_lf);
  const auto poses_cr = readTumTrajectory(traj_cr);
  ASSERT_EQ(poses_lf.size(), 2u);
  ASSERT_EQ(poses_cr.size(), poses_lf.size());
  for (std::size_t i = 0; i < poses_lf.size(); ++i) {
    EXPECT_EQ(poses_cr[i].stamp_s, poses_lf[i].stamp_s) << i;
    EXPECT_EQ(poses_cr[i].pose.position, poses_lf[i].pose.position) << i;
    EXPECT_EQ(poses_cr[i].pose.orientation.coeffs(),
              poses_lf[i].pose.orientation.coeffs())
        << i;
    EXPECT_EQ(poses_cr[i].line, poses_lf[i].line) << i;
  }
}

TEST(ForeignFiles, CrlfDetectionsAndFramesFolder)
{
  // Two frames folders, one LF and one CRLF, each with a detection file and its mask.
  TempDir dir;
  const std::string camera =
      "image_width: 8\nimage_height: 6\n"
      "camera_matrix: {rows: 3, cols: 3, data: [10.5, 0, 4.25, 0, "
      "11.25, 2.5, 0, 0, 1]}\n"
      "distortion_model: plumb_bob\n"
      "distortion_coefficients: {rows: 1, cols: 5, data: [0, 0, 0, "
      "0, 0]}\n";
  const std::string json =
      "{\"detections\": [\n"
      "  {\"class\": \"leaf_node\", \"score\": 0.5,\n"
      "   \"box\": [0, 0.25, 8, 6]},\n"
      "  {\"class\": \"fruit\", \"score\": 0.75, \"box\": [1, 2, 3, 4],\n"
      "   \"mask\": \"000000_1.png\"}\n"
      "]}\n";
  std::vector<std::uint8_t> mask(8 * 6, 0);
  mask[3] = 255;
  mask[47] = 7;
  std::vector<std::vector<Detection>> read;
  std::vector<FramesFolder> folders;
  folders.reserve(2);
  for (const std::string sub : {"lf", "crlf"}) {
    auto text = [&](const std::string& t) { return sub == "crlf" ? crlf(t) : t; };
    fs::create_directories(dir.file(sub + "/detections"));
    dir.write(sub + "/camera.yaml", text(camera));
    dir.write(sub + "/depth.txt",
              text("# depth\n0.000000 depth/000000.png\n1.000000 depth/000001.png\n"));
    dir.write(sub + "/groundtruth.txt",
              text("0.01 1 2 3 0 0 0 1\n0.99 1 2 3.5 0 0 0.6 0.8\n"));
    dir.write(sub + "/detections.txt", text("0.000000 detections/000000.json\n"));
    dir.write(sub + "/detections/000000.json", text(json));
    saveMaskPng(dir.file(sub + "/detections/000000_1.png"), 8, 6, mask);
    read.push_back(readDetections(dir.file(sub + "/detections/000000.json"), 8, 6));
    folders.emplace_back(dir.file(sub));
  }
  ASSERT_EQ(read[0].size(), 2u);
  ASSERT_EQ(read[1].size(), read[0].size());
  for (std::size_t i = 0; i < read[0].size(); ++i) {
    EXPECT_EQ(read[1][i].class_name, read[0][i].class_name) << i;
    EXPECT_EQ(read[1][i].score, read[0][i].score) << i;
    EXPECT_EQ(read[1][i].box_px, read[0][i].box_px) << i;
    EXPECT_EQ(read[1][i].mask, read[0][i].mask) << i;
  }
  EXPECT_EQ(read[1][1].mask, mask);

  ASSERT_EQ(folders[0].frames().size(), 2u);
  ASSERT_EQ(folders[1].frames().size(), folders[0].frames().size());
  for (std::size_t i = 0; i < folders[0].frames().size(); ++i) {
    const auto& a = folders[0].frames()[i];
    const auto& b = folders[1].frames()[i];
    EXPECT_EQ(b.stamp_s, a.stamp_s) << i;
    EXPECT_EQ(fs::path(b.depth_path).lexically_relative(folders[1].folder()),
              fs::path(a.depth_path).lexically_relative(folders[0].folder()))
        << i;
    EXPECT_EQ(b.T_W_O.position, a.T_W_O.position) << i;
    EXPECT_EQ(b.T_W_O.orientation.coeffs(), a.T_W_O.orientation.coeffs()) << i;
    EXPECT_EQ(b.pose_dt_s, a.pose_dt_s) << i;
    EXPECT_EQ(b.detections_path.empty(), a.detections_path.empty()) << i;
  }
  std::vector<Detection> frame_lf, frame_cr;
  folders[0].loadDetections(0, frame_lf);
  folders[1].loadDetections(0, frame_cr);
  ASSERT_EQ(frame_cr.size(), frame_lf.size());
  EXPECT_EQ(frame_cr[1].mask, mask);
}

TEST(ForeignFiles, ColladaUnitValueWinsOverItsName)
{
  // The name says centimetre, the value says millimetre: the value is the unit.
  TempDir dir;
  const TriangleMesh m = loadMesh(
      dir.write("mm.dae", triangleCollada("<unit name=\"centimeter\" meter=\"0.001\"/>"
                                          "<up_axis>Z_UP</up_axis>",
                                          "<node id=\"n\"><instance_geometry "
                                          "url=\"#tri\"/></node>")));
  ASSERT_EQ(m.size(), 1u);
  expectNear(corners(m, 0), {{0, 0, 0}, {0.001f, 0, 0}, {0, 0.002f, 0}}, 1e-9);
  Eigen::Vector3f lo, hi;
  m.bounds(lo, hi);
  EXPECT_FLOAT_EQ(hi.x() - lo.x(), 0.001f);
  EXPECT_FLOAT_EQ(hi.y() - lo.y(), 0.002f);
}

TEST(ForeignFiles, ColladaMatrixInsideATranslatedNode)
{
  // The inner matrix scales by 2, turns 90 degrees about z and moves by (0.5, 0, 0):
  // (x, y, z) -> (-2y + 0.5, 2x, 2z); the outer node then adds (1, 2, 3).
  TempDir dir;
  const TriangleMesh m = loadMesh(dir.write(
      "nested.dae", triangleCollada("<up_axis>Z_UP</up_axis>",
                                    "<node id=\"outer\"><translate>1 2 3</translate>\n"
                                    "  <node id=\"inner\" name=\"Leaf\">\n"
                                    "    <matrix>0 -2 0 0.5  2 0 0 0  0 0 2 0  0 0 0 "
                                    "1</matrix>\n"
                                    "    <instance_geometry url=\"#tri\"/>\n"
                                    "  </node>\n"
                                    "</node>")));
  ASSERT_EQ(m.size(), 1u);
  // (0,0,0) -> (1.5, 2, 3); (1,0,0) -> (1.5, 4, 3); (0,2,0) -> (-2.5, 2, 3).
  expectNear(corners(m, 0), {{1.5f, 2, 3}, {1.5f, 4, 3}, {-2.5f, 2, 3}}, 1e-6);
  ASSERT_EQ(m.node_ids.size(), 1u);
  EXPECT_EQ(m.node_names.at(m.node_ids[0]), "Leaf");
}

TEST(ForeignFiles, VrmlShapesSharingACoordinateNode)
{
  // VRML is Y up: file (x, y, z) becomes (x, -z, y).
  TempDir dir;
  const TriangleMesh m =
      loadMesh(dir.write("shared.wrl", "#VRML V2.0 utf8\n"
                                       "Shape {\n"
                                       "  geometry IndexedFaceSet {\n"
                                       "    coord DEF C Coordinate { "
                                       "point [ 0 0 0, 1 0 0, 0 2 0 ] "
                                       "}\n"
                                       "    coordIndex [ 0 1 2 -1 ]\n"
                                       "  }\n"
                                       "}\n"
                                       "Transform {\n"
                                       "  translation 0.5 0.25 -1\n"
                                       "  children [\n"
                                       "    Shape {\n"
                                       "      geometry IndexedFaceSet {\n"
                                       "        coord USE C\n"
                                       "        coordIndex [ 0 1 2 -1 ]\n"
                                       "      }\n"
                                       "    }\n"
                                       "  ]\n"
                                       "}\n"));
  ASSERT_EQ(m.size(), 2u);
  expectNear(corners(m, 0), {{0, 0, 0}, {1, 0, 0}, {0, 0, 2}}, 0.0);
  // Translated by file (0.5, 0.25, -1), i.e. (0.5, 1, 0.25) here, exactly.
  expectNear(corners(m, 1), {{0.5f, 1, 0.25f}, {1.5f, 1, 0.25f}, {0.5f, 1, 2.25f}}, 0.0);
  ASSERT_EQ(m.node_ids.size(), 2u);
  EXPECT_EQ(m.node_names.at(m.node_ids[0]), "shape_0");
  EXPECT_EQ(m.node_names.at(m.node_ids[1]), "shape_1");
}
