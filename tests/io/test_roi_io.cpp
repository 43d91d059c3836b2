#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/io/roi_io.h>

#include "io_test_util.h"

using plantnbv::Box;
using plantnbv::FormatError;
using plantnbv::IoError;
using plantnbv::Roi;
using plantnbv::io::loadRoi;
using plantnbv::io::saveRoi;
using plantnbv::test::fixture;
using plantnbv::test::TempDir;
using plantnbv::test::thrownMessage;

namespace {

/// The message loadRoi gives for a file with this content.
std::string roiError(const TempDir& dir, const std::string& content)
{
  const std::string path = dir.write("rois.yaml", content);
  return thrownMessage<FormatError>([&] { loadRoi(path); });
}

} // namespace

TEST(RoiIo, LoadsTheFixture)
{
  const Roi roi = loadRoi(fixture("rois.yaml"));
  ASSERT_EQ(roi.size(), 3u);
  EXPECT_EQ(roi.boxes()[0].name, "main_stem");
  EXPECT_EQ(roi.boxes()[0].center, Eigen::Vector3d(1.0, 0.0, 1.15));
  EXPECT_EQ(roi.boxes()[0].size, Eigen::Vector3d(0.05, 0.05, 0.7));
  EXPECT_EQ(roi.boxes()[1].name, "leaf_node_1");
  EXPECT_EQ(roi.boxes()[2].name, "");
  EXPECT_EQ(roi.boxes()[2].center, Eigen::Vector3d(1.01, -0.02, 1.25));
}

TEST(RoiIo, SaveLoadRoundTripIsExact)
{
  TempDir dir;
  Roi roi;
  roi.addBox(Box({0.1 + 0.2, 1.0 / 3.0, -1e-17}, {0.05, 2.0 / 3.0, 1e300}, "main_stem"));
  roi.addBox(Box({1, 2, 3}, {5e-324, 1e-300, 7}, "odd: name # with \"quotes\" and \\"));
  roi.addBox(Box({-0.0, 5e-324, 123456789.123456789}, {1, 1, 1}));
  roi.addBox(Box({0, 0, 0}, {1, 1, 1}, "null"));
  roi.addBox(Box({0, 0, 0}, {1, 1, 1}, "tab\tand\nnewline"));
  const std::string path = dir.file("roi.yaml");
  saveRoi(path, roi);
  const Roi back = loadRoi(path);
  ASSERT_EQ(back.size(), roi.size());
  for (std::size_t i = 0; i < roi.size(); ++i) {
    EXPECT_EQ(back.boxes()[i].name, roi.boxes()[i].name) << i;
    EXPECT_EQ(back.boxes()[i].center, roi.boxes()[i].center) << i;
    EXPECT_EQ(back.boxes()[i].size, roi.boxes()[i].size) << i;
  }
  // Short numbers stay short (shortest exact form, not 17 digits everywhere).
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("[0.30000000000000004, 0.3333333333333333, -1e-17]"),
            std::string::npos)
      << text.str();
  EXPECT_NE(text.str().find("name: main_stem\n"), std::string::npos) << text.str();
}

TEST(RoiIo, SaveErrors)
{
  TempDir dir;
  EXPECT_THROW(saveRoi(dir.file("empty.yaml"), Roi()), plantnbv::InvalidArgumentError);
  Roi roi;
  roi.addBox(Box({0, 0, 0}, {1, 1, 1}));
  EXPECT_THROW(saveRoi(dir.file("no/dir/roi.yaml"), roi), IoError);
}

TEST(RoiIo, NegativeSizeNamesTheBoxAndKey)
{
  TempDir dir;
  const std::string msg = roiError(dir, "boxes:\n"
                                        "  - center: [0, 0, 0]\n"
                                        "    size: [1, 1, 1]\n"
                                        "  - center: [0, 0, 0]\n"
                                        "    size: [1, 1, 1]\n"
                                        "  - center: [0, 0, 0]\n"
                                        "    size: [0.1, -0.2, 0.3]\n");
  EXPECT_EQ(msg,
            "'" + dir.file("rois.yaml") +
                "' boxes[2].size: expected 3 non-negative numbers, got [0.1, -0.2, 0.3]");
}

TEST(RoiIo, MissingKey)
{
  TempDir dir;
  const std::string msg = roiError(dir, "boxes:\n  - name: a\n    center: [0, 0, 0]\n");
  EXPECT_NE(msg.find("boxes[0]: missing key 'size'"), std::string::npos) << msg;
}

