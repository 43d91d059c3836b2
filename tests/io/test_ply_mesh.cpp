#include <algorithm>
#include <cstring>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/io/mesh_io.h>

#include "io_test_util.h"

using plantnbv::FormatError;
using plantnbv::PartLabel;
using plantnbv::TriangleMesh;
using plantnbv::io::loadMesh;
using plantnbv::io::MeshLoadOptions;
using plantnbv::io::saveMeshPly;
using plantnbv::test::TempDir;
using plantnbv::test::thrownMessage;

namespace {

TriangleMesh randomMesh(std::size_t vertices, std::size_t triangles, std::uint64_t seed)
{
  plantnbv::Rng rng(seed);
  TriangleMesh m;
  for (std::size_t i = 0; i < vertices; ++i)
    m.vertices.emplace_back(static_cast<float>(rng.uniform(-1, 1)),
                            static_cast<float>(rng.uniform(-1, 1)),
                            static_cast<float>(rng.uniform(0, 2)));
  for (std::size_t t = 0; t < triangles; ++t) {
    m.triangles.push_back({static_cast<std::uint32_t>(rng.index(vertices)),
                           static_cast<std::uint32_t>(rng.index(vertices)),
                           static_cast<std::uint32_t>(rng.index(vertices))});
    m.labels.push_back(static_cast<PartLabel>(rng.index(7)));
  }
  return m;
}

/// Big-endian bytes of a value (the PLY writer of the test, independent of ours).
template <typename T>
std::string bigEndian(T v)
{
  std::string s(sizeof(T), '\0');
  std::memcpy(s.data(), &v, sizeof(T));
  std::reverse(s.begin(), s.end()); // the test host is little-endian
  return s;
}

} // namespace

TEST(PlyMesh, RoundTripWithLabelsIsExact)
{
  TempDir dir;
  const TriangleMesh m = randomMesh(500, 1000, 3);
  const std::string path = dir.file("mesh.ply");
  saveMeshPly(path, m);
  const TriangleMesh back = loadMesh(path);
  EXPECT_EQ(back.vertices, m.vertices);
  EXPECT_EQ(back.triangles, m.triangles);
  EXPECT_EQ(back.labels, m.labels);
  EXPECT_TRUE(back.node_ids.empty());
}

TEST(PlyMesh, RoundTripWithoutLabels)
{
  TempDir dir;
  TriangleMesh m = randomMesh(10, 20, 4);
  m.labels.clear();
  const std::string path = dir.file("plain.ply");
  saveMeshPly(path, m);
  const TriangleMesh back = loadMesh(path);
  EXPECT_EQ(back.triangles, m.triangles);
  EXPECT_TRUE(back.labels.empty());
}

