#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <png.h>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include <plantnbv/camera/depth_image.h>
#include <plantnbv/common/error.h>
#include <plantnbv/io/depth_image_io.h>
#include <plantnbv/io/detections_io.h>
#include <plantnbv/io/frames_folder.h>

#include "io_test_util.h"

using plantnbv::DepthImage;
using plantnbv::Detection;
using plantnbv::detectionPixels;
using plantnbv::FileNotFoundError;
using plantnbv::FormatError;
using plantnbv::InvalidArgumentError;
using plantnbv::IoError;
using plantnbv::Pose;
using plantnbv::io::CameraInfo;
using plantnbv::io::FramesFolder;
using plantnbv::io::FramesFolderOptions;
using plantnbv::io::FramesFolderWriter;
using plantnbv::io::loadMaskPng;
using plantnbv::io::readDetections;
using plantnbv::io::saveMaskPng;
using plantnbv::io::writeCameraInfo;
using plantnbv::io::writeDetections;
using plantnbv::test::readBytes;
using plantnbv::test::TempDir;
using plantnbv::test::thrownMessage;

namespace fs = std::filesystem;

namespace {

constexpr std::uint32_t kWidth = 8, kHeight = 6;

Detection detection(const std::string& class_name, double score, double u0, double v0,
                    double u1, double v1)
{
  Detection d;
  d.class_name = class_name;
  d.score = score;
  d.box_px = Eigen::Vector4d(u0, v0, u1, v1);
  return d;
}

/// An 8 x 6 mask: the pixels of `pixels` set to `value`.
std::vector<std::uint8_t> mask(const std::vector<std::uint32_t>& pixels,
                               std::uint8_t value = 255)
{
  std::vector<std::uint8_t> m(kWidth * kHeight, 0);
  for (std::uint32_t p : pixels)
    m[p] = value;
  return m;
}

void expectSame(const std::vector<Detection>& read, const std::vector<Detection>& written)
{
  ASSERT_EQ(read.size(), written.size());
  for (std::size_t i = 0; i < read.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(read[i].class_name, written[i].class_name);
    EXPECT_EQ(read[i].score, written[i].score);
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(read[i].box_px[k], written[i].box_px[k]) << k;
    EXPECT_EQ(read[i].mask, written[i].mask);
  }
}

/// An image in `format` with every sample 1.
void writePng(const std::string& path, std::uint32_t width, std::uint32_t height,
              png_uint_32 format)
{
  plantnbv::test::writePng(path, width, height, format, 1);
}

/// One entry with `extra` appended inside it (", \"mask\": ...").
std::string entry(const std::string& extra = "")
{
  return R"({"class": "leaf_node", "score": 0.5, "box": [0, 0, 8, 6])" + extra + "}";
}

std::string file(const std::string& entries)
{
  return R"({"detections": [)" + entries + "]}";
}

/// The message of the FormatError readDetections gives for this content (8 x 6 image),
/// without its "'PATH' " prefix (checked).
std::string formatError(const TempDir& dir, const std::string& content)
{
  const std::string path = dir.write("det.json", content);
  const std::string msg =
      thrownMessage<FormatError>([&] { readDetections(path, kWidth, kHeight); });
  const std::string prefix = "'" + path + "'";
  if (msg.compare(0, prefix.size(), prefix) != 0) {
    ADD_FAILURE() << "'" << msg << "' does not start with " << prefix;
    return msg;
  }
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  return msg.substr(prefix.size());
}

/// A small camera: 8 x 6 pixels.
CameraInfo smallCamera()
{
  CameraInfo info;
  info.intrinsics =
      plantnbv::CameraIntrinsics::custom(kWidth, kHeight, 4.0, 4.0, 3.5, 2.5);
  info.depth_scale = 1000.0;
  return info;
}

DepthImage flatDepth(float metres)
{
  DepthImage depth;
  depth.width = kWidth;
  depth.height = kHeight;
  depth.depth_m.assign(kWidth * kHeight, metres);
  return depth;
}

/// A frames folder with one frame at each of `stamps` ("depth/a.png", ... not written)
/// and a pose at each.
void writeFolder(const TempDir& dir, const std::vector<std::string>& stamps)
{
  writeCameraInfo(dir.file("camera.yaml"), smallCamera());
  std::string depth, poses;
  char name = 'a';
  for (const std::string& s : stamps) {
    depth += s + " depth/" + name++ + ".png\n";
    poses += s + " 1 2 3 0 0 0 1\n";
  }
  dir.write("depth.txt", depth);
  dir.write("groundtruth.txt", poses);
}

} // namespace

// --- the file format ---

