#include <cmath>
#include <cstring>
#include <limits>

#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/io/cloud_io.h>

#include "io_test_util.h"

using plantnbv::CloudXYZ;
using plantnbv::CloudXYZL;
using plantnbv::FileNotFoundError;
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
  EXPECT_THROW(loadCloud(dir.file("nowhere.ply"), labelled), FileNotFoundError);
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

// Files on which PCL 1.13's PCDReader crashed (found by fuzzing, tests/fuzz/regressions):
// our reader reads them as the PCD format says, or refuses them naming the line.
TEST(CloudIo, PcdFilesThatCrashedPclReadAsWrittenOrAreRefused)
{
  TempDir dir;
  const std::string header =
      "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nDATA ascii\n";
  auto read = [&](const std::string& content) {
    CloudXYZ cloud;
    loadCloud(dir.write("good.pcd", content), cloud);
    return cloud;
  };
  auto message = [&](const std::string& content) {
    const std::string path = dir.write("bad.pcd", content);
    return thrownMessage<FormatError>([&] {
      CloudXYZ cloud;
      loadCloud(path, cloud);
    });
  };
  // Blank header lines, of a Windows file too.
  for (const std::string& before :
       {std::string(" \n"), std::string("VERSION .7\r\n\r\n")}) {
    const CloudXYZ blank = read(before + header + "1 2 3\n4 5 6\n");
    ASSERT_EQ(blank.size(), 2u);
    EXPECT_EQ(blank[1].x, 4.0f);
    EXPECT_EQ(blank[1].z, 6.0f);
  }
  const struct {
    std::string data, message;
  } refused[] = {
      {"FIELDS\n1 2 3\n", "line 1 of the ASCII data: 1 values, expected 3"},
      {"1 2 3\nx 5 6\n", "line 2 of the ASCII data: 'x' is not a number (field 'x')"},
      {"1 2 3\nCOLUMNS x y\n", "line 2 of the ASCII data: 'COLUMNS' is not a number"},
      {"1 2 3\n4 5      \n", "line 2 of the ASCII data: 2 values, expected 3"},
      {"1 2 3\n4 5 6\n7 8 9\n",
       "line 3 of the ASCII data: more data lines than the 2 POINTS"},
      {"1 2 3\n          \n", "truncated: 1 data lines of 2 POINTS"},
  };
  for (const auto& r : refused) {
    const std::string msg = message(header + r.data);
    EXPECT_NE(msg.find(r.message), std::string::npos) << r.data << ": " << msg;
  }
  // Binary data that starts like a header line is data.
  std::string binary = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nDATA binary\n";
  const std::string data = std::string("\nPOINTS 1") + std::string(24 - 9, '\0');
  const CloudXYZ points = read(binary + data);
  ASSERT_EQ(points.size(), 2u);
  float x0;
  std::memcpy(&x0, data.data(), 4);
  EXPECT_EQ(std::memcmp(&points[0].x, &x0, 4), 0);
  EXPECT_NE(message("FIELDS x y z\nSIZE 4 2 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n")
                .find("SIZE 2 of an F field is not 4 or 8"),
            std::string::npos);
  EXPECT_NE(
      message("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nPOINTS 3\nDATA ascii\n"
              "1 2 3\n4 5 6\n7 8 9\n")
          .find("POINTS 3 is not WIDTH x HEIGHT (2 x 1)"),
      std::string::npos);
  EXPECT_NE(
      message("FIELDS x y z label\nSIZE 4 4 4 4\nTYPE F F F U\nWIDTH 1\nDATA ascii\n"
              "1 2 3 0.5\n")
          .find("'0.5' is not a whole number (field 'label')"),
      std::string::npos);
}

/// Points of every PCD layout PCL writes, organized and with NaNs, for the reader.
CloudXYZL organizedCloudWithNans()
{
  CloudXYZL cloud = makeCloud(59, 11); // 60 points: 12 x 5
  cloud.width = 12;
  cloud.height = 5;
  cloud[7].x = cloud[7].y = cloud[7].z = std::numeric_limits<float>::quiet_NaN();
  cloud.is_dense = false;
  return cloud;
}