TEST(RoiIo, WrongVectorLengthAndNonNumbers)
{
  TempDir dir;
  std::string msg = roiError(dir, "boxes:\n  - center: [0, 0]\n    size: [1, 1, 1]\n");
  EXPECT_NE(msg.find("boxes[0].center: expected 3 numbers, got [0, 0]"),
            std::string::npos)
      << msg;
  msg = roiError(dir, "boxes:\n  - center: [0, x, 0]\n    size: [1, 1, 1]\n");
  EXPECT_NE(msg.find("center: expected 3 numbers, got [0, x, 0]"), std::string::npos)
      << msg;
  msg = roiError(dir, "boxes:\n  - center: 5\n    size: [1, 1, 1]\n");
  EXPECT_NE(msg.find("center: expected 3 numbers, got 5"), std::string::npos) << msg;
  msg = roiError(dir, "boxes:\n  - center: [0, 0, .nan]\n    size: [1, 1, 1]\n");
  EXPECT_NE(msg.find("center: expected 3 numbers"), std::string::npos) << msg;
  msg = roiError(dir,
                 "boxes:\n  - name: [a]\n    center: [0, 0, 0]\n    size: [1, 1, 1]\n");
  EXPECT_NE(msg.find("boxes[0].name: expected a name, got [a]"), std::string::npos)
      << msg;
}

TEST(RoiIo, UnknownKeysAreRejected)
{
  TempDir dir;
  std::string msg = roiError(
      dir, "boxes:\n  - center: [0, 0, 0]\n    size: [1, 1, 1]\n    colour: red\n");
  EXPECT_NE(msg.find("boxes[0].colour: unknown key (expected one of center, name, size)"),
            std::string::npos)
      << msg;
  msg =
      roiError(dir, "boxes:\n  - center: [0, 0, 0]\n    size: [1, 1, 1]\nframe: world\n");
  EXPECT_NE(msg.find("frame: unknown key (expected one of boxes)"), std::string::npos)
      << msg;
}

TEST(RoiIo, NotYamlAndNoBoxes)
{
  TempDir dir;
  std::string msg = roiError(dir, "boxes: [ {center: [0, 0, 0]\n");
  EXPECT_NE(msg.find("not valid YAML"), std::string::npos) << msg;
  msg = roiError(dir, "");
  EXPECT_NE(msg.find("no boxes"), std::string::npos) << msg;
  msg = roiError(dir, "boxes: []\n");
  EXPECT_NE(msg.find("no boxes"), std::string::npos) << msg;
  msg = roiError(dir, "boxes:\n");
  EXPECT_NE(msg.find("no boxes"), std::string::npos) << msg;
  msg = roiError(dir, "{}\n");
  EXPECT_NE(msg.find("no boxes"), std::string::npos) << msg;
  msg = roiError(dir, "boxes: {center: [0, 0, 0]}\n");
  EXPECT_NE(msg.find("boxes: expected a list of boxes"), std::string::npos) << msg;
  msg = roiError(dir, "- just a list\n");
  EXPECT_NE(msg.find("expected a map"), std::string::npos) << msg;
  msg = roiError(dir, "boxes:\n  - 3\n");
  EXPECT_NE(msg.find("boxes[0]: expected a map"), std::string::npos) << msg;
}