TEST(DetectionsIo, RoundTripWithoutMasksIsExact)
{
  TempDir dir;
  const std::vector<Detection> written = {
      detection("leaf_node", 0.1 + 0.2, 0.0, 0.0, 8.0, 6.0),
      detection("fruit", 1.0, 1.0 / 3.0, 2.5, 7.999999999999999, 2.5),
      detection("a \"quoted\" \\ class\twith tab, und Blätter", 0.0, 3.0, 3.0, 3.0, 3.0),
      detection("whatever_the_detector_says", -0.0, 5e-324, 0.0, 1.0, 1e-300)};
  const std::string path = dir.file("000001.json");
  writeDetections(path, written, kWidth, kHeight);
  expectSame(readDetections(path, kWidth, kHeight), written);
  EXPECT_FALSE(fs::exists(dir.file("000001_0.png")));
  EXPECT_EQ(readBytes(path).find("mask"), std::string::npos);
  // A sign of zero is kept.
  EXPECT_TRUE(std::signbit(readDetections(path, kWidth, kHeight)[3].score));
}

TEST(DetectionsIo, RoundTripWithMasks)
{
  TempDir dir;
  std::vector<Detection> written = {detection("leaf_node", 0.9, 1, 1, 4, 3),
                                    detection("fruit", 0.75, 0, 0, 8, 6),
                                    detection("main_stem", 0.5, 2, 0, 3, 6)};
  written[0].mask = mask({9, 10, 11, 17}, 1);
  written[2].mask = mask({2, 10, 18, 26, 34, 42}, 255);
  written[2].mask[0] = 7; // non-zero values are kept as they are
  fs::create_directories(dir.file("det"));
  const std::string path = dir.file("det/000004.json");
  writeDetections(path, written, kWidth, kHeight);
  EXPECT_TRUE(fs::is_regular_file(dir.file("det/000004_0.png")));
  EXPECT_FALSE(fs::exists(dir.file("det/000004_1.png")));
  EXPECT_TRUE(fs::is_regular_file(dir.file("det/000004_2.png")));
  EXPECT_NE(readBytes(path).find("\"mask\": \"000004_2.png\""), std::string::npos)
      << readBytes(path);
  expectSame(readDetections(path, kWidth, kHeight), written);
}

TEST(DetectionsIo, EmptyListAndHandWrittenFile)
{
  TempDir dir;
  const std::string path = dir.file("none.json");
  writeDetections(path, {}, kWidth, kHeight);
  EXPECT_TRUE(readDetections(path, kWidth, kHeight).empty());

  // As a detector's script would write it: integers, a mask in a subfolder, any key
  // order.
  fs::create_directories(dir.file("masks"));
  saveMaskPng(dir.file("masks/m.png"), kWidth, kHeight, mask({0, 47}));
  const std::vector<Detection> read = readDetections(
      dir.write("hand.json",
                "\xEF\xBB\xBF{ \"detections\" : [ {\"box\": [1, 2, 3, 4], \"mask\": "
                "\"masks/m.png\", \"score\": 1, \"class\": \"truss\"} ] }\r\n"),
      kWidth, kHeight);
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(read[0].class_name, "truss");
  EXPECT_EQ(read[0].score, 1.0);
  EXPECT_EQ(read[0].box_px, Eigen::Vector4d(1, 2, 3, 4));
  EXPECT_EQ(read[0].mask, mask({0, 47}));
}

// --- detectionPixels ---

TEST(DetectionsPixels, BoxTakesThePixelsWhoseCentresItHolds)
{
  using V = std::vector<std::uint32_t>;
  const auto pixels = [](double u0, double v0, double u1, double v1) {
    return detectionPixels(detection("x", 1, u0, v0, u1, v1), kWidth, kHeight);
  };
  V all(kWidth * kHeight);
  for (std::uint32_t i = 0; i < all.size(); ++i)
    all[i] = i;
  EXPECT_EQ(pixels(0, 0, 8, 6), all);
  EXPECT_EQ(pixels(2, 2, 3, 3), V({2 * 8 + 2})); // pixel (2, 2) spans [2, 3)
  // Centres at u + 0.5: u0 1.5 takes column 1, u1 3.5 column 3; v 2.5 only row 2.
  EXPECT_EQ(pixels(1.5, 2, 3.5, 3), V({17, 18, 19}));
  EXPECT_EQ(pixels(1.6, 2.5, 3.4, 2.5), V({18}));
  EXPECT_EQ(pixels(3, 3, 3, 3), V{});         // no centre inside
  EXPECT_EQ(pixels(2.6, 0, 3.4, 6), V{});     // between two centres
  EXPECT_EQ(pixels(7.5, 5.5, 8, 6), V({47})); // the last pixel
  EXPECT_EQ(pixels(-3, -3, 1, 1), V({0}));    // clipped to the image
  EXPECT_EQ(pixels(10, 0, 20, 6), V{});       // outside
  EXPECT_EQ(pixels(4, 0, 3, 6), V{});         // u0 > u1
  EXPECT_EQ(pixels(-1e300, -1e300, 1e300, 1e300), all);
  EXPECT_EQ(detectionPixels(detection("x", 1, 0, 0, 1, 1), 0, 0), V{});
}