TEST(CloudIo, ReadsWhatPclWritesInEachPcdLayoutExactly)
{
  TempDir dir;
  const CloudXYZL written = organizedCloudWithNans();
  pcl::PCDWriter writer;
  const struct {
    const char* name;
    int status;
  } files[] = {
      {"ascii.pcd", writer.writeASCII(dir.file("ascii.pcd"), written, 9)},
      {"binary.pcd", writer.writeBinary(dir.file("binary.pcd"), written)},
      {"compressed.pcd",
       writer.writeBinaryCompressed(dir.file("compressed.pcd"), written)},
  };
  for (const auto& f : files) {
    SCOPED_TRACE(f.name);
    ASSERT_EQ(f.status, 0);
    CloudXYZL back;
    loadCloud(dir.file(f.name), back);
    ASSERT_EQ(back.width, written.width);
    ASSERT_EQ(back.height, written.height);
    EXPECT_FALSE(back.is_dense);
    for (std::size_t i = 0; i < written.size(); ++i) {
      EXPECT_EQ(std::memcmp(&back[i].x, &written[i].x, 12), 0) << i; // NaN bits too
      EXPECT_EQ(back[i].label, written[i].label) << i;
    }
  }
  // A cloud with more fields than ours (PCL's XYZRGBNormal: padding, rgb, curvature).
  pcl::PointCloud<pcl::PointXYZRGBNormal> rich;
  for (const auto& p : written) {
    pcl::PointXYZRGBNormal q;
    q.x = p.x;
    q.y = p.y;
    q.z = p.z;
    q.r = 200;
    q.normal_x = 1.0f;
    q.curvature = 0.5f;
    rich.push_back(q);
  }
  ASSERT_EQ(writer.writeBinaryCompressed(dir.file("rich.pcd"), rich), 0);
  CloudXYZ back;
  loadCloud(dir.file("rich.pcd"), back);
  ASSERT_EQ(back.size(), rich.size());
  for (std::size_t i = 0; i < rich.size(); ++i)
    EXPECT_EQ(std::memcmp(&back[i].x, &rich[i].x, 12), 0) << i;
}

TEST(CloudIo, PclReadsWhatWeWrite)
{
  TempDir dir;
  const CloudXYZL written = organizedCloudWithNans();
  for (bool binary : {true, false}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    const std::string path = dir.file(binary ? "ours_binary.pcd" : "ours_ascii.pcd");
    saveCloud(path, written, binary);
    CloudXYZL back;
    ASSERT_EQ(pcl::io::loadPCDFile(path, back), 0);
    ASSERT_EQ(back.width, written.width);
    ASSERT_EQ(back.height, written.height);
    for (std::size_t i = 0; i < written.size(); ++i) {
      if (std::isnan(written[i].x)) {
        EXPECT_TRUE(std::isnan(back[i].x)) << i;
        continue;
      }
      EXPECT_EQ(back[i].x, written[i].x) << i;
      EXPECT_EQ(back[i].z, written[i].z) << i;
      EXPECT_EQ(back[i].label, written[i].label) << i;
    }
  }
}

TEST(CloudIo, PlyVertexListsAndColoursInAnyOrderAreSkipped)
{
  // Lists of different lengths per vertex and green without red made PCL 1.13 abort
  // (found by fuzzing); our reader skips what a cloud does not keep.
  TempDir dir;
  CloudXYZL cloud;
  loadCloud(dir.write("lists.ply",
                      "ply\nformat ascii 1.0\n"
                      "element camera 1\nproperty list uchar float view\n"
                      "element vertex 2\n"
                      "property list uchar int ids\n"
                      "property uchar green\nproperty float x\n"
                      "property float y\nproperty float z\n"
                      "property uint label\nproperty uchar red\n"
                      "element face 1\nproperty list uchar int vertex_indices\n"
                      "end_header\n"
                      "3 0.5 0.25 1\n"
                      "1 7 9 0 0 0 3 1\n3 7 8 9 9 1 2 3 4 1\n"
                      "3 0 1 1\n"),
            cloud);
  ASSERT_EQ(cloud.size(), 2u);
  EXPECT_EQ(cloud[1].x, 1.0f);
  EXPECT_EQ(cloud[1].z, 3.0f);
  EXPECT_EQ(cloud[0].label, 3u);
  EXPECT_EQ(cloud[1].label, 4u);
  // A list where a cloud needs one value is refused.
  const std::string msg = thrownMessage<FormatError>([&] {
    loadCloud(dir.write("label_list.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"
                                          "property float x\nproperty float y\n"
                                          "property float z\n"
                                          "property list uchar int label\nend_header\n"
                                          "0 0 0 1 7\n"),
              cloud);
  });
  EXPECT_NE(msg.find("vertex property 'label' is a list; it must be one value"),
            std::string::npos)
      << msg;
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
