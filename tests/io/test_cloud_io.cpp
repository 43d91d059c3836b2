#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/io/cloud_io.h>

#include "io_test_util.h"

using plantnbv::CloudXYZ;
using plantnbv::CloudXYZL;
using plantnbv::FormatError;
using plantnbv::IoError;
using plantnbv::io::loadCloud;
using plantnbv::io::saveCloud;
using plantnbv::test::TempDir;
using plantnbv::test::thrownMessage;

namespace {

/// Coordinates that need all 9 digits of a float, plus a few special magnitudes.
CloudXYZL makeCloud(std::size_t n, std::uint64_t seed)
{
  plantnbv::Rng rng(seed);
  CloudXYZL cloud;
  for (std::size_t i = 0; i < n; ++i) {
    pcl::PointXYZL p;
    p.x = static_cast<float>(rng.uniform(-2.0, 2.0));
    p.y = static_cast<float>(rng.uniform(-2.0, 2.0));
    p.z = static_cast<float>(rng.uniform(0.0, 3.0));
    p.label = static_cast<std::uint32_t>(rng.index(7));
    cloud.push_back(p);
  }
  pcl::PointXYZL special;
  special.x = 1e-7f;
  special.y = -123.456f;
  special.z = std::numeric_limits<float>::max();
  special.label = 4000000000u;
  cloud.push_back(special);
  return cloud;
}

CloudXYZ withoutLabels(const CloudXYZL& in)
{
  CloudXYZ out;
  for (const auto& p : in)
    out.push_back(pcl::PointXYZ(p.x, p.y, p.z));
  return out;
}

} // namespace

class CloudRoundTrip : public ::testing::TestWithParam<std::tuple<std::string, bool>> {};

TEST_P(CloudRoundTrip, XyzAndXyzlAreExact)
{
  const auto& [ext, binary] = GetParam();
  TempDir dir;
  const CloudXYZL labelled = makeCloud(200, 7);
  const CloudXYZ plain = withoutLabels(labelled);

  const std::string path_l = dir.file("labelled" + ext);
  saveCloud(path_l, labelled, binary);
  CloudXYZL back_l;
  loadCloud(path_l, back_l);
  ASSERT_EQ(back_l.size(), labelled.size());
  for (std::size_t i = 0; i < labelled.size(); ++i) {
    EXPECT_EQ(back_l[i].x, labelled[i].x) << i;
    EXPECT_EQ(back_l[i].y, labelled[i].y) << i;
    EXPECT_EQ(back_l[i].z, labelled[i].z) << i;
    EXPECT_EQ(back_l[i].label, labelled[i].label) << i;
  }

  const std::string path = dir.file("plain" + ext);
  saveCloud(path, plain, binary);
  CloudXYZ back;
  loadCloud(path, back);
  ASSERT_EQ(back.size(), plain.size());
  for (std::size_t i = 0; i < plain.size(); ++i) {
    EXPECT_EQ(back[i].x, plain[i].x) << i;
    EXPECT_EQ(back[i].y, plain[i].y) << i;
    EXPECT_EQ(back[i].z, plain[i].z) << i;
  }

  // A file without labels read as XYZL: label 0 everywhere.
  CloudXYZL unlabelled;
  loadCloud(path, unlabelled);
  ASSERT_EQ(unlabelled.size(), plain.size());
  for (std::size_t i = 0; i < plain.size(); ++i) {
    EXPECT_EQ(unlabelled[i].x, plain[i].x);
    EXPECT_EQ(unlabelled[i].label, 0u);
  }
  // And a labelled file read as XYZ keeps the coordinates.
  CloudXYZ dropped;
  loadCloud(path_l, dropped);
  ASSERT_EQ(dropped.size(), labelled.size());
  EXPECT_EQ(dropped[3].z, labelled[3].z);
}

INSTANTIATE_TEST_SUITE_P(Formats, CloudRoundTrip,
                         ::testing::Values(std::make_tuple(".pcd", true),
                                           std::make_tuple(".pcd", false),
                                           std::make_tuple(".ply", true),
                                           std::make_tuple(".ply", false)));

TEST(CloudIo, NonFinitePointsAreKept)
{
  TempDir dir;
  CloudXYZ cloud;
  cloud.push_back(pcl::PointXYZ(1, 2, 3));
  cloud.push_back(pcl::PointXYZ(std::numeric_limits<float>::quiet_NaN(), 0,
                                std::numeric_limits<float>::infinity()));
  cloud.is_dense = false;
  for (const char* ext : {".pcd", ".ply"})
    for (bool binary : {true, false}) {
      const std::string path = dir.file(std::string(binary ? "b" : "a") + ext);
      saveCloud(path, cloud, binary);
      CloudXYZ back;
      loadCloud(path, back);
      ASSERT_EQ(back.size(), 2u) << path;
      EXPECT_EQ(back[0].z, 3.0f) << path;
      EXPECT_TRUE(std::isnan(back[1].x)) << path;
      EXPECT_EQ(back[1].z, std::numeric_limits<float>::infinity()) << path;
    }
}