TEST(DetectionsPixels, MaskTakesItsNonZeroPixelsWhateverTheBox)
{
  Detection d = detection("fruit", 0.5, 0, 0, 1, 1);
  d.mask = mask({3, 20, 47}, 1);
  d.mask[5] = 200;
  EXPECT_EQ(detectionPixels(d, kWidth, kHeight),
            std::vector<std::uint32_t>({3, 5, 20, 47}));
  d.mask.assign(kWidth * kHeight, 0);
  EXPECT_TRUE(detectionPixels(d, kWidth, kHeight).empty());

  d.mask.resize(10);
  EXPECT_EQ(thrownMessage<InvalidArgumentError>([&] { detectionPixels(d, 8, 6); }),
            "detectionPixels: a mask of 10 bytes for a 8x6 image");
  d.mask.clear();
  d.box_px[2] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(thrownMessage<InvalidArgumentError>([&] { detectionPixels(d, 8, 6); }),
            "detectionPixels: box [0, 0, inf, 1] has a non-finite number");
}

// --- bad files ---

TEST(DetectionsIoErrors, MalformedJsonAndTopLevel)
{
  TempDir dir;
  EXPECT_EQ(
      formatError(dir, "{").rfind(": not JSON ([json.exception.parse_error.101]", 0), 0u);
  EXPECT_EQ(formatError(dir, "").rfind(": not JSON (", 0), 0u);
  EXPECT_EQ(
      formatError(dir, file(R"({"class": "a", "score": 1e999, "box": [0, 0, 1, 1]})"))
          .rfind(": not JSON (", 0),
      0u);
  EXPECT_EQ(formatError(dir, "{\"detections\": [{\"class\": \"\xff\"}]}")
                .rfind(": not JSON (", 0),
            0u);
  EXPECT_EQ(formatError(dir, "[]"),
            ": expected an object {\"detections\": [...]}, got a list of 0");
  EXPECT_EQ(formatError(dir, "\"detections\""),
            ": expected an object {\"detections\": [...]}, got \"detections\"");
  EXPECT_EQ(
      formatError(dir, "{}"),
      " detections: missing (a list of {\"class\", \"score\", \"box\"[, \"mask\"]})");
  EXPECT_EQ(formatError(dir, R"({"detections": [], "image": "rgb/1.png"})"),
            " image: unknown key (expected detections)");
  EXPECT_EQ(formatError(dir, R"({"detections": {}})"),
            " detections: expected a list, got an object");
  EXPECT_EQ(formatError(dir, R"({"detections": null})"),
            " detections: expected a list, got null");
}

