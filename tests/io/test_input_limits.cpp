// The caps of input_limits.h and the handling of non-finite values, reader by reader:
// every hostile header is refused with a FormatError naming the file and the cap before
// anything is allocated for it.
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <sys/stat.h>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/camera/depth_image.h>
#include <plantnbv/common/error.h>
#include <plantnbv/io/cloud_io.h>
#include <plantnbv/io/depth_image_io.h>
#include <plantnbv/io/file_kind.h>
#include <plantnbv/io/input_limits.h>
#include <plantnbv/io/mesh_io.h>
#include <plantnbv/io/roi_io.h>

#include "io_test_util.h"

using plantnbv::CloudXYZ;
using plantnbv::CloudXYZL;
using plantnbv::FormatError;
using plantnbv::io::defaultInputLimits;
using plantnbv::io::InputLimits;
using plantnbv::io::loadCloud;
using plantnbv::io::loadMesh;
using plantnbv::io::loadRoi;
using plantnbv::io::MeshLoadOptions;
using plantnbv::io::setDefaultInputLimits;
using plantnbv::test::TempDir;
using plantnbv::test::thrownMessage;

namespace {

bool contains(const std::string& s, const std::string& part)
{
  return s.find(part) != std::string::npos;
}

/// Sets the process-wide limits for one test and restores the previous ones.
class DefaultLimits {
public:
  explicit DefaultLimits(const InputLimits& limits) : saved_(defaultInputLimits())
  {
    setDefaultInputLimits(limits);
  }
  ~DefaultLimits() { setDefaultInputLimits(saved_); }

private:
  InputLimits saved_;
};

const std::string kXyz = "property float x\nproperty float y\nproperty float z\n";

/// An ASCII PLY mesh: a unit square as two triangles, with `vertex` in place of the
/// second vertex line.
std::string squarePly(const std::string& vertex = "1 0 0")
{
  return "ply\nformat ascii 1.0\nelement vertex 4\n" + kXyz +
         "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n" +
         vertex + "\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
}

const char* const kTrianglePcd = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
                                 "COUNT 1 1 1\nWIDTH 3\nHEIGHT 1\nPOINTS 3\nDATA ascii\n"
                                 "0 0 0\n1 0 0\n0 1 0\n";

} // namespace

TEST(InputLimits, DefaultsAreGenerousAndUnlimitedIsZero)
{
  const InputLimits d;
  EXPECT_EQ(d.max_file_bytes, std::uint64_t{2} << 30);
  EXPECT_EQ(d.max_points, 100'000'000u);
  EXPECT_EQ(d.max_triangles, 50'000'000u);
  const InputLimits none = InputLimits::unlimited();
  EXPECT_EQ(none.max_file_bytes + none.max_points + none.max_triangles, 0u);
}

TEST(InputLimits, HugePlyVertexCountIsRefusedFromTheHeader)
{
  TempDir dir;
  const std::string path = dir.write("huge.ply", "ply\nformat binary_little_endian 1.0\n"
                                                 "element vertex 1000000000000\n" +
                                                     kXyz + "end_header\n");
  std::string msg = thrownMessage<FormatError>([&] {
    CloudXYZ cloud;
    loadCloud(path, cloud);
  });
  EXPECT_TRUE(contains(msg, path + ": 1000000000000 points exceed the limit of "
                                   "100000000 (InputLimits::max_points)"))
      << msg;
  msg = thrownMessage<FormatError>([&] { loadMesh(path); });
  EXPECT_TRUE(contains(msg, path + ": 1000000000000 vertices exceed the limit of "
                                   "100000000 (InputLimits::max_points)"))
      << msg;
  // Without a cap, the body check still refuses it before allocating.
  MeshLoadOptions unlimited;
  unlimited.limits = InputLimits::unlimited();
  msg = thrownMessage<FormatError>([&] { loadMesh(path, unlimited); });
  EXPECT_TRUE(contains(msg, "too short")) << msg;
}

TEST(InputLimits, HugePcdPointCountIsRefusedFromTheHeader)
{
  TempDir dir;
  for (const char* data : {"ascii", "binary", "binary_compressed"}) {
    const std::string path =
        dir.write(std::string(data) + ".pcd",
                  "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                  "WIDTH 1000000000000\nHEIGHT 1\nPOINTS 1000000000000\nDATA " +
                      std::string(data) + "\n");
    const std::string msg = thrownMessage<FormatError>([&] {
      CloudXYZ cloud;
      loadCloud(path, cloud);
    });
    EXPECT_TRUE(contains(msg, "(InputLimits::max_points)")) << msg;
    // With no cap the file is too short for its count: still refused before PCL reads.
    const std::string unlimited = thrownMessage<FormatError>([&] {
      CloudXYZ cloud;
      loadCloud(path, cloud, InputLimits::unlimited());
    });
    EXPECT_TRUE(contains(unlimited, "truncated")) << data << ": " << unlimited;
  }
}

