#include <map>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/io/mesh_io.h>

#include "io_test_util.h"

using plantnbv::FormatError;
using plantnbv::TriangleMesh;
using plantnbv::io::loadMesh;
using plantnbv::io::MeshLoadOptions;
using plantnbv::test::fixture;
using plantnbv::test::TempDir;
using plantnbv::test::thrownMessage;

namespace {

constexpr const char* kHeader = "#VRML V2.0 utf8\n";

/// The file's own axes (no Y-up conversion), to check transforms directly.
MeshLoadOptions fileAxes()
{
  MeshLoadOptions o;
  o.up_axis = MeshLoadOptions::UpAxis::z;
  return o;
}

std::map<std::string, std::size_t> trianglesPerName(const TriangleMesh& m)
{
  std::map<std::string, std::size_t> count;
  for (auto id : m.node_ids)
    ++count[m.node_names.at(id)];
  return count;
}

void expectNear(const Eigen::Vector3f& a, const Eigen::Vector3f& b)
{
  EXPECT_LT((a - b).norm(), 1e-6f) << a.transpose() << " vs " << b.transpose();
}

const char* const kTriangle = "Shape { geometry IndexedFaceSet { coord Coordinate { "
                              "point [ 0 0 0, 1 0 0, 0 1 0 ] } "
                              "coordIndex [ 0 1 2 -1 ] } }";

} // namespace

TEST(Vrml, FixtureLoadsZUpWithTransformsApplied)
{
  const TriangleMesh m = loadMesh(fixture("plant_yup.wrl"));
  ASSERT_EQ(m.size(), 13u); // 6 quads of the stem, 1 leaf triangle
  EXPECT_EQ(trianglesPerName(m),
            (std::map<std::string, std::size_t>{{"Stem", 12}, {"Leaf_1", 1}}));
  Eigen::Vector3f lo, hi;
  m.bounds(lo, hi);
  expectNear(lo, {-0.01f, -0.01f, 0.0f});
  expectNear(hi, {0.01f, 0.1f, 0.5f});
  // The leaf: rotated 90 degrees about the (file) up axis, moved 0.3 up, then Y up -> Z
  // up.
  std::size_t leaf = m.size();
  for (std::size_t t = 0; t < m.size(); ++t)
    if (m.node_names[m.node_ids[t]] == "Leaf_1")
      leaf = t;
  ASSERT_LT(leaf, m.size());
  const auto& tri = m.triangles[leaf];
  expectNear(m.vertices[tri[0]], {0.01f, 0.0f, 0.3f});
  expectNear(m.vertices[tri[1]], {0.01f, 0.1f, 0.3f});
  expectNear(m.vertices[tri[2]], {0.01f, 0.0f, 0.32f});
}

TEST(Vrml, TransformFollowsTheVrml97Order)
{
  TempDir dir;
  // scale before translation in the file: still T * S, so (1,0,0) -> (3,0,0).
  // center: rotating (2,0,0) by pi about Z around (1,0,0) gives (0,0,0).
  const std::string path = dir.write(
      "order.wrl",
      std::string(kHeader) + "Transform { scale 2 2 2 translation 1 0 0 children [ " +
          kTriangle +
          " ] }\n"
          "Transform { center 1 0 0 rotation 0 0 1 3.141592653589793 children [ "
          "Shape { geometry IndexedFaceSet { coord Coordinate { point [ 2 0 0, 2 "
          "1 0, 2 0 1 ] } coordIndex [ 0 1 2 ] } } ] }\n");
  const TriangleMesh m = loadMesh(path, fileAxes());
  ASSERT_EQ(m.size(), 2u);
  expectNear(m.vertices[m.triangles[0][1]], {3, 0, 0});
  expectNear(m.vertices[m.triangles[0][2]], {1, 2, 0});
  expectNear(m.vertices[m.triangles[1][0]], {0, 0, 0});
  expectNear(m.vertices[m.triangles[1][1]], {0, -1, 0});
}

