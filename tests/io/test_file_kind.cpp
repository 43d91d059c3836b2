#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/io/file_kind.h>

#include "io_test_util.h"

using plantnbv::FormatError;
using plantnbv::IoError;
using plantnbv::io::extensionOf;
using plantnbv::io::FileKind;
using plantnbv::io::fileKind;
using plantnbv::test::TempDir;
using plantnbv::test::thrownMessage;

TEST(FileKind, ExtensionOf)
{
  EXPECT_EQ(extensionOf("a/b/cloud.PCD"), ".pcd");
  EXPECT_EQ(extensionOf("plant.v2.Dae"), ".dae");
  EXPECT_EQ(extensionOf("dir.d/noext"), "");
  EXPECT_EQ(extensionOf(""), "");
}

TEST(FileKind, ByExtension)
{
  // No file is opened for these: the extension decides.
  EXPECT_EQ(fileKind("x.pcd"), FileKind::cloud);
  EXPECT_EQ(fileKind("X.PCD"), FileKind::cloud);
  for (const char* p : {"m.obj", "m.stl", "m.dae", "m.wrl", "m.vrml", "M.WRL"})
    EXPECT_EQ(fileKind(p), FileKind::mesh) << p;
  EXPECT_EQ(fileKind("map.bt"), FileKind::octree);
  EXPECT_EQ(fileKind("map.ot"), FileKind::octree);
}

TEST(FileKind, PlyDependsOnItsFaces)
{
  TempDir dir;
  const std::string header = "ply\nformat binary_little_endian 1.0\ncomment x\n"
                             "element vertex 3\nproperty float x\nproperty float y\n"
                             "property float z\n";
  EXPECT_EQ(fileKind(dir.write("cloud.ply", header + "end_header\n")), FileKind::cloud);
  EXPECT_EQ(fileKind(dir.write(
                "empty_faces.ply",
                header + "element face 0\n"
                         "property list uchar int vertex_indices\nend_header\n")),
            FileKind::cloud);
  EXPECT_EQ(
      fileKind(dir.write(
          "mesh.PLY", header + "element face 1\n"
                               "property list uchar int vertex_indices\nend_header\n")),
      FileKind::mesh);
  // Windows line ends in the header.
  EXPECT_EQ(
      fileKind(dir.write("crlf.ply", "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\n"
                                     "element face 2\r\nend_header\r\n")),
      FileKind::mesh);
}

TEST(FileKind, Errors)
{
  TempDir dir;
  const std::string missing = dir.file("missing.ply");
  const std::string msg = thrownMessage<IoError>([&] { fileKind(missing); });
  EXPECT_NE(msg.find(missing), std::string::npos) << msg;
  EXPECT_THROW(fileKind(dir.write("junk.ply", "solid x\n")), FormatError);
  EXPECT_THROW(fileKind(dir.write("unterminated.ply", "ply\nformat ascii 1.0\n")),
               FormatError);
  const std::string unknown = thrownMessage<FormatError>([] { fileKind("scan.las"); });
  EXPECT_NE(unknown.find("'.las'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find(".pcd"), std::string::npos) << unknown;
  EXPECT_THROW(fileKind("noextension"), FormatError);
}