TEST(InputLimits, MalformedPcdSizesAreRefused)
{
  TempDir dir;
  auto message = [&](const std::string& header) {
    const std::string path = dir.write("bad.pcd", header);
    return thrownMessage<FormatError>([&] {
      CloudXYZ cloud;
      loadCloud(path, cloud, InputLimits::unlimited());
    });
  };
  EXPECT_TRUE(
      contains(message("FIELDS x y z\nSIZE 4 3 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n"
                       "0 0 0\n"),
               "SIZE 3 is not 1, 2, 4 or 8"));
  EXPECT_TRUE(contains(message("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 0 1\n"
                               "WIDTH 1\nDATA ascii\n0 0 0\n"),
                       "COUNT 0 is not in"));
  EXPECT_TRUE(contains(message("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
                               "WIDTH 9223372036854775808\nHEIGHT 4\nDATA binary\n"),
                       "WIDTH x HEIGHT overflows"));
  // A compressed block that claims more than LZF can expand to.
  std::string compressed = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1000\n"
                           "DATA binary_compressed\n";
  const std::uint32_t sizes[2] = {4, 12000};
  compressed.append(reinterpret_cast<const char*>(sizes), 8);
  compressed += "abcd";
  EXPECT_TRUE(contains(message(compressed), "inconsistent compressed data"));
}

TEST(InputLimits, FileSizeIsCheckedBeforeReading)
{
  TempDir dir;
  InputLimits small;
  small.max_file_bytes = 40;
  const std::string cloud_path = dir.write("cloud.pcd", kTrianglePcd);
  std::string msg = thrownMessage<FormatError>([&] {
    CloudXYZ cloud;
    loadCloud(cloud_path, cloud, small);
  });
  EXPECT_TRUE(contains(msg, cloud_path + ": ") &&
              contains(msg, "bytes exceed the limit of 40 (InputLimits::max_file_bytes)"))
      << msg;

  MeshLoadOptions options;
  options.limits = small;
  for (const auto& [name, content] :
       {std::pair<std::string, std::string>{"m.ply", squarePly()},
        {"m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n# padding\n"},
        {"m.wrl",
         "#VRML V2.0 utf8\nShape { geometry Box { size 1 1 1 } }\n# padding\n"}}) {
    const std::string path = dir.write(name, content);
    msg = thrownMessage<FormatError>([&] { loadMesh(path, options); });
    EXPECT_TRUE(contains(msg, "(InputLimits::max_file_bytes)")) << name << ": " << msg;
    EXPECT_NO_THROW(loadMesh(path)) << name;
  }

  // The ROI reader takes the process-wide limits.
  const std::string roi =
      dir.write("rois.yaml",
                "boxes:\n  - name: stem\n    center: [1, 0, 1]\n    size: [1, 1, 1]\n");
  EXPECT_NO_THROW(loadRoi(roi));
  const DefaultLimits guard(small);
  msg = thrownMessage<FormatError>([&] { loadRoi(roi); });
  EXPECT_TRUE(contains(msg, "(InputLimits::max_file_bytes)")) << msg;
}