TEST(DetectionsIoErrors, Entries)
{
  TempDir dir;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"3", " detections[0]: expected an object {\"class\", \"score\", \"box\"[, "
            "\"mask\"]}, got 3"},
      {entry(R"(, "colour": "red")"),
       " detections[0].colour: unknown key (expected one of box, class, mask, score)"},
      {entry(R"(, "a b\n": 1)"), " detections[0].\"a b\\n\": unknown key (expected one "
                                 "of box, class, mask, score)"},
      {R"({"score": 0.5, "box": [0, 0, 1, 1]})",
       " detections[0].class: missing (the object's class, e.g. \"leaf_node\")"},
      {R"({"class": 3, "score": 0.5, "box": [0, 0, 1, 1]})",
       " detections[0].class: expected a non-empty string, got 3"},
      {R"({"class": "", "score": 0.5, "box": [0, 0, 1, 1]})",
       " detections[0].class: is empty (expected the object's class, e.g. "
       "\"leaf_node\")"},
      {R"({"class": "a", "box": [0, 0, 1, 1]})",
       " detections[0].score: missing (a number in [0, 1])"},
      {R"({"class": "a", "score": "high", "box": [0, 0, 1, 1]})",
       " detections[0].score: expected a number in [0, 1], got \"high\""},
      {R"({"class": "a", "score": true, "box": [0, 0, 1, 1]})",
       " detections[0].score: expected a number in [0, 1], got true"},
      {R"({"class": "a", "score": 1.5, "box": [0, 0, 1, 1]})",
       " detections[0].score: 1.5 is not in [0, 1]"},
      {R"({"class": "a", "score": -0.25, "box": [0, 0, 1, 1]})",
       " detections[0].score: -0.25 is not in [0, 1]"},
      {R"({"class": "a", "score": 2, "box": [0, 0, 1, 1]})",
       " detections[0].score: 2 is not in [0, 1]"},
      {R"({"class": "a", "score": 0.5})",
       " detections[0].box: missing ([u0, v0, u1, v1] in pixels)"},
      {R"({"class": "a", "score": 0.5, "box": [0, 0, 1]})",
       " detections[0].box: expected 4 numbers [u0, v0, u1, v1] in pixels, got a list of "
       "3"},
      {R"({"class": "a", "score": 0.5, "box": [0, 0, 1, 1, 1]})",
       " detections[0].box: expected 4 numbers [u0, v0, u1, v1] in pixels, got a list of "
       "5"},
      {R"({"class": "a", "score": 0.5, "box": {"u0": 0}})",
       " detections[0].box: expected 4 numbers [u0, v0, u1, v1] in pixels, got an "
       "object"},
      {R"({"class": "a", "score": 0.5, "box": [0, null, 1, 1]})",
       " detections[0].box[1]: expected a number of pixels, got null"},
      {R"({"class": "a", "score": 0.5, "box": [0, 0, "1", 1]})",
       " detections[0].box[2]: expected a number of pixels, got \"1\""},
      {R"({"class": "a", "score": 0.5, "box": [3, 0, 2, 1]})",
       " detections[0].box: [3, 0, 2, 1]: u0 3 > u1 2 (expected [u0, v0, u1, v1], u0 <= "
       "u1)"},
      {R"({"class": "a", "score": 0.5, "box": [0, 1.5, 2, 1]})",
       " detections[0].box: [0, 1.5, 2, 1]: v0 1.5 > v1 1 (expected [u0, v0, u1, v1], v0 "
       "<= v1)"},
      {R"({"class": "a", "score": 0.5, "box": [0, 0, 8.5, 6]})",
       " detections[0].box: [0, 0, 8.5, 6] is outside the 8x6 image (expected 0 <= u0 <= "
       "u1 <= 8, 0 <= v0 <= v1 <= 6)"},
      {R"({"class": "a", "score": 0.5, "box": [-0.5, 0, 1, 1]})",
       " detections[0].box: [-0.5, 0, 1, 1] is outside the 8x6 image (expected 0 <= u0 "
       "<= u1 <= 8, 0 <= v0 <= v1 <= 6)"},
      {R"({"class": "a", "score": 0.5, "box": [0, 0, 1, 6.000001]})",
       " detections[0].box: [0, 0, 1, 6.000001] is outside the 8x6 image (expected 0 <= "
       "u0 <= u1 <= 8, 0 <= v0 <= v1 <= 6)"},
      {R"({"class": "a", "score": 0.5, "score": 0.6, "box": [0, 0, 1, 1]})",
       " detections[0].score: repeated key (a key may appear once in an object)"},
      {entry(R"(, "mask": 3)"),
       " detections[0].mask: expected the name of an 8-bit grey PNG, got 3"},
      {entry(R"(, "mask": "")"),
       " detections[0].mask: expected the name of an 8-bit grey PNG, got \"\""},
      {entry(R"(, "mask": "a\u0001.png")"),
       " detections[0].mask: expected a file name without control characters, got "
       "\"a\\u0001.png\""},
      {entry(R"(, "mask": "/tmp/m.png")"),
       " detections[0].mask: '/tmp/m.png' must be a path inside the JSON file's folder "
       "(relative, no '..')"},
      {entry(R"(, "mask": "masks/../../m.png")"),
       " detections[0].mask: 'masks/../../m.png' must be a path inside the JSON file's "
       "folder (relative, no '..')"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.first);
    EXPECT_EQ(formatError(dir, file(c.first)), c.second);
  }
  // The entry is named by its index; a repeated key by its path.
  EXPECT_EQ(
      formatError(dir, file(entry() + ", " + entry() + ", " +
                            R"({"class": "a", "score": 1.5, "box": [0, 0, 1, 1]})")),
      " detections[2].score: 1.5 is not in [0, 1]");
  EXPECT_EQ(formatError(dir, R"({"detections": [], "detections": []})"),
            " detections: repeated key (a key may appear once in an object)");
  EXPECT_EQ(formatError(dir, file(entry() + ", " + entry(R"(, "box": [1, 1, 2, 2])"))),
            " detections[1].box: repeated key (a key may appear once in an object)");
  // Keys of nested values (not read) are checked too, with their path.
  EXPECT_EQ(
      formatError(dir, file(entry(R"(, "x": [[0, {"k": 1, "k": 2}]])"))),
      " detections[0].x[0][1].k: repeated key (a key may appear once in an object)");
}

