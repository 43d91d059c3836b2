#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/common/error.h>

using plantnbv::CameraIntrinsics;
using plantnbv::InvalidArgumentError;
using plantnbv::L515Mode;
using plantnbv::parseCameraIntrinsics;

namespace {

constexpr double kDeg = M_PI / 180.0;

/// The message of the InvalidArgumentError that parsing `spec` throws ("" if none).
std::string parseError(const std::string& spec)
{
  try {
    parseCameraIntrinsics(spec);
  } catch (const InvalidArgumentError& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST(CameraIntrinsics, L515PresetsHaveTheDatasheetFieldOfView)
{
  for (L515Mode mode :
       {L515Mode::xga_1024x768, L515Mode::vga_640x480, L515Mode::qvga_320x240}) {
    const CameraIntrinsics c = CameraIntrinsics::l515(mode);
    EXPECT_NO_THROW(c.validate());
    EXPECT_NEAR(c.horizontalFov(), 70.0 * kDeg, 1e-12);
    // 55 deg +- 2 deg in the datasheet; square pixels give 55.4 deg.
    EXPECT_NEAR(c.verticalFov(), 55.0 * kDeg, 0.5 * kDeg);
    EXPECT_DOUBLE_EQ(c.fx, c.fy);
    EXPECT_DOUBLE_EQ(c.cx, 0.5 * (c.width - 1));
    EXPECT_DOUBLE_EQ(c.cy, 0.5 * (c.height - 1));
    EXPECT_DOUBLE_EQ(c.min_range_m, 0.25);
    EXPECT_DOUBLE_EQ(c.max_range_m, 9.0);
  }
  const CameraIntrinsics xga = CameraIntrinsics::l515(L515Mode::xga_1024x768);
  EXPECT_EQ(xga.width, 1024u);
  EXPECT_EQ(xga.height, 768u);
  EXPECT_NEAR(xga.fx, 731.2, 0.05);
  const CameraIntrinsics vga = CameraIntrinsics::l515(L515Mode::vga_640x480);
  EXPECT_EQ(vga.width, 640u);
  EXPECT_EQ(vga.height, 480u);
  EXPECT_NEAR(vga.fx, 457.0, 0.05);
}

TEST(CameraIntrinsics, ParsesPresetsAndCustomCameras)
{
  EXPECT_EQ(parseCameraIntrinsics("l515").width, 1024u);
  EXPECT_EQ(parseCameraIntrinsics("L515-1024").height, 768u);
  EXPECT_EQ(parseCameraIntrinsics("l515-640").width, 640u);
  EXPECT_EQ(parseCameraIntrinsics("l515-320").height, 240u);

  const CameraIntrinsics c = parseCameraIntrinsics("640x480:457,458.5,319.5,239.25");
  EXPECT_EQ(c.width, 640u);
  EXPECT_EQ(c.height, 480u);
  EXPECT_DOUBLE_EQ(c.fx, 457.0);
  EXPECT_DOUBLE_EQ(c.fy, 458.5);
  EXPECT_DOUBLE_EQ(c.cx, 319.5);
  EXPECT_DOUBLE_EQ(c.cy, 239.25);
  EXPECT_DOUBLE_EQ(c.min_range_m, 0.25);
  EXPECT_DOUBLE_EQ(c.max_range_m, 9.0);
}

TEST(CameraIntrinsics, ParseErrorsNameTheBadValue)
{
  EXPECT_NE(parseError("l516").find("'l516'"), std::string::npos);
  EXPECT_NE(parseError("l516").find("expected l515"), std::string::npos);
  EXPECT_NE(parseError("").find("unknown camera"), std::string::npos);
  EXPECT_NE(parseError("640x480").find("unknown camera"), std::string::npos);
  EXPECT_NE(parseError("640x480:457,457,319.5").find("3 values"), std::string::npos);
  EXPECT_NE(parseError("640x480:457,457,319.5,239.5,1").find("5 values"),
            std::string::npos);
  EXPECT_NE(parseError("640x480:abc,457,319.5,239.5").find("'abc' is not a number"),
            std::string::npos);
  EXPECT_NE(parseError("640x480:457,,319.5,239.5").find("'' is not a number"),
            std::string::npos);
  EXPECT_NE(parseError("-640x480:457,457,319.5,239.5").find("'-640'"), std::string::npos);
  EXPECT_NE(parseError("0x480:457,457,319.5,239.5").find("width 0"), std::string::npos);
  EXPECT_NE(parseError("640x99999:457,457,319.5,239.5").find("height 99999"),
            std::string::npos);
  EXPECT_NE(parseError("640x480:-457,457,319.5,239.5").find("fx = -457"),
            std::string::npos);
  EXPECT_NE(parseError("640x480:457,0,319.5,239.5").find("fy = 0"), std::string::npos);
  EXPECT_NE(parseError("640x480:457,457,nan,239.5").find("cx = nan"), std::string::npos);
  EXPECT_NE(parseError("640x480:457,457,319.5,inf").find("cy = inf"), std::string::npos);
}

TEST(CameraIntrinsics, ValidateChecksTheRangeLimits)
{
  CameraIntrinsics c = CameraIntrinsics::l515(L515Mode::vga_640x480);
  c.min_range_m = -0.1;
  EXPECT_THROW(c.validate(), InvalidArgumentError);
  c.min_range_m = 1.0;
  c.max_range_m = 1.0;
  try {
    c.validate();
    FAIL() << "max_range_m = min_range_m was accepted";
  } catch (const InvalidArgumentError& e) {
    EXPECT_NE(std::string(e.what()).find("max_range_m = 1"), std::string::npos);
  }
  c.max_range_m = INFINITY;
  EXPECT_THROW(c.validate(), InvalidArgumentError);
  c.max_range_m = 2.0;
  EXPECT_NO_THROW(c.validate());
  EXPECT_NE(c.toString().find("640x480"), std::string::npos);
}