TEST(InputLimits, PointAndTriangleCaps)
{
  TempDir dir;
  InputLimits limits;
  limits.max_points = 2;
  const std::string pcd = dir.write("three.pcd", kTrianglePcd);
  const std::string ply =
      dir.write("three.ply", "ply\nformat ascii 1.0\nelement vertex 3\n" + kXyz +
                                 "end_header\n0 0 0\n1 0 0\n0 1 0\n");
  for (const std::string& path : {pcd, ply}) {
    CloudXYZL cloud;
    const std::string msg =
        thrownMessage<FormatError>([&] { loadCloud(path, cloud, limits); });
    EXPECT_TRUE(contains(msg, "3 points exceed the limit of 2")) << msg;
    limits.max_points = 3;
    EXPECT_NO_THROW(loadCloud(path, cloud, limits));
    limits.max_points = 2;
  }

  const std::string square = dir.write("square.ply", squarePly());
  MeshLoadOptions options;
  options.limits.max_points = 3;
  EXPECT_TRUE(contains(thrownMessage<FormatError>([&] { loadMesh(square, options); }),
                       "4 vertices exceed the limit of 3"));
  options.limits.max_points = 0;
  options.limits.max_triangles = 1;
  EXPECT_TRUE(contains(thrownMessage<FormatError>([&] { loadMesh(square, options); }),
                       "InputLimits::max_triangles"));

  // VRML: a Box is 8 vertices and 12 triangles.
  const std::string box =
      dir.write("box.wrl", "#VRML V2.0 utf8\nShape { geometry Box { size 1 1 1 } }\n");
  options.limits.max_triangles = 11;
  EXPECT_TRUE(contains(thrownMessage<FormatError>([&] { loadMesh(box, options); }),
                       "more than 11 triangles (the limit, InputLimits::max_triangles)"));
  options.limits.max_triangles = 12;
  options.limits.max_points = 7;
  EXPECT_TRUE(contains(thrownMessage<FormatError>([&] { loadMesh(box, options); }),
                       "more than 7 vertices (the limit, InputLimits::max_points)"));
  options.limits.max_points = 8;
  EXPECT_EQ(loadMesh(box, options).size(), 12u);

  // OBJ through Assimp: counted in Assimp's scene before they are copied out.
  const std::string obj =
      dir.write("two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n");
  options.limits.max_points = 3;
  EXPECT_TRUE(contains(thrownMessage<FormatError>([&] { loadMesh(obj, options); }),
                       "4 vertices exceed the limit of 3"));
}

TEST(InputLimits, ProcessWideDefaultsAndPerCallOverride)
{
  TempDir dir;
  const std::string path = dir.write("three.pcd", kTrianglePcd);
  InputLimits tiny;
  tiny.max_points = 1;
  const DefaultLimits guard(tiny);
  EXPECT_EQ(defaultInputLimits().max_points, 1u);
  CloudXYZ cloud;
  EXPECT_THROW(loadCloud(path, cloud), FormatError);
  loadCloud(path, cloud, InputLimits::unlimited());
  EXPECT_EQ(cloud.size(), 3u);
}

TEST(InputLimits, DefUseBlowUpInVrmlIsBounded)
{
  // 40 levels of groups that USE the previous one twice: 2^40 instances, no geometry.
  std::string wrl = "#VRML V2.0 utf8\nDEF G0 Group { }\n";
  for (int i = 1; i <= 40; ++i)
    wrl += "DEF G" + std::to_string(i) + " Group { children [ USE G" +
           std::to_string(i - 1) + " USE G" + std::to_string(i - 1) + " ] }\n";
  TempDir dir;
  const std::string path = dir.write("dag.wrl", wrl);
  MeshLoadOptions options;
  options.limits.max_triangles = 100'000;
  const std::string msg = thrownMessage<FormatError>([&] { loadMesh(path, options); });
  EXPECT_TRUE(contains(msg, "more than 100000 node instances, DEF/USE nested too often"))
      << msg;
}

TEST(InputLimits, ColladaArrayCountBeyondTheFileIsRefused)
{
  TempDir dir;
  const std::string path = dir.write(
      "count.dae", "<?xml version=\"1.0\"?>\n<COLLADA version=\"1.4.1\">\n"
                   "<float_array id=\"a\" count=\"1000000000000\">0 0 0</float_array>\n"
                   "</COLLADA>\n");
  const std::string msg = thrownMessage<FormatError>([&] { loadMesh(path); });
  EXPECT_TRUE(contains(msg, "line 3: <float_array> count 1000000000000 is more than the "
                            "file can hold"))
      << msg;
}

TEST(InputLimits, WhatIsNotARegularFileIsRefusedByNameWithoutBlocking)
{
  // Opening a FIFO for reading blocks until a writer comes; each reader refuses it first.
  TempDir dir;
  for (const char* name :
       {"cloud.pcd", "cloud.ply", "mesh.obj", "mesh.dae", "depth.png", "rois.yaml"}) {
    SCOPED_TRACE(name);
    const std::string path = dir.file(name);
    ASSERT_EQ(mkfifo(path.c_str(), 0600), 0);
    const std::string ext = plantnbv::io::extensionOf(path);
    const std::string msg = thrownMessage<plantnbv::IoError>([&] {
      if (ext == ".pcd" || ext == ".ply") {
        CloudXYZ cloud;
        loadCloud(path, cloud);
      } else if (ext == ".png") {
        plantnbv::DepthImage depth;
        plantnbv::io::loadDepthPng(path, depth);
      } else if (ext == ".yaml")
        loadRoi(path);
      else
        plantnbv::io::loadMesh(path);
    });
    EXPECT_NE(msg.find(path + ": is not a regular file (a FIFO, socket or device)"),
              std::string::npos)
        << msg;
  }
}

