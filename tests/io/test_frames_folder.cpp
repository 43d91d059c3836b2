#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <png.h>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <plantnbv/camera/depth_image.h>
#include <plantnbv/common/error.h>
#include <plantnbv/io/depth_image_io.h>
#include <plantnbv/io/frames_folder.h>

#include "file_size_limit.h"
#include "io_test_util.h"

using plantnbv::DepthImage;
using plantnbv::FileNotFoundError;
using plantnbv::FormatError;
using plantnbv::InvalidArgumentError;
using plantnbv::IoError;
using plantnbv::Pose;
using plantnbv::io::CameraInfo;
using plantnbv::io::FramesFolder;
using plantnbv::io::FramesFolderOptions;
using plantnbv::io::FramesFolderWriter;
using plantnbv::io::readCameraInfo;
using plantnbv::io::readTumFileList;
using plantnbv::io::readTumTrajectory;
using plantnbv::io::writeCameraInfo;
using plantnbv::test::readBytes;
using plantnbv::test::TempDir;
using plantnbv::test::thrownMessage;

namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();

/// camera.yaml as ROS camera_calibration writes it (numpy's "0." style, a wrapped row).
const char* const kRosCameraYaml = "image_width: 640\n"
                                   "image_height: 480\n"
                                   "camera_name: narrow_stereo\n"
                                   "camera_matrix:\n"
                                   "  rows: 3\n"
                                   "  cols: 3\n"
                                   "  data: [615.29, 0., 316.03, 0., 615.69, 241.27,\n"
                                   "         0., 0., 1.]\n"
                                   "distortion_model: plumb_bob\n"
                                   "distortion_coefficients:\n"
                                   "  rows: 1\n"
                                   "  cols: 5\n"
                                   "  data: [0., 0., 0., 0., 0.]\n"
                                   "rectification_matrix:\n"
                                   "  rows: 3\n"
                                   "  cols: 3\n"
                                   "  data: [1., 0., 0., 0., 1., 0., 0., 0., 1.]\n"
                                   "projection_matrix:\n"
                                   "  rows: 3\n"
                                   "  cols: 4\n"
                                   "  data: [615.29, 0., 316.03, 0., 0., 615.69, 241.27, "
                                   "0., 0., 0., 1., 0.]\n";

/// A small camera: 8 x 6 pixels, depth in units of 0.2 mm (TUM's 5000 per metre).
CameraInfo smallCamera()
{
  CameraInfo info;
  info.intrinsics = plantnbv::CameraIntrinsics::custom(8, 6, 10.0 / 3.0, 4.25, 3.5, 2.5);
  info.depth_scale = 5000.0;
  return info;
}

/// A seeded depth frame of `camera` with a few pixels that cannot be stored.
DepthImage randomDepth(const CameraInfo& camera, std::uint32_t seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> metres(0.2f, 3.0f);
  DepthImage depth;
  depth.width = camera.intrinsics.width;
  depth.height = camera.intrinsics.height;
  depth.depth_m.resize(std::size_t(depth.width) * depth.height);
  for (float& d : depth.depth_m)
    d = metres(rng);
  depth.depth_m[0] = kNaN;     // no return
  depth.depth_m[1] = 0.00005f; // rounds to 0 units: no return
  depth.depth_m[2] = 20.0f;    // over 65535 units
  return depth;
}

/// A seeded pose with a unit quaternion (as Pose normalizes it).
Pose randomPose(std::uint32_t seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> n;
  return Pose::fromXyzQuat(n(rng), n(rng), n(rng), n(rng), n(rng), n(rng), n(rng));
}

