#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/sensor/noise_model.h>

using plantnbv::InvalidArgumentError;
using plantnbv::NoiseConfig;

namespace {
constexpr double kDeg = M_PI / 180.0;
}

TEST(NoiseConfig, DefaultsAreOffAndL515Like)
{
  const NoiseConfig c;
  EXPECT_FALSE(c.enabled);
  EXPECT_NO_THROW(c.validate());
  // The datasheet's 1-sigma depth noise: 2.5 mm at 1 m, 15.5 mm at 9 m.
  EXPECT_NEAR(c.axialSigma(1.0), 0.0025, 1e-12);
  EXPECT_NEAR(c.axialSigma(9.0), 0.0155, 1e-12);
  EXPECT_NE(c.toString().find("lateral_sigma_px: 0.2"), std::string::npos);
}

TEST(NoiseConfig, GrazingDropoutRisesLinearly)
{
  const NoiseConfig c; // 70 to 85 deg
  EXPECT_DOUBLE_EQ(c.grazingDropoutProbability(0.0), 0.0);
  EXPECT_DOUBLE_EQ(c.grazingDropoutProbability(69.9 * kDeg), 0.0);
  EXPECT_NEAR(c.grazingDropoutProbability(77.5 * kDeg), 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(c.grazingDropoutProbability(85.0 * kDeg), 1.0);
  EXPECT_DOUBLE_EQ(c.grazingDropoutProbability(90.0 * kDeg), 1.0);
}

TEST(NoiseConfig, ValidateNamesTheBadField)
{
  auto message = [](const NoiseConfig& c) -> std::string {
    try {
      c.validate();
    } catch (const InvalidArgumentError& e) {
      return e.what();
    }
    return "";
  };
  NoiseConfig c;
  c.axial_sigma_m = -1e-3;
  EXPECT_NE(message(c).find("axial_sigma_m = -0.001"), std::string::npos);
  c = NoiseConfig();
  c.lateral_sigma_px = NAN;
  EXPECT_NE(message(c).find("lateral_sigma_px"), std::string::npos);
  c = NoiseConfig();
  c.grazing_end_rad = 60.0 * kDeg; // below the start (70 deg)
  EXPECT_NE(message(c).find("grazing_end_rad"), std::string::npos);
  c = NoiseConfig();
  c.edge_dropout_probability = 1.5;
  EXPECT_NE(message(c).find("edge_dropout_probability = 1.5"), std::string::npos);
  c = NoiseConfig();
  c.edge_jump_m = 0.0;
  EXPECT_NE(message(c).find("edge_jump_m"), std::string::npos);
}