TEST(NonFinite, MeshVerticesAreRejectedNamingTheFile)
{
  TempDir dir;
  for (const char* value : {"nan 0 0", "0 inf 0", "0 0 -inf"}) {
    const std::string path = dir.write("nan.ply", squarePly(value));
    const std::string msg = thrownMessage<FormatError>([&] { loadMesh(path); });
    EXPECT_EQ(msg, path + ": vertex 1 is not finite") << value;
  }
  const std::string wrl = dir.write(
      "nan.wrl",
      "#VRML V2.0 utf8\nShape { geometry IndexedFaceSet {\n"
      "  coord Coordinate { point [ 0 0 0, 1 0 0, 0 nan 0 ] } coordIndex [ 0 1 2 ]"
      " } }\n");
  // The VRML lexer takes "nan" for a word, not a number: a parse error naming the line.
  EXPECT_TRUE(
      contains(thrownMessage<FormatError>([&] { loadMesh(wrl); }), wrl + ": line"));
  const std::string big = dir.write(
      "big.wrl", "#VRML V2.0 utf8\nTransform { scale 1e300 1 1 children Shape {\n"
                 "  geometry Box { size 1e10 1 1 } } }\n");
  EXPECT_TRUE(contains(thrownMessage<FormatError>([&] { loadMesh(big); }),
                       big + ": vertex 0 is not finite"));
  // A scale that overflows float is caught after it is applied.
  MeshLoadOptions options;
  options.scale = 1e300;
  const std::string square = dir.write("square.ply", squarePly());
  EXPECT_TRUE(contains(thrownMessage<FormatError>([&] { loadMesh(square, options); }),
                       square + ": vertex 1 is not finite"));
}

TEST(NonFinite, CloudPointsAreKeptAndTheCloudIsNotDense)
{
  TempDir dir;
  const std::string nan = dir.write(
      "nan.pcd", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                 "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3\nnan 0 inf\n");
  CloudXYZ cloud;
  loadCloud(nan, cloud);
  ASSERT_EQ(cloud.size(), 2u);
  EXPECT_TRUE(std::isnan(cloud[1].x));
  EXPECT_FALSE(cloud.is_dense);
  loadCloud(dir.write("finite.pcd", kTrianglePcd), cloud);
  EXPECT_TRUE(cloud.is_dense);
  const std::string ply =
      dir.write("inf.ply", "ply\nformat ascii 1.0\nelement vertex 2\n" + kXyz +
                               "end_header\n0 0 0\n0 -inf 0\n");
  loadCloud(ply, cloud);
  EXPECT_FALSE(cloud.is_dense);
  EXPECT_EQ(cloud[1].y, -std::numeric_limits<float>::infinity());
}

TEST(NonFinite, RoiBoxesAreRejectedNamingTheBoxAndKey)
{
  TempDir dir;
  auto message = [&](const std::string& box) {
    const std::string path =
        dir.write("rois.yaml", "boxes:\n  - center: [0, 0, 0]\n    size: [1, 1, 1]\n"
                               "  - " +
                                   box + "\n");
    return thrownMessage<FormatError>([&] { loadRoi(path); });
  };
  EXPECT_TRUE(contains(message("{center: [0, .nan, 0], size: [1, 1, 1]}"),
                       "boxes[1].center: expected 3 numbers, got [0, .nan, 0]"));
  EXPECT_TRUE(contains(message("{center: [0, 0, 0], size: [1, .inf, 1]}"),
                       "boxes[1].size: expected 3 non-negative numbers, got [1, .inf, 1]"));
  EXPECT_TRUE(contains(message("{center: [0, 0, -.Inf], size: [1, 1, 1]}"),
                       "boxes[1].center: expected 3 numbers"));
  // min > max: a negative size.
  EXPECT_TRUE(contains(message("{center: [0, 0, 0], size: [1, -0.1, 1]}"),
                       "boxes[1].size: expected 3 non-negative numbers"));
  // Finite, but the corners overflow.
  EXPECT_TRUE(contains(message("{center: [1e308, 0, 0], size: [1.7e308, 1, 1]}"),
                       "boxes[1]: center +- size/2 overflows"));
}