/// Whether two floats are the same value, NaN equal to NaN.
bool sameDepth(float a, float b)
{
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

/// An image in `format` (PNG_FORMAT_GRAY, PNG_FORMAT_RGB) with every sample 128.
void writePng(const std::string& path, std::uint32_t width, std::uint32_t height,
              png_uint_32 format)
{
  plantnbv::test::writePng(path, width, height, format, 128);
}

/// A frames folder with `camera.yaml` (smallCamera), one frame "depth/a.png" at 1 s (its
/// PNG not written) and a pose at `pose_stamp`.
void writeFolder(const TempDir& dir, const std::string& pose_stamp = "1.0")
{
  writeCameraInfo(dir.file("camera.yaml"), smallCamera());
  dir.write("depth.txt", "# timestamp filename\n1.0 depth/a.png\n");
  dir.write("groundtruth.txt", pose_stamp + " 1 2 3 0 0 0 1\n");
  std::filesystem::create_directories(dir.file("depth"));
}

/// The FormatError message readCameraInfo gives for a camera.yaml with this content.
std::string cameraError(const TempDir& dir, const std::string& content)
{
  const std::string path = dir.write("camera.yaml", content);
  return thrownMessage<FormatError>([&] { readCameraInfo(path); });
}

/// kRosCameraYaml with `from` replaced by `to`.
std::string rosYamlWith(const std::string& from, const std::string& to)
{
  std::string text = kRosCameraYaml;
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

/// The FormatError message readTumTrajectory gives for groundtruth.txt lines.
std::string poseError(const TempDir& dir, const std::string& content)
{
  const std::string path = dir.write("groundtruth.txt", content);
  return thrownMessage<FormatError>([&] { readTumTrajectory(path); });
}

/// The FormatError message readTumFileList gives for depth.txt lines.
std::string listError(const TempDir& dir, const std::string& content)
{
  const std::string path = dir.write("depth.txt", content);
  return thrownMessage<FormatError>([&] { readTumFileList(path); });
}

/// Whether `message` starts with "'path' line N: ".
::testing::AssertionResult namesLine(const std::string& message, const std::string& path,
                                     int line)
{
  const std::string prefix = "'" + path + "' line " + std::to_string(line) + ": ";
  if (message.compare(0, prefix.size(), prefix) == 0)
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "'" << message << "' does not start with '" << prefix << "'";
}

} // namespace

// --- camera.yaml ---

TEST(FramesFolderCamera, ReadsRosCameraCalibrationYaml)
{
  TempDir dir;
  const CameraInfo info = readCameraInfo(dir.write("camera.yaml", kRosCameraYaml));
  EXPECT_EQ(info.intrinsics.width, 640u);
  EXPECT_EQ(info.intrinsics.height, 480u);
  EXPECT_EQ(info.intrinsics.fx, 615.29);
  EXPECT_EQ(info.intrinsics.fy, 615.69);
  EXPECT_EQ(info.intrinsics.cx, 316.03);
  EXPECT_EQ(info.intrinsics.cy, 241.27);
  EXPECT_EQ(info.depth_scale, 1000.0);
  EXPECT_EQ(info.distortion_model, "plumb_bob");

  const CameraInfo tum = readCameraInfo(
      dir.write("camera.yaml", std::string(kRosCameraYaml) + "depth_scale: 5000\n"));
  EXPECT_EQ(tum.depth_scale, 5000.0);
  EXPECT_EQ(tum.intrinsics.fx, 615.29);
}

TEST(FramesFolderCamera, WriteReadRoundTripIsExact)
{
  TempDir dir;
  CameraInfo info;
  info.intrinsics = plantnbv::CameraIntrinsics::custom(641, 479, 1000.0 / 3.0, 0.1 + 0.2,
                                                       320.0 / 7.0, -1e-17);
  info.depth_scale = 4000.0 / 3.0;
  const std::string path = dir.file("camera.yaml");
  writeCameraInfo(path, info);
  const CameraInfo back = readCameraInfo(path);
  EXPECT_EQ(back.intrinsics.width, info.intrinsics.width);
  EXPECT_EQ(back.intrinsics.height, info.intrinsics.height);
  EXPECT_EQ(back.intrinsics.fx, info.intrinsics.fx);
  EXPECT_EQ(back.intrinsics.fy, info.intrinsics.fy);
  EXPECT_EQ(back.intrinsics.cx, info.intrinsics.cx);
  EXPECT_EQ(back.intrinsics.cy, info.intrinsics.cy);
  EXPECT_EQ(back.depth_scale, info.depth_scale);
  EXPECT_EQ(back.distortion_model, info.distortion_model);
  EXPECT_THROW(writeCameraInfo(dir.file("no/dir/camera.yaml"), info), IoError);
}

TEST(FramesFolderCamera, MissingCameraMatrix)
{
  TempDir dir;
  const std::string msg = cameraError(
      dir, "image_width: 640\nimage_height: 480\ndistortion_model: plumb_bob\n");
  EXPECT_EQ(msg.rfind("'" + dir.file("camera.yaml") + "' camera_matrix: missing", 0), 0u)
      << msg;
}

TEST(FramesFolderCamera, NonNumericMatrixEntry)
{
  TempDir dir;
  const std::string msg = cameraError(dir, rosYamlWith("316.03, 0.", "316.03, zero"));
  EXPECT_EQ(msg.rfind("'" + dir.file("camera.yaml") +
                          "' camera_matrix.data: expected 9 numbers",
                      0),
            0u)
      << msg;
  EXPECT_NE(msg.find("zero"), std::string::npos) << msg;
}

TEST(FramesFolderCamera, NonPinholeMatrix)
{
  TempDir dir;
  // A skew term.
  std::string msg =
      cameraError(dir, rosYamlWith("615.29, 0., 316.03", "615.29, 0.5, 316.03"));
  EXPECT_EQ(msg.rfind("'" + dir.file("camera.yaml") +
                          "' camera_matrix.data: expected a pinhole "
                          "matrix",
                      0),
            0u)
      << msg;
  // A last row other than [0, 0, 1].
  msg = cameraError(dir, rosYamlWith("0., 0., 1.]", "0., 0., 2.]"));
  EXPECT_NE(msg.find("camera_matrix.data: expected a pinhole matrix"), std::string::npos)
      << msg;
  // fx of 0 passes the shape but not the intrinsics' check.
  msg = cameraError(
      dir, rosYamlWith("[615.29, 0., 316.03, 0., 615.69", "[0, 0., 316.03, 0., 615.69"));
  EXPECT_NE(msg.find("' camera_matrix: camera fx = 0"), std::string::npos) << msg;
}

TEST(FramesFolderCamera, NonZeroDistortionSaysToRectify)
{
  TempDir dir;
  const std::string msg =
      cameraError(dir, rosYamlWith("[0., 0., 0., 0., 0.]", "[0.1, -0.2, 0., 0., 0.]"));
  EXPECT_EQ(msg.rfind("'" + dir.file("camera.yaml") +
                          "' distortion_coefficients.data: non-zero distortion",
                      0),
            0u)
      << msg;
  EXPECT_NE(msg.find("rectify"), std::string::npos) << msg;
}

TEST(FramesFolderCamera, DepthScaleMustBePositive)
{
  TempDir dir;
  for (const char* scale : {"0", "-1"}) {
    const std::string msg =
        cameraError(dir, std::string(kRosCameraYaml) + "depth_scale: " + scale + "\n");
    EXPECT_EQ(msg, "'" + dir.file("camera.yaml") +
                       "' depth_scale: expected units per metre > 0 (1000: millimetres), "
                       "got " +
                       scale)
        << msg;
  }
}

TEST(FramesFolderCamera, OtherErrors)
{
  TempDir dir;
  EXPECT_NE(cameraError(dir, rosYamlWith("image_width: 640\n", ""))
                .find("image_width: missing"),
            std::string::npos);
  EXPECT_NE(cameraError(dir, rosYamlWith("image_height: 480", "image_height: 0"))
                .find("image_height: expected 1 to 16384 pixels, got 0"),
            std::string::npos);
  EXPECT_NE(
      cameraError(dir, std::string(kRosCameraYaml) + "fx: 3\n").find("fx: unknown key"),
      std::string::npos);
  EXPECT_NE(cameraError(dir, "").find("(top level): expected a map"), std::string::npos);
  const std::string missing = dir.file("missing.yaml");
  EXPECT_NE(thrownMessage<IoError>([&] { readCameraInfo(missing); }).find(missing),
            std::string::npos);
}

// --- writer -> reader ---

TEST(FramesFolderWriter, AppendsAndReadsBackExactly)
{
  TempDir dir;
  const std::string folder = dir.file("frames");
  const CameraInfo camera = smallCamera();
  std::vector<DepthImage> depths;
  std::vector<Pose> poses;
  for (std::uint32_t i = 0; i < 4; ++i) {
    depths.push_back(randomDepth(camera, 10 + i));
    poses.push_back(randomPose(20 + i));
  }
  poses[1].position = {-0.0, 5e-324, 123456789.123456789}; // signed zero, subnormal
  {
    FramesFolderWriter writer(folder, camera);
    EXPECT_EQ(writer.frameCount(), 0u);
    EXPECT_EQ(writer.lastStamp(), -1.0);
    writer.append(depths[0], poses[0], 1305031102.175304);
    writer.append(depths[1], poses[1], 1305031102.211214);
    writer.append(depths[2], poses[2], std::nan("")); // the last + 1 s
    EXPECT_EQ(writer.frameCount(), 3u);
  }
  {
    // A second writer continues the folder: its count, its stamps, its file names.
    FramesFolderWriter writer(folder, camera);
    EXPECT_EQ(writer.frameCount(), 3u);
    EXPECT_EQ(writer.lastStamp(), 1305031103.211214);
    writer.append(depths[3], poses[3], std::nan(""));
    EXPECT_EQ(writer.frameCount(), 4u);
    EXPECT_EQ(writer.lastStamp(), 1305031104.211214);
  }
  EXPECT_TRUE(std::filesystem::is_regular_file(folder + "/depth/000003.png"));

  const FramesFolder frames(folder);
  EXPECT_EQ(frames.folder(), folder);
  EXPECT_EQ(frames.camera().intrinsics.fx, camera.intrinsics.fx);
  EXPECT_EQ(frames.camera().depth_scale, camera.depth_scale);
  EXPECT_EQ(frames.skippedFrames(), 0u);
  ASSERT_EQ(frames.frames().size(), 4u);
  const double stamps[] = {1305031102.175304, 1305031102.211214, 1305031103.211214,
                           1305031104.211214};
  for (std::size_t i = 0; i < 4; ++i) {
    SCOPED_TRACE(i);
    const plantnbv::io::FrameRecord& f = frames.frames()[i];
    EXPECT_EQ(f.stamp_s, stamps[i]);
    EXPECT_EQ(f.pose_dt_s, 0.0);
    EXPECT_EQ(f.depth_path, (std::filesystem::path(folder) /
                             ("depth/00000" + std::to_string(i) + ".png"))
                                .string());
    // Bit for bit: position and quaternion coefficients.
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(f.T_W_O.position[k], poses[i].position[k]) << k;
      EXPECT_EQ(std::signbit(f.T_W_O.position[k]), std::signbit(poses[i].position[k]))
          << k;
    }
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(f.T_W_O.orientation.coeffs()[k], poses[i].orientation.coeffs()[k]) << k;

    DepthImage depth;
    frames.loadDepth(i, depth);
    ASSERT_EQ(depth.width, camera.intrinsics.width);
    ASSERT_EQ(depth.height, camera.intrinsics.height);
    ASSERT_EQ(depth.depth_m.size(), depths[i].depth_m.size());
    for (std::size_t p = 0; p < depth.depth_m.size(); ++p) {
      const float expected = plantnbv::depthFromUnits(
          plantnbv::depthToUnits(depths[i].depth_m[p], camera.depth_scale),
          camera.depth_scale);
      EXPECT_TRUE(sameDepth(depth.depth_m[p], expected))
          << "pixel " << p << ": " << depth.depth_m[p] << " vs " << expected;
    }
    EXPECT_TRUE(std::isnan(depth.depth_m[0]));
    EXPECT_TRUE(std::isnan(depth.depth_m[1]));
    EXPECT_TRUE(std::isnan(depth.depth_m[2]));
  }
  EXPECT_THROW(
      {
        DepthImage depth;
        frames.loadDepth(4, depth);
      },
      std::out_of_range);
}