TEST(PlyMesh, AsciiQuadsAreFanTriangulatedAndOtherPropertiesSkipped)
{
  TempDir dir;
  const std::string path =
      dir.write("quads.ply", "ply\r\n"
                             "format ascii 1.0\r\n"
                             "comment doubles, colours, normals\r\n"
                             "element vertex 5\r\n"
                             "property double x\r\n"
                             "property double y\r\n"
                             "property uchar red\r\n"
                             "property double z\r\n"
                             "property list uchar float extra\r\n"
                             "element edge 1\r\n"
                             "property int vertex1\r\n"
                             "property int vertex2\r\n"
                             "element face 3\r\n"
                             "property list uchar float texcoord\r\n"
                             "property list int uint vertex_index\r\n"
                             "property char label\r\n"
                             "end_header\r\n"
                             "0 0 255 0 0\r\n"
                             "1 0 0 0 2 0.5 0.5\r\n"
                             "1 1 0 0 0\r\n"
                             "0 1 0 0 1 7\r\n"
                             "0.5 0.5 0 1 0\r\n"
                             "0 1\r\n"
                             "0 4 0 1 2 3 1\r\n"
                             "2 0 0 3 0 1 4 5\r\n"
                             "0 2 0 1 3\r\n");
  const TriangleMesh m = loadMesh(path);
  ASSERT_EQ(m.size(), 3u); // quad -> 2, triangle -> 1, 2-vertex face -> none
  EXPECT_EQ(m.triangles[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_EQ(m.triangles[2], (std::array<std::uint32_t, 3>{0, 1, 4}));
  EXPECT_EQ(m.labels,
            (std::vector<PartLabel>{PartLabel::stem, PartLabel::stem, PartLabel::fruit}));
  EXPECT_EQ(m.vertices[4], Eigen::Vector3f(0.5f, 0.5f, 1.0f));
}

TEST(PlyMesh, BigEndianDoublesAndShortLabels)
{
  TempDir dir;
  std::string ply = "ply\n"
                    "format binary_big_endian 1.0\n"
                    "element vertex 4\n"
                    "property double x\n"
                    "property double y\n"
                    "property double z\n"
                    "property float confidence\n"
                    "element face 1\n"
                    "property list ushort int vertex_indices\n"
                    "property short label\n"
                    "end_header\n";
  const double xyz[4][3] = {{0, 0, 0}, {0.25, 0, 0}, {0.25, 0.5, 0}, {0, 0.5, 1.5}};
  for (const auto& v : xyz) {
    for (double c : v)
      ply += bigEndian(c);
    ply += bigEndian(0.75f);
  }
  ply += bigEndian<std::uint16_t>(4);
  for (std::int32_t i : {3, 2, 1, 0})
    ply += bigEndian(i);
  ply += bigEndian<std::int16_t>(3);
  const TriangleMesh m = loadMesh(dir.write("be.ply", ply));
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m.vertices[3], Eigen::Vector3f(0, 0.5f, 1.5f));
  EXPECT_EQ(m.triangles[0], (std::array<std::uint32_t, 3>{3, 2, 1}));
  EXPECT_EQ(m.triangles[1], (std::array<std::uint32_t, 3>{3, 1, 0}));
  EXPECT_EQ(m.labels, (std::vector<PartLabel>{PartLabel::leaflet, PartLabel::leaflet}));
}

TEST(PlyMesh, MaxTrianglesIsRefused)
{
  TempDir dir;
  const std::string path = dir.file("ten.ply");
  saveMeshPly(path, randomMesh(6, 10, 5));
  MeshLoadOptions options;
  options.limits.max_triangles = 9;
  const std::string msg = thrownMessage<FormatError>([&] { loadMesh(path, options); });
  EXPECT_NE(msg.find("max_triangles"), std::string::npos) << msg;
  options.limits.max_triangles = 10;
  EXPECT_EQ(loadMesh(path, options).size(), 10u);
}

TEST(PlyMesh, MalformedFilesAreFormatErrors)
{
  TempDir dir;
  const std::string header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                             "property float y\nproperty float z\nelement face 1\n"
                             "property list uchar int vertex_indices\n";
  const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n";
  // A label outside PartLabel.
  const std::string label = thrownMessage<FormatError>([&] {
    loadMesh(dir.write("label.ply", header + "property uchar label\nend_header\n" +
                                        vertices + "3 0 1 2 9\n"));
  });
  EXPECT_NE(label.find("label 9"), std::string::npos) << label;
  // An index beyond the vertices.
  EXPECT_THROW(
      loadMesh(dir.write("index.ply", header + "end_header\n" + vertices + "3 0 1 3\n")),
      FormatError);
  // Truncated data.
  EXPECT_THROW(
      loadMesh(dir.write("short.ply", header + "end_header\n" + vertices + "3 0 1\n")),
      FormatError);
  // A count the file cannot hold is refused before anything is allocated for it.
  EXPECT_THROW(
      loadMesh(dir.write("huge.ply", "ply\nformat binary_little_endian 1.0\n"
                                     "element vertex 4000000000\nproperty float x\n"
                                     "property float y\nproperty float z\n"
                                     "end_header\n")),
      FormatError);
  // No x.
  EXPECT_THROW(loadMesh(dir.write("nox.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"
                                             "property float y\nend_header\n1\n")),
               FormatError);
  // Not a number in ASCII data.
  EXPECT_THROW(
      loadMesh(dir.write("nan.ply", header + "end_header\n0 0 zero\n1 0 0\n0 1 0\n"
                                             "3 0 1 2\n")),
      FormatError);
  // A point cloud is not a mesh.
  const std::string cloud = thrownMessage<FormatError>([&] {
    loadMesh(dir.write("cloud.ply",
                       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                       "property float y\nproperty float z\nend_header\n1 2 3\n"));
  });
  EXPECT_NE(cloud.find("no triangles"), std::string::npos) << cloud;
  EXPECT_THROW(loadMesh(dir.write("garbage.ply", std::string(10000, '\x07'))),
               FormatError);
}

TEST(PlyMesh, SaveRefusesAnInvalidMeshAndAnUnwritablePath)
{
  TempDir dir;
  TriangleMesh m = randomMesh(3, 1, 6);
  EXPECT_THROW(saveMeshPly(dir.file("no/dir/m.ply"), m), plantnbv::IoError);
  m.triangles[0][0] = 3;
  EXPECT_THROW(saveMeshPly(dir.file("bad.ply"), m), FormatError);
}