TEST(Vrml, DefUseNamesAndNesting)
{
  TempDir dir;
  const std::string path = dir.write(
      "defuse.wrl", std::string(kHeader) +
                        "# a comment, then a PROTO that is skipped\n"
                        "PROTO Leaf [ field SFFloat size 1 ] { Group { } }\n"
                        "DEF Plant Transform { translation 0 0 1 children [\n"
                        "  DEF Stem Transform { children [ " +
                        kTriangle +
                        " ] }\n"
                        "  Transform { translation 5 0 0 children [ USE Stem ] }\n"
                        "  Shape { geometry DEF Fruit Sphere { radius 0.5 } }\n"
                        "  Shape { geometry Box { size 1 1 1 } }\n"
                        "  Leaf { size 2 }\n"
                        "] }\n"
                        "Shape { geometry IndexedFaceSet { coord Coordinate { point [ 0 "
                        "0 0, 1 0 0, 0 1 0, 1 1 "
                        "0 ] } coordIndex [ 0 1 3 2 ] } }\n"
                        "ROUTE A.b TO C.d\n");
  const TriangleMesh m = loadMesh(path, fileAxes());
  const auto names = trianglesPerName(m);
  EXPECT_EQ(names.at("Stem"), 2u);              // the original and its USE
  EXPECT_EQ(names.at("Plant"), 12u);            // the box: nearest DEF is the Transform
  EXPECT_EQ(names.at("Fruit"), 2u * 15u * 32u); // UV sphere: 16 stacks, 32 slices
  EXPECT_EQ(names.at("shape_4"), 2u);           // unnamed quad, fifth shape
  // The USE'd copy sits 5 further along x, inside Plant's translation.
  bool moved = false;
  for (const auto& v : m.vertices)
    moved = moved || (v - Eigen::Vector3f(6, 0, 1)).norm() < 1e-6f;
  EXPECT_TRUE(moved);
}

TEST(Vrml, PrimitivesHaveTheirSizes)
{
  TempDir dir;
  const std::string path = dir.write(
      "prims.wrl",
      std::string(kHeader) +
          "Shape { geometry Box { size 2 4 6 } }\n"
          "Transform { translation 10 0 0 children Shape { geometry Cylinder { "
          "radius 0.5 height 3 } } }\n"
          "Transform { translation 20 0 0 children Shape { geometry Cone { } } }\n");
  const TriangleMesh m = loadMesh(path); // Y up: the box's 4 along Y becomes Z
  Eigen::Vector3f lo, hi;
  m.bounds(lo, hi);
  expectNear(lo, {-1, -3, -2});
  expectNear(hi, {21, 3, 2});
  ASSERT_EQ(m.size(), 12u + 4u * 32u + 2u * 32u);
  double box_area = 0.0;
  for (std::size_t t = 0; t < 12; ++t)
    box_area += m.triangleArea(t);
  EXPECT_NEAR(box_area, 2 * (2 * 4 + 4 * 6 + 2 * 6), 1e-5);
}

TEST(Vrml, MaxTrianglesAndScale)
{
  MeshLoadOptions options;
  options.limits.max_triangles = 12;
  EXPECT_THROW(loadMesh(fixture("plant_yup.wrl"), options), FormatError);
  options.limits.max_triangles = 13;
  options.scale = 100.0;
  const TriangleMesh m = loadMesh(fixture("plant_yup.wrl"), options);
  Eigen::Vector3f lo, hi;
  m.bounds(lo, hi);
  EXPECT_NEAR(hi.z(), 50.0f, 1e-4);
}

TEST(Vrml, Errors)
{
  TempDir dir;
  const std::string not_vrml =
      thrownMessage<FormatError>([&] { loadMesh(dir.write("x.wrl", "Shape { }\n")); });
  EXPECT_NE(not_vrml.find("#VRML V2.0"), std::string::npos) << not_vrml;
  EXPECT_THROW(loadMesh(dir.write("v1.wrl", "#VRML V1.0 ascii\nSeparator { }\n")),
               FormatError);
  const std::string use = thrownMessage<FormatError>([&] {
    loadMesh(dir.write("use.wrl",
                       std::string(kHeader) + "\nTransform { children USE Nope }\n"));
  });
  EXPECT_NE(use.find("line 3"), std::string::npos) << use;
  EXPECT_NE(use.find("Nope"), std::string::npos) << use;
  EXPECT_THROW(
      loadMesh(dir.write("open.wrl", std::string(kHeader) + "Group { children [\n")),
      FormatError);
  EXPECT_THROW(
      loadMesh(dir.write("range.wrl",
                         std::string(kHeader) +
                             "Shape { geometry IndexedFaceSet { coord Coordinate { "
                             "point [ 0 0 0, 1 0 0, 0 1 0 ] } coordIndex [ 0 1 3 ] } }")),
      FormatError);
  EXPECT_THROW(loadMesh(dir.write("bad_transform.wrl",
                                  std::string(kHeader) +
                                      "Transform { translation 1 2 children [ " +
                                      kTriangle + " ] }")),
               FormatError);
  const std::string empty = thrownMessage<FormatError>([&] {
    loadMesh(dir.write("points.wrl",
                       std::string(kHeader) +
                           "Shape { geometry PointSet { coord Coordinate { point "
                           "[ 0 0 0 ] } } }\nInline { url \"other.wrl\" }\n"));
  });
  EXPECT_NE(empty.find("no triangles"), std::string::npos) << empty;
  EXPECT_NE(empty.find("Inline"), std::string::npos) << empty;
}