TEST(CloudIo, OrganizedCloudKeepsItsShape)
{
  TempDir dir;
  CloudXYZ cloud(4, 3, pcl::PointXYZ(0.5f, 0.25f, 1.0f));
  cloud.at(3, 2) = pcl::PointXYZ(9, 8, 7);
  const std::string path = dir.file("organized.pcd");
  saveCloud(path, cloud);
  CloudXYZ back;
  loadCloud(path, back);
  EXPECT_EQ(back.width, 4u);
  EXPECT_EQ(back.height, 3u);
  EXPECT_EQ(back.at(3, 2).y, 8.0f);
}

TEST(CloudIo, DoubleAndIntegerFieldsAreConverted)
{
  // PCL's own conversion leaves zeros for double coordinates; ours converts them.
  TempDir dir;
  const std::string path = dir.write("doubles.ply", "ply\n"
                                                    "format ascii 1.0\n"
                                                    "element vertex 2\n"
                                                    "property double x\n"
                                                    "property double y\n"
                                                    "property double z\n"
                                                    "property ushort label\n"
                                                    "end_header\n"
                                                    "0.125 -2.5 3 5\n"
                                                    "1 2 4 65535\n");
  CloudXYZL cloud;
  loadCloud(path, cloud);
  ASSERT_EQ(cloud.size(), 2u);
  EXPECT_EQ(cloud[0].x, 0.125f);
  EXPECT_EQ(cloud[0].y, -2.5f);
  EXPECT_EQ(cloud[0].z, 3.0f);
  EXPECT_EQ(cloud[0].label, 5u);
  EXPECT_EQ(cloud[1].z, 4.0f);
  EXPECT_EQ(cloud[1].label, 65535u);
}

