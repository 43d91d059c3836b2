#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/plant/anatomy_json.h>
#include <plantnbv/plant/tomato_plant_generator.h>

using namespace plantnbv;

TEST(AnatomyJson, RoundTripIsExact)
{
  Plant plant = TomatoPlantGenerator(defaultPlantConfig(7)).generate();
  posePlant(plant, Eigen::Vector3d(1.0, 0.0, 0.8), 0.3);
  Plant back;
  anatomyFromJson(anatomyToJson(plant), back);
  EXPECT_EQ(back.name, plant.name);
  EXPECT_EQ(back.base_position, plant.base_position);
  EXPECT_EQ(back.yaw_rad, plant.yaw_rad);
  const PlantAnatomy &a = plant.anatomy, &b = back.anatomy;
  EXPECT_EQ(b.stem_axis, a.stem_axis);
  EXPECT_EQ(b.stem_radius_m, a.stem_radius_m);
  EXPECT_EQ(b.top_height_m, a.top_height_m);
  ASSERT_EQ(b.leaves.size(), a.leaves.size());
  ASSERT_FALSE(a.trusses.empty());
  for (std::size_t i = 0; i < a.leaves.size(); ++i) {
    EXPECT_EQ(b.leaves[i].node.position, a.leaves[i].node.position);
    EXPECT_EQ(b.leaves[i].node.petiole_direction, a.leaves[i].node.petiole_direction);
    EXPECT_EQ(b.leaves[i].axis, a.leaves[i].axis);
    ASSERT_EQ(b.leaves[i].leaflets.size(), a.leaves[i].leaflets.size());
    EXPECT_EQ(b.leaves[i].leaflets.back().tip, a.leaves[i].leaflets.back().tip);
    EXPECT_EQ(b.leaves[i].leaflets.back().terminal, a.leaves[i].leaflets.back().terminal);
  }
  ASSERT_EQ(b.trusses.size(), a.trusses.size());
  EXPECT_EQ(b.trusses[0].fruits.back().center, a.trusses[0].fruits.back().center);
  EXPECT_EQ(b.trusses[0].fruits.back().radius_m, a.trusses[0].fruits.back().radius_m);
}

TEST(AnatomyJson, ErrorsNameTheJsonPath)
{
  Plant plant = TomatoPlantGenerator(defaultPlantConfig(0)).generate();
  const std::string good = anatomyToJson(plant);
  auto message = [](const std::string& text) {
    Plant p;
    try {
      anatomyFromJson(text, p);
    } catch (const FormatError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("{ not json").find("not JSON"), std::string::npos);
  EXPECT_NE(message("[1, 2]").find("missing key 'format'"), std::string::npos);
  EXPECT_NE(message(R"({"format": "other", "version": 1})").find("format"),
            std::string::npos);
  std::string bad = good;
  bad.replace(bad.find("\"leaf_index\": 0"), 15, "\"leaf_index\": \"x\"");
  EXPECT_NE(message(bad).find("leaves[0].node.leaf_index: expected an integer"),
            std::string::npos)
      << message(bad);
  // Out of int's range: refused, not wrapped around.
  for (const char* index : {"4294967296", "-2147483649", "18446744073709551615"}) {
    bad = good;
    bad.replace(bad.find("\"leaf_index\": 0"), 15,
                std::string("\"leaf_index\": ") + index);
    EXPECT_NE(message(bad).find("leaves[0].node.leaf_index: expected an integer in the "
                                "int range"),
              std::string::npos)
        << message(bad);
  }
  // A number beyond double is a JSON error too (nlohmann throws out_of_range for it,
  // not parse_error; found by fuzzing).
  EXPECT_NE(message(R"({"format": 1e400})").find("not JSON"), std::string::npos);
  bad = good;
  const auto at = bad.find("\"radius_m\"", bad.find("\"fruits\""));
  bad.replace(at, 10, "\"radius\"");
  EXPECT_NE(message(bad).find("trusses[0].fruits[0]: missing key 'radius_m'"),
            std::string::npos)
      << message(bad);
}
