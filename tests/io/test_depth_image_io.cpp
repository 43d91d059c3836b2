#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/io/depth_image_io.h>

#include "io_test_util.h"

using plantnbv::FormatError;
using plantnbv::InvalidArgumentError;
using plantnbv::IoError;
using plantnbv::io::loadDepthPng;
using plantnbv::io::saveDepthPng;
using plantnbv::test::TempDir;

namespace {
const float kNaN = std::numeric_limits<float>::quiet_NaN();
}

TEST(DepthImageIo, RoundTripInMillimetres)
{
  TempDir dir;
  // 3 x 2: ordinary depths (rounded to 1 mm), no return, too near, too far for 16 bits.
  const std::vector<float> depth{0.5f, 1.2344f, kNaN, 0.0004f, 70.0f, 65.535f};
  const std::string path = dir.file("depth.png");
  saveDepthPng(path, 3, 2, depth);
  std::uint32_t w = 0, h = 0;
  std::vector<float> back;
  loadDepthPng(path, w, h, back);
  ASSERT_EQ(w, 3u);
  ASSERT_EQ(h, 2u);
  ASSERT_EQ(back.size(), 6u);
  EXPECT_FLOAT_EQ(back[0], 0.5f);
  EXPECT_FLOAT_EQ(back[1], 1.234f);
  EXPECT_TRUE(std::isnan(back[2]));
  EXPECT_TRUE(std::isnan(back[3])); // rounds to 0 mm: "no return"
  EXPECT_TRUE(std::isnan(back[4])); // beyond 65535 mm
  EXPECT_FLOAT_EQ(back[5], 65.535f);
  // Sub-millimetre units: 0.25 mm, the L515's own depth unit.
  saveDepthPng(path, 3, 2, depth, 4000.0);
  loadDepthPng(path, w, h, back, 4000.0);
  EXPECT_FLOAT_EQ(back[1], 1.2345f);
}

TEST(DepthImageIo, Errors)
{
  TempDir dir;
  const std::vector<float> depth(6, 1.0f);
  EXPECT_THROW(saveDepthPng(dir.file("a.png"), 4, 2, depth), InvalidArgumentError);
  EXPECT_THROW(saveDepthPng(dir.file("a.png"), 0, 0, {}), InvalidArgumentError);
  EXPECT_THROW(saveDepthPng(dir.file("a.png"), 3, 2, depth, 0.0), InvalidArgumentError);
  EXPECT_THROW(saveDepthPng(dir.file("no/dir/a.png"), 3, 2, depth), IoError);
  std::uint32_t w, h;
  std::vector<float> back;
  EXPECT_THROW(loadDepthPng(dir.file("missing.png"), w, h, back), IoError);
  EXPECT_THROW(loadDepthPng(dir.write("text.png", "not a png"), w, h, back), FormatError);
}