TEST(RoiIo, MissingFileIsAnIoError)
{
  TempDir dir;
  const std::string path = dir.file("absent.yaml");
  const std::string msg = thrownMessage<IoError>([&] { loadRoi(path); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
}

TEST(RoiIo, SizesThatAreNotPositiveAreRefusedNamingTheBox)
{
  // A box without volume scored F1 = 1 from one point: every side must be > 0.
  TempDir dir;
  for (int axis = 0; axis < 3; ++axis)
    for (const std::string v : {"0", "0.0", "-0", "0e5"}) {
      std::string sizes[3] = {"0.1", "0.2", "0.3"};
      sizes[axis] = v;
      const std::string msg =
          roiError(dir, "boxes:\n  - center: [0, 0, 0]\n    size: [1, 1, 1]\n"
                        "  - center: [1, 2, 3]\n    size: [" +
                            sizes[0] + ", " + sizes[1] + ", " + sizes[2] + "]\n");
      EXPECT_NE(msg.find("'" + dir.file("rois.yaml") +
                         "' boxes[1].size: expected 3 "
                         "sizes > 0 (metres)"),
                std::string::npos)
          << msg;
    }
}

TEST(RoiIo, LoadsTheRoiViewpointPlannerListOfCorners)
{
  // roi_viewpoint_planner's form: the document is the list, each box min and max.
  TempDir dir;
  const Roi roi = loadRoi(dir.write("rois.yaml", "- {min: [0.5, -0.25, 1.0], max: [1.5, "
                                                 "0.25, 2.0]}\n"
                                                 "- name: leaf\n"
                                                 "  min: [-2, 0.125, -1]\n"
                                                 "  max: [-1, 0.375, 3]\n"));
  ASSERT_EQ(roi.size(), 2u);
  EXPECT_EQ(roi.boxes()[0].name, "");
  EXPECT_EQ(roi.boxes()[0].center, Eigen::Vector3d(1.0, 0.0, 1.5));
  EXPECT_EQ(roi.boxes()[0].size, Eigen::Vector3d(1.0, 0.5, 1.0));
  EXPECT_EQ(roi.boxes()[0].min(), Eigen::Vector3d(0.5, -0.25, 1.0));
  EXPECT_EQ(roi.boxes()[0].max(), Eigen::Vector3d(1.5, 0.25, 2.0));
  EXPECT_EQ(roi.boxes()[1].name, "leaf");
  EXPECT_EQ(roi.boxes()[1].center, Eigen::Vector3d(-1.5, 0.25, 1.0));
  EXPECT_EQ(roi.boxes()[1].size, Eigen::Vector3d(1.0, 0.25, 4.0));
}

TEST(RoiIo, BoxesMayGiveCornersUnderTheBoxesKey)
{
  TempDir dir;
  const Roi roi = loadRoi(dir.write("rois.yaml", "boxes:\n"
                                                 "  - name: a\n"
                                                 "    min: [0.5, -0.25, 1.0]\n"
                                                 "    max: [1.5, 0.25, 2.0]\n"
                                                 "  - center: [1, 2, 3]\n"
                                                 "    size: [0.5, 0.5, 0.5]\n"));
  ASSERT_EQ(roi.size(), 2u);
  EXPECT_EQ(roi.boxes()[0].name, "a");
  EXPECT_EQ(roi.boxes()[0].center, Eigen::Vector3d(1.0, 0.0, 1.5));
  EXPECT_EQ(roi.boxes()[0].size, Eigen::Vector3d(1.0, 0.5, 1.0));
  EXPECT_EQ(roi.boxes()[1].center, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(roi.boxes()[1].size, Eigen::Vector3d(0.5, 0.5, 0.5));
  // A list file may give centres and sizes too.
  const Roi list =
      loadRoi(dir.write("list.yaml", "- {center: [1, 2, 3], size: [1, 1, 1]}\n"));
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list.boxes()[0].center, Eigen::Vector3d(1, 2, 3));
}

TEST(RoiIo, ABoxMixingCentreAndCornersIsRefused)
{
  TempDir dir;
  const std::string file = "'" + dir.file("rois.yaml") + "' ";
  EXPECT_EQ(roiError(dir, "- {min: [0, 0, 0], max: [1, 1, 1]}\n"
                          "- {center: [0, 0, 0], max: [1, 1, 1]}\n"),
            file + "[1]: give center and size, or min and max, not both");
  EXPECT_EQ(roiError(dir, "boxes:\n  - {min: [0, 0, 0], size: [1, 1, 1]}\n"),
            file + "boxes[0]: give center and size, or min and max, not both");
}

TEST(RoiIo, MinMustBeBelowMaxOnEveryAxis)
{
  TempDir dir;
  const std::string file = "'" + dir.file("rois.yaml") + "' ";
  EXPECT_EQ(
      roiError(dir, "- {min: [0, 0, 0], max: [1, 1, 1]}\n"
                    "- {min: [0, 2, 0], max: [1, 1, 1]}\n"),
      file + "[1]: expected min < max on every axis, got min [0, 2, 0], max [1, 1, 1]");
  EXPECT_EQ(roiError(dir, "boxes:\n  - {min: [0, 0, 0.5], max: [1, 1, 0.5]}\n"),
            file + "boxes[0]: expected min < max on every axis, got min [0, 0, 0.5], "
                   "max [1, 1, 0.5]");
}

TEST(RoiIo, CornerMistakesNameTheBoxAndKey)
{
  TempDir dir;
  const std::string file = "'" + dir.file("rois.yaml") + "' ";
  EXPECT_EQ(roiError(dir, "- name: a\n  min: [0, 0, 0]\n"),
            file + "[0]: missing key 'max'");
  EXPECT_EQ(roiError(dir, "- max: [0, 0, 0]\n"), file + "[0]: missing key 'min'");
  EXPECT_EQ(roiError(dir, "- {min: [0, 0, .nan], max: [1, 1, 1]}\n"),
            file + "[0].min: expected 3 numbers, got [0, 0, .nan]");
  EXPECT_EQ(roiError(dir, "- {min: [0, 0, 0], max: [1, .inf, 1]}\n"),
            file + "[0].max: expected 3 numbers, got [1, .inf, 1]");
  EXPECT_EQ(roiError(dir, "- {min: [0, 0, 0], max: [1, 1]}\n"),
            file + "[0].max: expected 3 numbers, got [1, 1]");
  EXPECT_EQ(roiError(dir, "- {min: [0, 0, 0], max: [1, 1, 1], frame: world}\n"),
            file + "[0].frame: unknown key (expected one of max, min, name)");
  EXPECT_EQ(roiError(dir, "- {min: [-1e308, 0, 0], max: [1e308, 1, 1]}\n"),
            file + "[0]: max - min overflows: min [-1e308, 0, 0], max [1e308, 1, 1]");
  // Corners near the largest double: the centre is still found.
  const Roi far =
      loadRoi(dir.write("far.yaml", "- {min: [1e308, 0, 0], max: [1.5e308, 1, 1]}\n"));
  EXPECT_EQ(far.boxes()[0].center.x(), 0.5 * 1e308 + 0.5 * 1.5e308);
}

TEST(RoiIo, AnEmptyListHasNoBoxes)
{
  TempDir dir;
  EXPECT_EQ(roiError(dir, "[]\n"),
            "'" + dir.file("rois.yaml") + "' (top level): no boxes (the list is empty)");
}