TEST(DetectionsIoErrors, Masks)
{
  TempDir dir;
  const std::string path = dir.file("det.json");
  const auto withMask = [&](const std::string& name) {
    return dir.write("det.json", file(entry(", \"mask\": \"" + name + "\"")));
  };
  const std::string at = "'" + path + "' detections[0].mask: ";

  withMask("none.png");
  EXPECT_EQ(thrownMessage<FileNotFoundError>([&] { readDetections(path, 8, 6); }),
            at + dir.file("none.png") + ": no such file");
  withMask(".");
  EXPECT_EQ(thrownMessage<IoError>([&] { readDetections(path, 8, 6); }),
            at + dir.file(".") + ": is a directory, expected a file");

  dir.write("text.png", "not a png");
  withMask("text.png");
  EXPECT_EQ(thrownMessage<FormatError>([&] {
              readDetections(path, 8, 6);
            }).rfind(at + "'" + dir.file("text.png") + "' is not a PNG file: ", 0),
            0u);

  for (const png_uint_32 format :
       {png_uint_32(PNG_FORMAT_RGB), png_uint_32(PNG_FORMAT_GA),
        png_uint_32(PNG_FORMAT_LINEAR_Y), png_uint_32(PNG_FORMAT_RGBA)}) {
    SCOPED_TRACE(format);
    writePng(dir.file("other.png"), 8, 6, format);
    withMask("other.png");
    EXPECT_EQ(thrownMessage<FormatError>([&] { readDetections(path, 8, 6); }),
              at + "'" + dir.file("other.png") +
                  "' is not an 8-bit grey PNG (an instance mask)");
  }
  writePng(dir.file("small.png"), 4, 3, PNG_FORMAT_GRAY);
  withMask("small.png");
  EXPECT_EQ(thrownMessage<FormatError>([&] { readDetections(path, 8, 6); }),
            at + "'" + dir.file("small.png") + "' is 4x3, the depth image is 8x6");

  saveMaskPng(dir.file("good.png"), 8, 6, mask({1}));
  const std::string good = readBytes(dir.file("good.png"));
  dir.write("truncated.png", good.substr(0, good.size() - 20));
  withMask("truncated.png");
  EXPECT_EQ(thrownMessage<FormatError>([&] {
              readDetections(path, 8, 6);
            }).rfind(at + "cannot decode mask '" + dir.file("truncated.png") + "'", 0),
            0u);
}

TEST(DetectionsIoErrors, Limits)
{
  TempDir dir;
  std::string entries = entry();
  for (std::size_t i = 1; i <= plantnbv::io::kMaxDetectionsPerFrame; ++i)
    entries += ", " + entry();
  EXPECT_EQ(formatError(dir, file(entries)),
            " detections: 10001 entries, more than 10000 (kMaxDetectionsPerFrame)");
  entries = entry();
  for (std::size_t i = 1; i < plantnbv::io::kMaxDetectionsPerFrame; ++i)
    entries += ", " + entry();
  EXPECT_EQ(readDetections(dir.write("det.json", file(entries)), 8, 6).size(), 10000u);

  // The masks' memory is checked before any mask is read (these do not exist).
  const std::string five =
      file(entry(R"(, "mask": "m.png")") + ", " + entry(R"(, "mask": "m.png")") + ", " +
           entry(R"(, "mask": "m.png")") + ", " + entry(R"(, "mask": "m.png")") + ", " +
           entry(R"(, "mask": "m.png")"));
  const std::string path = dir.write("det.json", five);
  EXPECT_EQ(thrownMessage<FormatError>([&] { readDetections(path, 16384, 16384); }),
            "'" + path +
                "' detections: 5 masks of 16384x16384 take 1342177280 bytes, more than "
                "1073741824 (kMaxMaskBytesPerFrame)");

  EXPECT_EQ(thrownMessage<InvalidArgumentError>([&] { readDetections(path, 0, 6); }),
            "readDetections: image 0x6 is not 1 to 16384 pixels per side");
  EXPECT_EQ(thrownMessage<FileNotFoundError>(
                [&] { readDetections(dir.file("no.json"), 8, 6); }),
            dir.file("no.json") + ": no such file");
}