TEST(CloudIo, MissingFileIsAnIoErrorNamingThePath)
{
  TempDir dir;
  const std::string path = dir.file("nowhere.pcd");
  CloudXYZ cloud;
  const std::string msg = thrownMessage<IoError>([&] { loadCloud(path, cloud); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  CloudXYZL labelled;
  EXPECT_THROW(loadCloud(dir.file("nowhere.ply"), labelled), IoError);
}

TEST(CloudIo, GarbageIsAFormatError)
{
  TempDir dir;
  CloudXYZ cloud;
  const std::string garbage = "this is not a point cloud\n\x01\x02\x03 at all\n";
  EXPECT_THROW(loadCloud(dir.write("garbage.pcd", garbage), cloud), FormatError);
  EXPECT_THROW(loadCloud(dir.write("garbage.ply", garbage), cloud), FormatError);
  EXPECT_THROW(loadCloud(dir.write("empty.pcd", ""), cloud), FormatError);
}

// Files on which PCL 1.13's PCDReader crashes (found by fuzzing, tests/fuzz/regressions)
// never reach it.
TEST(CloudIo, PcdFilesThatCrashPclAreFormatErrors)
{
  TempDir dir;
  const std::string header =
      "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nDATA ascii\n";
  auto message = [&](const std::string& content) {
    const std::string path = dir.write("bad.pcd", content);
    return thrownMessage<FormatError>([&] {
      CloudXYZ cloud;
      loadCloud(path, cloud);
    });
  };
  EXPECT_NE(message(" \n" + header + "1 2 3\n4 5 6\n").find("a line starts with a blank"),
            std::string::npos);
  EXPECT_NE(message(header + "FIELDS\n1 2 3\n")
                .find("the data starts with 'FIELDS', which PCL would read as a header "
                      "line"),
            std::string::npos);
  EXPECT_NE(message(header + "1 2 3\nx 5 6\n")
                .find("line 2 of the ASCII data does not start with a number: 'x 5 6'"),
            std::string::npos);
  EXPECT_NE(message(header + "1 2 3\nCOLUMNS x\n").find("line 2 of the ASCII data"),
            std::string::npos);
  // An empty line of a Windows file in the header.
  EXPECT_NE(message("VERSION .7\r\n\r\n" + header + "1 2 3\n4 5 6\n")
                .find("a line starts with a blank"),
            std::string::npos);
  // PCL reads on after DATA while lines look like header lines, binary data included.
  std::string binary = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nDATA binary\n";
  binary += "\nPOINTS 1";
  binary.resize(binary.size() + 24 - 8, '\0');
  EXPECT_NE(message(binary).find("the data starts with 'POINTS', which PCL would read as "
                                 "a header line"),
            std::string::npos);
  EXPECT_NE(message("FIELDS x y z\nSIZE 4 2 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n")
                .find("SIZE 2 of an F field is not 4 or 8"),
            std::string::npos);
}

TEST(CloudIo, PlyVertexListPropertyIsAFormatError)
{
  // Lists of different lengths per vertex made PCL 1.13 abort (found by fuzzing).
  TempDir dir;
  const std::string path = dir.write("lists.ply", "ply\nformat ascii 1.0\n"
                                                  "element vertex 2\n"
                                                  "property float x\nproperty float y\n"
                                                  "property float z\n"
                                                  "property list uchar int ids\n"
                                                  "end_header\n"
                                                  "0 0 0 1 7\n1 0 0 3 7 8 9\n");
  CloudXYZ cloud;
  const std::string msg = thrownMessage<FormatError>([&] { loadCloud(path, cloud); });
  EXPECT_NE(msg.find("vertex property 'ids' is a list"), std::string::npos) << msg;
}

TEST(CloudIo, PlyColoursOnlyInTheOrderPclReads)
{
  // PCL 1.13 abort()ed on green without red (found by fuzzing).
  TempDir dir;
  auto ply = [&](const std::string& colour_properties, const std::string& row) {
    return dir.write("c.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"
                              "property float x\nproperty float y\nproperty float z\n" +
                                  colour_properties + "end_header\n0 0 0 " + row + "\n");
  };
  const std::string rgb = "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  CloudXYZ cloud;
  EXPECT_NO_THROW(loadCloud(ply(rgb, "1 2 3"), cloud));
  EXPECT_NO_THROW(loadCloud(ply(rgb + "property uchar alpha\n", "1 2 3 4"), cloud));
  EXPECT_NO_THROW(loadCloud(ply("property float green\n", "1"), cloud)); // a plain scalar
  // (properties, row) pairs; not a structured binding: C++17 lambdas cannot capture one.
  for (const auto& bad : std::vector<std::pair<std::string, std::string>>{
           {"property uchar green\nproperty uchar blue\n", "1 2"},
           {"property uchar red\nproperty uchar green\n", "1 2"},
           {"property uchar red\nproperty float i\nproperty uchar green\n"
            "property uchar blue\n",
            "1 2 3 4"},
           {"property uchar alpha\n" + rgb, "1 2 3 4"},
           {rgb + rgb, "1 2 3 4 5 6"}}) {
    const std::string msg =
        thrownMessage<FormatError>([&] { loadCloud(ply(bad.first, bad.second), cloud); });
    EXPECT_NE(msg.find("vertex colour properties must be uchar red, green, blue"),
              std::string::npos)
        << bad.first << ": " << msg;
  }
}

TEST(CloudIo, FileWithoutXyzIsAFormatError)
{
  TempDir dir;
  const std::string path = dir.write("intensity.pcd", "VERSION .7\n"
                                                      "FIELDS a b c\n"
                                                      "SIZE 4 4 4\n"
                                                      "TYPE F F F\n"
                                                      "COUNT 1 1 1\n"
                                                      "WIDTH 1\n"
                                                      "HEIGHT 1\n"
                                                      "VIEWPOINT 0 0 0 1 0 0 0\n"
                                                      "POINTS 1\n"
                                                      "DATA ascii\n"
                                                      "1 2 3\n");
  CloudXYZ cloud;
  const std::string msg = thrownMessage<FormatError>([&] { loadCloud(path, cloud); });
  EXPECT_NE(msg.find("'x'"), std::string::npos) << msg;
}

TEST(CloudIo, UnknownExtensionNamesItAndTheAcceptedOnes)
{
  TempDir dir;
  const std::string path = dir.write("cloud.xyz", "1 2 3\n");
  CloudXYZ cloud;
  const std::string msg = thrownMessage<FormatError>([&] { loadCloud(path, cloud); });
  EXPECT_NE(msg.find("'.xyz'"), std::string::npos) << msg;
  EXPECT_NE(msg.find(".pcd"), std::string::npos) << msg;
  EXPECT_NE(msg.find(".ply"), std::string::npos) << msg;
  EXPECT_THROW(saveCloud(dir.file("cloud.txt"), cloud), FormatError);
}

TEST(CloudIo, UnwritablePathIsAnIoError)
{
  TempDir dir;
  CloudXYZ cloud;
  cloud.push_back(pcl::PointXYZ(1, 2, 3));
  EXPECT_THROW(saveCloud(dir.file("no/such/dir/cloud.pcd"), cloud), IoError);
  EXPECT_THROW(saveCloud(dir.file("no/such/dir/cloud.ply"), cloud, false), IoError);
}
