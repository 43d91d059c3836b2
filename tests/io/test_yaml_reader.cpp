#include <functional>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <plantnbv/common/error.h>
#include <plantnbv/io/yaml_reader.h>

using plantnbv::FormatError;
using plantnbv::io::YamlReader;

namespace {

std::string failure(const std::function<void()>& f)
{
  try {
    f();
  } catch (const FormatError& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST(YamlReader, ReadsTypedValuesWithKeyPaths)
{
  const YamlReader r("c.yaml");
  const YAML::Node root = r.parse("a: {b: [1, 2.5, 3]}\nn: 4\nflag: true\n");
  int n = 0;
  bool flag = false;
  std::vector<double> numbers;
  std::vector<std::string> paths;
  r.forEach(root, "",
            {{"a",
              [&](const YAML::Node& v, const std::string& k) {
                r.forEach(v, k, {{"b", [&](const YAML::Node& w, const std::string& j) {
                                    paths.push_back(j);
                                    numbers = r.readNumbers(w, j, 3);
                                  }}});
              }},
             {"n", [&](const YAML::Node& v,
                       const std::string& k) { n = r.read<int>(v, k, "n"); }},
             {"flag", [&](const YAML::Node& v, const std::string& k) {
                flag = r.read<bool>(v, k, "a flag");
              }}});
  EXPECT_EQ(n, 4);
  EXPECT_TRUE(flag);
  EXPECT_EQ(numbers, (std::vector<double>{1.0, 2.5, 3.0}));
  EXPECT_EQ(paths, (std::vector<std::string>{"a.b"}));
  EXPECT_EQ(r.readList<int>(r.parse("[1, 2]"), "x", "integers"),
            (std::vector<int>{1, 2}));
}

TEST(YamlReader, EveryMistakeNamesTheFileAndThePath)
{
  const YamlReader r("c.yaml");
  const auto none = [](const YAML::Node&, const std::string&) {};
  EXPECT_EQ(failure([&] { r.parse("a: [1,"); }).rfind("'c.yaml' is not valid YAML: ", 0),
            0u);
  EXPECT_EQ(failure([&] {
              r.forEach(r.parse("b: 1"), "trial", {{"a", none}, {"c", none}});
            }),
            "'c.yaml' trial.b: unknown key (expected one of a, c)");
  EXPECT_EQ(failure([&] {
              r.forEach(r.parse("? [x]\n: 1"), "", {{"a", none}});
            }),
            "'c.yaml' (top level): a key must be a name, not [x]");
  EXPECT_EQ(failure([&] {
              r.forEach(r.parse("[1]"), "s", {{"a", none}});
            }),
            "'c.yaml' s: expected a map of keys, got [1]");
  EXPECT_EQ(failure([&] { r.read<int>(r.parse("ten"), "views", "an integer"); }),
            "'c.yaml' views: 'ten' is not an integer");
  EXPECT_EQ(failure([&] { r.read<int>(r.parse("{a: 1}"), "views", "an integer"); }),
            "'c.yaml' views: expected an integer, got {a: 1}");
  EXPECT_EQ(failure([&] { r.readList<int>(r.parse("[1, x]"), "p", "integers"); }),
            "'c.yaml' p[1]: 'x' is not integers");
  EXPECT_EQ(failure([&] { r.readNumbers(r.parse("[1, -2, 3]"), "size", 3, true); }),
            "'c.yaml' size: expected 3 non-negative numbers, got [1, -2, 3]");
  EXPECT_EQ(failure([&] { r.readNumbers(r.parse("[1, .inf, 3]"), "c", 3); }),
            "'c.yaml' c: expected 3 numbers, got [1, .inf, 3]");
  EXPECT_EQ(failure([&] { r.readNumbers(r.parse("[1, 2]"), "c", 3); }),
            "'c.yaml' c: expected 3 numbers, got [1, 2]");
}

TEST(YamlReader, ReadsFilesWithinTheInputLimits)
{
  EXPECT_THROW(YamlReader::readText("/nonexistent/c.yaml"), plantnbv::IoError);
  const std::string text =
      YamlReader::readText(std::string(PLANTNBV_DATA_DIR) + "/campaigns/quick.yaml");
  EXPECT_NE(text.find("name: quick"), std::string::npos);
}

TEST(YamlReader, AValueHoldingAnAliasOfItselfIsDescribedShortly)
{
  // An anchor whose value holds an alias of itself: a cycle, described as far as 4
  // levels and about 160 characters (it recursed without end before).
  const YAML::Node cycle = YAML::Load("a: &x [1, {b: *x}]")["a"];
  const std::string text = YamlReader::describe(cycle);
  EXPECT_EQ(text.rfind("[1, {b: [1, {b: ", 0), 0u) << text;
  EXPECT_NE(text.find("..."), std::string::npos) << text;
  EXPECT_LT(text.size(), 200u) << text;
  const YAML::Node long_list = YAML::Load("[" + std::string(2000, '7') + ", 1, 2]");
  EXPECT_LT(YamlReader::describe(long_list).size(), 200u);
  EXPECT_EQ(YamlReader::describe(YAML::Load("{k: [1, 2]}")), "{k: [1, 2]}");
}