TEST(DetectionsIoErrors, WriterRefusesWhatTheReaderWould)
{
  TempDir dir;
  const std::string path = dir.file("w.json");
  const std::string at = "'" + path + "' ";
  const auto writeError = [&](const Detection& d) {
    return thrownMessage<InvalidArgumentError>([&] {
      writeDetections(path, {detection("ok", 1, 0, 0, 1, 1), d}, 8, 6);
    });
  };
  EXPECT_EQ(writeError(detection("", 0.5, 0, 0, 1, 1)),
            at + "detections[1].class: is empty (expected the object's class, e.g. "
                 "\"leaf_node\")");
  EXPECT_EQ(writeError(detection("leaf\xff", 0.5, 0, 0, 1, 1)),
            at + "detections[1].class: is not UTF-8 text");
  EXPECT_EQ(writeError(detection("a", std::nan(""), 0, 0, 1, 1)),
            at + "detections[1].score: nan is not in [0, 1]");
  EXPECT_EQ(writeError(detection("a", 1.0000001, 0, 0, 1, 1)),
            at + "detections[1].score: 1.0000001 is not in [0, 1]");
  EXPECT_EQ(
      writeError(detection("a", 1, 0, -std::numeric_limits<double>::infinity(), 1, 1)),
      at + "detections[1].box: [0, -inf, 1, 1] has a non-finite number");
  EXPECT_EQ(
      writeError(detection("a", 1, 2, 0, 1, 1)),
      at + "detections[1].box: [2, 0, 1, 1]: u0 2 > u1 1 (expected [u0, v0, u1, v1], "
           "u0 <= u1)");
  EXPECT_EQ(writeError(detection("a", 1, 0, 0, 9, 1)),
            at +
                "detections[1].box: [0, 0, 9, 1] is outside the 8x6 image (expected 0 <= "
                "u0 <= u1 <= 8, 0 <= v0 <= v1 <= 6)");
  Detection d = detection("a", 1, 0, 0, 1, 1);
  d.mask.assign(47, 1);
  EXPECT_EQ(writeError(d),
            at + "detections[1].mask: has 47 bytes, expected 0 (no mask) or "
                 "8 x 6 = 48");
  EXPECT_FALSE(fs::exists(path)); // nothing written
  EXPECT_EQ(thrownMessage<InvalidArgumentError>(
                [&] { writeDetections(path, std::vector<Detection>(10001, d), 8, 6); }),
            at + "detections: 10001 entries, more than 10000 (kMaxDetectionsPerFrame)");
  EXPECT_THROW(writeDetections(path, {}, 8, 16385), InvalidArgumentError);
  EXPECT_THROW(writeDetections(dir.file("no/such/folder/w.json"), {}, 8, 6), IoError);
}

// --- mask PNGs ---

TEST(MaskPng, RoundTripAndFormats)
{
  TempDir dir;
  std::vector<std::uint8_t> m(8 * 6);
  for (std::size_t i = 0; i < m.size(); ++i)
    m[i] = std::uint8_t(i * 5);
  saveMaskPng(dir.file("m.png"), 8, 6, m);
  std::uint32_t w = 0, h = 0;
  std::vector<std::uint8_t> read;
  loadMaskPng(dir.file("m.png"), w, h, read);
  EXPECT_EQ(w, 8u);
  EXPECT_EQ(h, 6u);
  EXPECT_EQ(read, m);
  // An 8-bit grey PNG of another writer reads as it is.
  writePng(dir.file("grey.png"), 3, 2, PNG_FORMAT_GRAY);
  loadMaskPng(dir.file("grey.png"), w, h, read, 3, 2);
  EXPECT_EQ(read, std::vector<std::uint8_t>(6, 1));
  // A depth PNG is not a mask, nor a mask a depth PNG.
  EXPECT_EQ(thrownMessage<FormatError>([&] {
              plantnbv::io::saveDepthPng(dir.file("d.png"), 8, 6,
                                         std::vector<float>(48, 1.0f));
              loadMaskPng(dir.file("d.png"), w, h, read);
            }),
            "'" + dir.file("d.png") + "' is not an 8-bit grey PNG (an instance mask)");
  EXPECT_EQ(thrownMessage<FormatError>([&] {
              std::vector<float> depth;
              plantnbv::io::loadDepthPng(dir.file("m.png"), w, h, depth);
            }),
            "'" + dir.file("m.png") + "' is not a 16-bit grey PNG (a depth image)");
  EXPECT_EQ(thrownMessage<InvalidArgumentError>([&] {
              saveMaskPng(dir.file("x.png"), 8, 6, std::vector<std::uint8_t>(3));
            }),
            "saveMaskPng: image 8x6 does not match 3 mask bytes");
}