TEST(FramesFolderWriter, AFrameThatCannotBeStoredWholeLeavesTheFolderAsItWas)
{
  TempDir dir;
  const std::string folder = dir.file("frames");
  const CameraInfo camera = smallCamera();
  FramesFolderWriter writer(folder, camera);
  for (std::uint32_t i = 0; i < 40; ++i)
    writer.append(randomDepth(camera, i), randomPose(100 + i), std::nan(""));
  const std::string poses = readBytes(folder + "/groundtruth.txt");
  const std::string list = readBytes(folder + "/depth.txt");
  // The image fits under the limit, the pose list with its new line does not: neither
  // list changes, and the image, which no list names, is gone again.
  ASSERT_LT(std::filesystem::file_size(folder + "/depth/000000.png") + 512, poses.size());
  try {
    const plantnbv::test::FileSizeLimit full(poses.size());
    writer.append(randomDepth(camera, 40), randomPose(140), std::nan(""));
    FAIL() << "a frame was stored past the limit";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("groundtruth.txt': File too large"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(readBytes(folder + "/groundtruth.txt"), poses);
  EXPECT_EQ(readBytes(folder + "/depth.txt"), list);
  EXPECT_FALSE(std::filesystem::exists(folder + "/depth/000040.png"));
  for (const auto& e : std::filesystem::directory_iterator(folder))
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
  // With room again, the same writer goes on where it was.
  EXPECT_EQ(writer.frameCount(), 40u);
  writer.append(randomDepth(camera, 40), randomPose(140), std::nan(""));
  EXPECT_EQ(FramesFolder(folder).frames().size(), 41u);
}

TEST(FramesFolderWriter, RefusesAnotherCamera)
{
  TempDir dir;
  const std::string folder = dir.file("frames");
  const CameraInfo camera = smallCamera();
  FramesFolderWriter(folder, camera).append(randomDepth(camera, 1), randomPose(2), 1.0);
  CameraInfo other = camera;
  other.intrinsics.fx += 1.0;
  std::string msg =
      thrownMessage<FormatError>([&] { FramesFolderWriter(folder, other); });
  EXPECT_NE(msg.find("camera.yaml' describes another camera"), std::string::npos) << msg;
  other = camera;
  other.depth_scale = 1000.0;
  msg = thrownMessage<FormatError>([&] { FramesFolderWriter(folder, other); });
  EXPECT_NE(msg.find("depth_scale 5000"), std::string::npos) << msg;
  // The folder is unchanged.
  EXPECT_EQ(readCameraInfo(folder + "/camera.yaml").intrinsics.fx, camera.intrinsics.fx);
  EXPECT_EQ(FramesFolder(folder).frames().size(), 1u);
}

TEST(FramesFolderWriter, RefusesAStampNotAfterTheLastAndAWrongSize)
{
  TempDir dir;
  const std::string folder = dir.file("frames");
  const CameraInfo camera = smallCamera();
  FramesFolderWriter writer(folder, camera);
  writer.append(randomDepth(camera, 1), randomPose(2), 5.0);
  EXPECT_THROW(writer.append(randomDepth(camera, 1), randomPose(2), 5.0),
               InvalidArgumentError);
  EXPECT_THROW(writer.append(randomDepth(camera, 1), randomPose(2), 4.0),
               InvalidArgumentError);
  EXPECT_THROW(writer.append(randomDepth(camera, 1), randomPose(2), INFINITY),
               InvalidArgumentError);
  // A new writer knows the last stamp from depth.txt.
  FramesFolderWriter again(folder, camera);
  EXPECT_THROW(again.append(randomDepth(camera, 1), randomPose(2), 4.5),
               InvalidArgumentError);
  DepthImage small;
  small.width = 4;
  small.height = 3;
  small.depth_m.assign(12, 1.0f);
  EXPECT_THROW(again.append(small, randomPose(2), 6.0), InvalidArgumentError);
  EXPECT_EQ(again.frameCount(), 1u);
  EXPECT_EQ(FramesFolder(folder).frames().size(), 1u);
  EXPECT_FALSE(std::filesystem::exists(folder + "/depth/000001.png"));
}

TEST(FramesFolderWriter, NeverOverwritesAnUnlistedPng)
{
  TempDir dir;
  const std::string folder = dir.file("frames");
  const CameraInfo camera = smallCamera();
  FramesFolderWriter writer(folder, camera);
  writer.append(randomDepth(camera, 1), randomPose(2), 1.0);
  // What an interrupted append leaves: a PNG that depth.txt does not list.
  const std::string stray = folder + "/depth/000001.png";
  {
    std::ofstream(stray, std::ios::binary) << "an interrupted frame";
  }
  const std::string msg = thrownMessage<IoError>(
      [&] { writer.append(randomDepth(camera, 3), randomPose(4), 2.0); });
  EXPECT_NE(msg.find(stray), std::string::npos) << msg;
  EXPECT_EQ(readBytes(stray), "an interrupted frame");
  EXPECT_EQ(writer.frameCount(), 1u);
  EXPECT_EQ(FramesFolder(folder).frames().size(), 1u);
}

// --- association of frames and poses ---

TEST(FramesFolderAssociation, TakesAPoseWithin20Milliseconds)
{
  TempDir dir;
  writeFolder(dir, "1.015");
  const FramesFolder frames(dir.file(""));
  ASSERT_EQ(frames.frames().size(), 1u);
  EXPECT_NEAR(frames.frames()[0].pose_dt_s, 0.015, 1e-12);
  EXPECT_EQ(frames.frames()[0].T_W_O.position, Eigen::Vector3d(1, 2, 3));
}

TEST(FramesFolderAssociation, AFrameWithoutAPoseIsAnErrorNamingItsLine)
{
  TempDir dir;
  writeFolder(dir, "1.03");
  const std::string msg = thrownMessage<FormatError>([&] { FramesFolder(dir.file("")); });
  EXPECT_TRUE(namesLine(msg, dir.file("depth.txt"), 2));
  EXPECT_NE(msg.find("frame 'depth/a.png' (1.000000 s)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("(nearest 1.030000 s)"), std::string::npos) << msg;
  // A wider window takes it.
  FramesFolderOptions options;
  options.max_pose_dt_s = 0.05;
  EXPECT_EQ(FramesFolder(dir.file(""), options).frames().size(), 1u);
}

TEST(FramesFolderAssociation, SkipUnmatchedSkipsAndCounts)
{
  TempDir dir;
  writeFolder(dir);
  dir.write("depth.txt", "1.0 depth/a.png\n2.0 depth/b.png\n3.0 depth/c.png\n"
                         "3.5 depth/d.png\n");
  dir.write("groundtruth.txt", "1.0 1 0 0 0 0 0 1\n3.01 3 0 0 0 0 0 1\n");
  EXPECT_THROW(FramesFolder(dir.file("")), FormatError);
  FramesFolderOptions options;
  options.skip_unmatched = true;
  const FramesFolder frames(dir.file(""), options);
  ASSERT_EQ(frames.frames().size(), 2u);
  EXPECT_EQ(frames.skippedFrames(), 2u);
  EXPECT_EQ(frames.frames()[0].T_W_O.position.x(), 1.0);
  EXPECT_EQ(frames.frames()[1].T_W_O.position.x(), 3.0);
  EXPECT_EQ(frames.frames()[1].depth_path,
            (std::filesystem::path(dir.file("")) / "depth/c.png").string());
  // None matched: an error even when skipping.
  dir.write("groundtruth.txt", "100 1 0 0 0 0 0 1\n");
  const std::string msg =
      thrownMessage<FormatError>([&] { FramesFolder(dir.file(""), options); });
  EXPECT_NE(msg.find("none of its 4 frames has a pose"), std::string::npos) << msg;
}

TEST(FramesFolderAssociation, TakesTheNearestOfTwoPoses)
{
  TempDir dir;
  writeFolder(dir);
  // Out of order on purpose: the reader sorts the poses by stamp.
  dir.write("depth.txt", "1.0 depth/a.png\n2.0 depth/b.png\n");
  dir.write("groundtruth.txt", "2.012 4 0 0 0 0 0 1\n1.005 2 0 0 0 0 0 1\n"
                               "0.99 1 0 0 0 0 0 1\n1.995 3 0 0 0 0 0 1\n");
  const FramesFolder frames(dir.file(""));
  ASSERT_EQ(frames.frames().size(), 2u);
  EXPECT_EQ(frames.frames()[0].T_W_O.position.x(), 2.0);
  EXPECT_NEAR(frames.frames()[0].pose_dt_s, 0.005, 1e-12);
  EXPECT_EQ(frames.frames()[1].T_W_O.position.x(), 3.0);
  EXPECT_NEAR(frames.frames()[1].pose_dt_s, 0.005, 1e-12);
}

TEST(FramesFolderAssociation, ReadsPosesTxtWithoutGroundtruthTxt)
{
  TempDir dir;
  writeFolder(dir);
  std::filesystem::remove(dir.file("groundtruth.txt"));
  dir.write("poses.txt", "1.0 7 8 9 0 0 0 1\n");
  const FramesFolder frames(dir.file(""));
  ASSERT_EQ(frames.frames().size(), 1u);
  EXPECT_EQ(frames.frames()[0].T_W_O.position, Eigen::Vector3d(7, 8, 9));
  // groundtruth.txt wins when both are there.
  dir.write("groundtruth.txt", "1.0 1 2 3 0 0 0 1\n");
  EXPECT_EQ(FramesFolder(dir.file("")).frames()[0].T_W_O.position,
            Eigen::Vector3d(1, 2, 3));
  // Neither: an IoError naming groundtruth.txt.
  std::filesystem::remove(dir.file("groundtruth.txt"));
  std::filesystem::remove(dir.file("poses.txt"));
  const std::string msg = thrownMessage<IoError>([&] { FramesFolder(dir.file("")); });
  EXPECT_NE(msg.find(dir.file("groundtruth.txt")), std::string::npos) << msg;
  EXPECT_NE(msg.find("poses.txt"), std::string::npos) << msg;
}

// --- bad folders ---

TEST(FramesFolderErrors, MissingFolderAndEmptyFolder)
{
  TempDir dir;
  std::string msg =
      thrownMessage<FileNotFoundError>([&] { FramesFolder(dir.file("nothing")); });
  EXPECT_NE(msg.find(dir.file("nothing")), std::string::npos) << msg;
  msg = thrownMessage<FileNotFoundError>([&] { FramesFolder(dir.file("")); });
  EXPECT_NE(msg.find(dir.file("camera.yaml") + "': no such file"), std::string::npos)
      << msg;
  // A file where the folder should be exists: an IoError, not "no such folder".
  dir.write("a_file", "x");
  msg = thrownMessage<IoError>([&] { FramesFolder(dir.file("a_file")); });
  EXPECT_NE(msg.find("is not a folder"), std::string::npos) << msg;
}

TEST(FramesFolderErrors, MissingCameraYamlOrDepthTxt)
{
  TempDir dir;
  writeFolder(dir);
  std::filesystem::remove(dir.file("camera.yaml"));
  std::string msg = thrownMessage<FileNotFoundError>([&] { FramesFolder(dir.file("")); });
  EXPECT_NE(msg.find(dir.file("camera.yaml") + "': no such file"), std::string::npos)
      << msg;
  writeFolder(dir);
  std::filesystem::remove(dir.file("depth.txt"));
  msg = thrownMessage<FileNotFoundError>([&] { FramesFolder(dir.file("")); });
  EXPECT_NE(msg.find(dir.file("depth.txt") + "': no such file"), std::string::npos)
      << msg;
}

TEST(FramesFolderErrors, BadCameraYamlInAFolder)
{
  TempDir dir;
  writeFolder(dir);
  dir.write("camera.yaml", std::string(kRosCameraYaml) + "depth_scale: -1\n");
  const std::string msg = thrownMessage<FormatError>([&] { FramesFolder(dir.file("")); });
  EXPECT_EQ(msg.rfind("'" + dir.file("camera.yaml") + "' depth_scale:", 0), 0u) << msg;
  FramesFolderOptions options;
  options.depth_scale = -2.0;
  writeFolder(dir);
  EXPECT_THROW(FramesFolder(dir.file(""), options), InvalidArgumentError);
  options.depth_scale = 2500.0;
  EXPECT_EQ(FramesFolder(dir.file(""), options).camera().depth_scale, 2500.0);
}

TEST(FramesFolderErrors, AFolderThatListsNoFrame)
{
  TempDir dir;
  writeFolder(dir);
  dir.write("depth.txt", "# timestamp filename\n\n   \n");
  const std::string msg = thrownMessage<FormatError>([&] { FramesFolder(dir.file("")); });
  EXPECT_EQ(msg, "'" + dir.file("depth.txt") + "': lists no frame");
}

// --- depth PNGs ---

TEST(FramesFolderDepth, ImageSizeMustMatchTheCamera)
{
  TempDir dir;
  writeFolder(dir);
  const std::string png = dir.file("depth/a.png");
  plantnbv::io::saveDepthPng(png, 4, 3, std::vector<float>(12, 1.0f), 5000.0);
  const FramesFolder frames(dir.file(""));
  DepthImage depth;
  const std::string msg = thrownMessage<FormatError>([&] { frames.loadDepth(0, depth); });
  EXPECT_EQ(msg, "'" + png + "' is 4x3, camera.yaml says 8x6");
}

TEST(FramesFolderDepth, EightBitAndRgbPngsAreRefused)
{
  TempDir dir;
  writeFolder(dir);
  const std::string png = dir.file("depth/a.png");
  const FramesFolder frames(dir.file(""));
  DepthImage depth;
  for (png_uint_32 format : {png_uint_32(PNG_FORMAT_GRAY), png_uint_32(PNG_FORMAT_RGB)}) {
    SCOPED_TRACE(format);
    writePng(png, 8, 6, format);
    const std::string msg =
        thrownMessage<FormatError>([&] { frames.loadDepth(0, depth); });
    EXPECT_EQ(msg, "'" + png + "' is not a 16-bit grey PNG (a depth image)");
  }
}

TEST(FramesFolderDepth, TruncatedPng)
{
  TempDir dir;
  writeFolder(dir);
  const std::string png = dir.file("depth/a.png");
  plantnbv::io::saveDepthPng(png, 8, 6, randomDepth(smallCamera(), 3).depth_m, 5000.0);
  const FramesFolder frames(dir.file(""));
  DepthImage depth;
  frames.loadDepth(0, depth); // whole, it reads
  const std::string bytes = readBytes(png);
  dir.write("depth/a.png", bytes.substr(0, bytes.size() / 2));
  const std::string msg = thrownMessage<FormatError>([&] { frames.loadDepth(0, depth); });
  EXPECT_NE(msg.find("'" + png + "'"), std::string::npos) << msg;
}

TEST(FramesFolderDepth, AMissingPngIsAnIoError)
{
  TempDir dir;
  writeFolder(dir);
  const FramesFolder frames(dir.file(""));
  DepthImage depth;
  const std::string msg = thrownMessage<IoError>([&] { frames.loadDepth(0, depth); });
  EXPECT_NE(msg.find(dir.file("depth/a.png")), std::string::npos) << msg;
}

// --- depth.txt ---

TEST(FramesFolderLists, ReadsTumFileLists)
{
  TempDir dir;
  const auto files = readTumFileList(
      dir.write("depth.txt", "# depth maps\n# timestamp filename\n"
                             "1305031102.160407 depth/1305031102.160407.png\r\n\n"
                             "  1305031102.194330\tdepth/b.png  \n"));
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0].stamp_s, 1305031102.160407);
  EXPECT_EQ(files[0].file, "depth/1305031102.160407.png");
  EXPECT_EQ(files[0].line, 3u);
  EXPECT_EQ(files[1].file, "depth/b.png");
  EXPECT_EQ(files[1].line, 5u);
}

TEST(FramesFolderLists, PathsMustStayInsideTheFolder)
{
  TempDir dir;
  const std::string path = dir.file("depth.txt");
  for (const char* file : {"/tmp/x.png", "../x.png", "depth/../../x.png", "depth/.."}) {
    SCOPED_TRACE(file);
    const std::string msg = listError(dir, "# ts file\n1.0 " + std::string(file) + "\n");
    EXPECT_TRUE(namesLine(msg, path, 2));
    EXPECT_NE(msg.find("'" + std::string(file) + "' must be a path inside the folder"),
              std::string::npos)
        << msg;
  }
}

TEST(FramesFolderLists, TimestampMustBeANumber)
{
  TempDir dir;
  const std::string path = dir.file("depth.txt");
  std::string msg = listError(dir, "1.0 depth/a.png\nabc depth/b.png\n");
  EXPECT_TRUE(namesLine(msg, path, 2));
  EXPECT_NE(msg.find("timestamp 'abc' is not a number"), std::string::npos) << msg;
  msg = listError(dir, "1.0s depth/a.png\n");
  EXPECT_TRUE(namesLine(msg, path, 1));
  msg = listError(dir, "nan depth/a.png\n");
  EXPECT_NE(msg.find("timestamp 'nan' is not a finite number"), std::string::npos) << msg;
  msg = listError(dir, "1.0 depth/a.png extra\n");
  EXPECT_NE(msg.find("expected 'timestamp filename', got 3 fields"), std::string::npos)
      << msg;
  // Through the folder as well.
  writeFolder(dir);
  dir.write("depth.txt", "x depth/a.png\n");
  msg = thrownMessage<FormatError>([&] { FramesFolder(dir.file("")); });
  EXPECT_TRUE(namesLine(msg, path, 1));
}

// --- groundtruth.txt ---

TEST(FramesFolderPoses, ReadsTumTrajectories)
{
  TempDir dir;
  const auto poses = readTumTrajectory(
      dir.write("groundtruth.txt",
                "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n"
                "1305031098.6659 1.3563 0.6305 1.6380 0.6132 0.5962 -0.3311 -0.3986\n"));
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_EQ(poses[0].stamp_s, 1305031098.6659);
  EXPECT_EQ(poses[0].line, 3u);
  EXPECT_EQ(poses[0].pose.position, Eigen::Vector3d(1.3563, 0.6305, 1.6380));
  EXPECT_NEAR(poses[0].pose.orientation.norm(), 1.0, 1e-15);
  EXPECT_EQ(poses[0].pose.orientation.w() < 0, true);
}

TEST(FramesFolderPoses, WrongNumberOfFields)
{
  TempDir dir;
  const std::string path = dir.file("groundtruth.txt");
  std::string msg = poseError(dir, "1.0 0 0 0 0 0 0 1\n2.0 1 2 3 0 0\n");
  EXPECT_TRUE(namesLine(msg, path, 2));
  EXPECT_NE(msg.find("expected 8 numbers 'timestamp tx ty tz qx qy qz qw', got 6"),
            std::string::npos)
      << msg;
  msg = poseError(dir, "2.0 1 2 3 0 0 0 1 5\n");
  EXPECT_TRUE(namesLine(msg, path, 1));
  EXPECT_NE(msg.find("got 9"), std::string::npos) << msg;
}

TEST(FramesFolderPoses, NonFiniteNumbers)
{
  TempDir dir;
  const std::string path = dir.file("groundtruth.txt");
  std::string msg = poseError(dir, "# c\n2.0 1 nan 3 0 0 0 1\n");
  EXPECT_TRUE(namesLine(msg, path, 2));
  EXPECT_NE(msg.find("ty 'nan' is not a finite number"), std::string::npos) << msg;
  msg = poseError(dir, "2.0 1 2 3 0 0 0 inf\n");
  EXPECT_TRUE(namesLine(msg, path, 1));
  EXPECT_NE(msg.find("qw 'inf' is not a finite number"), std::string::npos) << msg;
  msg = poseError(dir, "2.0 1 2 1e999 0 0 0 1\n");
  EXPECT_NE(msg.find("tz '1e999' is not a finite number"), std::string::npos) << msg;
  msg = poseError(dir, "2.0 1 2 3 0 0 0 one\n");
  EXPECT_NE(msg.find("qw 'one' is not a number"), std::string::npos) << msg;
}

TEST(FramesFolderPoses, QuaternionNorm)
{
  TempDir dir;
  const std::string path = dir.file("groundtruth.txt");
  std::string msg = poseError(dir, "\n\n2.0 1 2 3 0 0 0 0\n");
  EXPECT_TRUE(namesLine(msg, path, 3));
  EXPECT_NE(msg.find("quaternion (0, 0, 0, 0) has norm 0"), std::string::npos) << msg;
  msg = poseError(dir, "2.0 1 2 3 0 0 0 1.01\n");
  EXPECT_TRUE(namesLine(msg, path, 1));
  EXPECT_NE(msg.find("has norm 1.01, expected a unit quaternion"), std::string::npos)
      << msg;
  // Within 1e-3 of 1: accepted and normalized.
  const auto poses =
      readTumTrajectory(dir.write("groundtruth.txt", "2.0 1 2 3 0 0.6 0 0.8004\n"));
  ASSERT_EQ(poses.size(), 1u);
  const Eigen::Quaterniond& q = poses[0].pose.orientation;
  const double norm = std::sqrt(0.6 * 0.6 + 0.8004 * 0.8004);
  EXPECT_NEAR(norm, 1.0003, 1e-4);
  EXPECT_NEAR(q.norm(), 1.0, 1e-15);
  EXPECT_NEAR(q.y(), 0.6 / norm, 1e-15);
  EXPECT_NEAR(q.w(), 0.8004 / norm, 1e-15);
  EXPECT_EQ(q.x(), 0.0);
  EXPECT_EQ(q.z(), 0.0);
  const auto scaled =
      readTumTrajectory(dir.write("groundtruth.txt", "2.0 1 2 3 0 0 0 1.0005\n"));
  ASSERT_EQ(scaled.size(), 1u);
  EXPECT_EQ(scaled[0].pose.orientation.w(), 1.0);
}