TEST(MaskPng, OneBitGreyIsExpandedZeroStayingZero)
{
  // 8 x 6, 1-bit grey (as PIL's mode "1" writes masks), pixel (u, v) set where u == v.
  const std::string png(
      "\x89\x50\x4e\x47\x0d\x0a\x1a\x0a\x00\x00\x00\x0d\x49\x48\x44\x52\x00\x00\x00\x08"
      "\x00\x00\x00\x06\x01\x00\x00\x00\x00\xd6\x7e\xe2\x56\x00\x00\x00\x14\x49\x44\x41"
      "\x54\x78\xda\x63\x68\x60\x70\x60\x50\x60\x10\x60\xe0\x60\x60\x01\x00\x09\x18\x00"
      "\xfd\x3b\xd9\x97\x13\x00\x00\x00\x00\x49\x45\x4e\x44\xae\x42\x60\x82",
      77);
  TempDir dir;
  std::uint32_t w = 0, h = 0;
  std::vector<std::uint8_t> read;
  loadMaskPng(dir.write("one_bit.png", png), w, h, read, 8, 6);
  EXPECT_EQ(read, mask({0, 9, 18, 27, 36, 45}, 255));
}

// --- frames folders ---

TEST(FramesFolderDetections, AppendsAndReadsBack)
{
  TempDir dir;
  const std::string folder = dir.file("frames");
  const CameraInfo camera = smallCamera();
  std::vector<Detection> with_mask = {detection("leaf_node", 0.9, 1, 1, 3, 3),
                                      detection("fruit", 0.6, 4, 2, 8, 6)};
  with_mask[1].mask = mask({30, 31, 38, 39});
  const std::vector<Detection> none;
  {
    FramesFolderWriter writer(folder, camera);
    writer.append(flatDepth(1.0f), Pose(), 1.5); // no detections
    writer.append(flatDepth(1.1f), Pose(), 2.5, &with_mask);
  }
  EXPECT_FALSE(fs::exists(folder + "/detections/000000.json"));
  EXPECT_TRUE(fs::is_regular_file(folder + "/detections/000001.json"));
  EXPECT_TRUE(fs::is_regular_file(folder + "/detections/000001_1.png"));
  {
    FramesFolderWriter writer(folder, camera); // continues the folder
    writer.append(flatDepth(1.2f), Pose(), 3.5, &none);
  }
  const std::string list = readBytes(folder + "/detections.txt");
  EXPECT_NE(list.find("\n2.500000 detections/000001.json\n"), std::string::npos) << list;
  EXPECT_NE(list.find("\n3.500000 detections/000002.json\n"), std::string::npos) << list;

  const FramesFolder frames(folder);
  ASSERT_EQ(frames.frames().size(), 3u);
  EXPECT_EQ(frames.frames()[0].detections_path, "");
  EXPECT_EQ(frames.frames()[1].detections_path,
            (fs::path(folder) / "detections/000001.json").string());
  EXPECT_EQ(frames.frames()[2].detections_path,
            (fs::path(folder) / "detections/000002.json").string());
  std::vector<Detection> read = with_mask; // replaced, not appended to
  frames.loadDetections(0, read);
  EXPECT_TRUE(read.empty());
  frames.loadDetections(1, read);
  expectSame(read, with_mask);
  frames.loadDetections(2, read);
  EXPECT_TRUE(read.empty());
  EXPECT_THROW(frames.loadDetections(3, read), std::out_of_range);
  // Frames and their detections meet the depth images: the same numbers.
  DepthImage depth;
  frames.loadDepth(1, depth);
  EXPECT_EQ(depth.depth_m[0], 1.1f);
}

TEST(FramesFolderDetections, AFolderWithoutDetectionsStillWorks)
{
  TempDir dir;
  const std::string folder = dir.file("frames");
  {
    FramesFolderWriter writer(folder, smallCamera());
    writer.append(flatDepth(1.0f), Pose(), 1.0);
  }
  EXPECT_FALSE(fs::exists(folder + "/detections.txt"));
  EXPECT_FALSE(fs::exists(folder + "/detections"));
  const FramesFolder frames(folder);
  ASSERT_EQ(frames.frames().size(), 1u);
  EXPECT_EQ(frames.frames()[0].detections_path, "");
  std::vector<Detection> read(2);
  frames.loadDetections(0, read);
  EXPECT_TRUE(read.empty());
}

TEST(FramesFolderDetections, MatchesStampsWithinAMicrosecond)
{
  TempDir dir;
  writeFolder(dir, {"1305031102.160407", "1305031102.194330", "1305031102.226738"});
  dir.write("detections.txt", "# timestamp filename\n"
                              "1305031102.226738 detections/c.json\n"
                              "1305031102.1604075 detections/a.json\n");
  const FramesFolder frames(dir.file(""));
  ASSERT_EQ(frames.frames().size(), 3u);
  EXPECT_EQ(frames.frames()[0].detections_path, dir.file("detections/a.json"));
  EXPECT_EQ(frames.frames()[1].detections_path, "");
  EXPECT_EQ(frames.frames()[2].detections_path, dir.file("detections/c.json"));
  // Read when asked for: a missing file is an error then.
  std::vector<Detection> read;
  EXPECT_THROW(frames.loadDetections(0, read), FileNotFoundError);
  frames.loadDetections(1, read);
  EXPECT_TRUE(read.empty());
}

TEST(FramesFolderDetections, ALineWithoutItsFrameOrASecondOneIsAnError)
{
  TempDir dir;
  writeFolder(dir, {"1.0", "2.0"});
  const std::string list = dir.file("detections.txt");
  const std::string depth = dir.file("depth.txt");
  dir.write("detections.txt", "1.0 detections/a.json\n2.000002 detections/b.json\n");
  EXPECT_EQ(
      thrownMessage<FormatError>([&] { FramesFolder(dir.file("")); }),
      "'" + list + "' line 2: 'detections/b.json' (2.000002 s) matches no frame of '" +
          depth + "' (a detection file takes the frame of its stamp, within 1e-6 s)");
  dir.write("detections.txt", "2.0 detections/b.json\n# again\n2.0 detections/b2.json\n");
  EXPECT_EQ(thrownMessage<FormatError>([&] { FramesFolder(dir.file("")); }),
            "'" + list +
                "' line 3: 'detections/b2.json' is a second detection file for "
                "frame 'depth/b.png' (2.000000 s, line 2 of '" +
                depth + "'; line 1 lists 'detections/b.json')");
  dir.write("detections.txt", "1.0 /tmp/a.json\n");
  EXPECT_EQ(thrownMessage<FormatError>([&] { FramesFolder(dir.file("")); }),
            "'" + list +
                "' line 1: '/tmp/a.json' must be a path inside the folder "
                "(relative, no '..')");
  // A frame skipped for want of a pose takes its detections with it.
  dir.write("groundtruth.txt", "1.0 1 2 3 0 0 0 1\n");
  dir.write("detections.txt", "1.0 detections/a.json\n2.0 detections/b.json\n");
  FramesFolderOptions options;
  options.skip_unmatched = true;
  const FramesFolder frames(dir.file(""), options);
  ASSERT_EQ(frames.frames().size(), 1u);
  EXPECT_EQ(frames.frames()[0].detections_path, dir.file("detections/a.json"));
}

TEST(FramesFolderDetections, WriterNeverOverwritesAndLeavesTheFolderOnBadDetections)
{
  TempDir dir;
  const std::string folder = dir.file("frames");
  const CameraInfo camera = smallCamera();
  FramesFolderWriter writer(folder, camera);
  writer.append(flatDepth(1.0f), Pose(), 1.0);

  // Bad detections: nothing of the frame is left.
  const std::vector<Detection> bad = {detection("a", 2.0, 0, 0, 1, 1)};
  EXPECT_EQ(thrownMessage<InvalidArgumentError>(
                [&] { writer.append(flatDepth(1.0f), Pose(), 2.0, &bad); }),
            "'" + (fs::path(folder) / "detections/000001.json").string() +
                "' detections[0].score: 2 is not in [0, 1]");
  EXPECT_FALSE(fs::exists(folder + "/depth/000001.png"));
  EXPECT_FALSE(fs::exists(folder + "/detections/000001.json"));
  EXPECT_FALSE(fs::exists(folder + "/detections.txt"));
  EXPECT_EQ(writer.frameCount(), 1u);

  // What an interrupted append leaves: an unlisted mask.
  std::vector<Detection> good = {detection("a", 0.5, 0, 0, 1, 1)};
  good[0].mask = mask({0});
  fs::create_directories(folder + "/detections");
  const std::string stray = (fs::path(folder) / "detections/000001_0.png").string();
  std::ofstream(stray) << "interrupted";
  EXPECT_EQ(
      thrownMessage<IoError>([&] { writer.append(flatDepth(1.0f), Pose(), 2.0, &good); }),
      "'" + stray +
          "' exists but detections.txt does not list it: refusing to overwrite it");
  EXPECT_EQ(readBytes(stray), "interrupted");
  EXPECT_FALSE(fs::exists(folder + "/depth/000001.png"));
  fs::remove(stray);
  writer.append(flatDepth(1.0f), Pose(), 2.0, &good);
  const FramesFolder frames(folder);
  ASSERT_EQ(frames.frames().size(), 2u);
  std::vector<Detection> read;
  frames.loadDetections(1, read);
  expectSame(read, good);
}
