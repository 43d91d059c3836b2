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

namespace {

/// The message of parse()'s FormatError for `text` ("" if it parses).
std::string parseError(const std::string& text)
{
  try {
    YamlReader("f.yaml").parse(text);
  } catch (const FormatError& e) {
    return e.what();
  }
  return "";
}

} // namespace

TEST(YamlReader, DocumentsThatWouldMakeReadersRecurseOrExplodeAreRefusedByLine)
{
  // Alias cycles, directly or through maps and lists, at any depth.
  for (const std::string cycle :
       {"a: &x [1, *x]\n", "a: &x {b: *x}\n", "k: 1\nl:\n  - &y [0, [1, [2, *y]]]\n",
        "&top {a: [*top]}\n", "a: &x {b: [{c: *x}]}\n"}) {
    const std::string e = parseError(cycle);
    EXPECT_NE(e.find("holds an alias of itself"), std::string::npos) << cycle << e;
    EXPECT_NE(e.find("f.yaml"), std::string::npos) << e;
  }
  // Nesting: the limit itself passes, one level more is refused, in flow and block
  // styles; yaml-cpp's own limit (2000) beyond that is a FormatError too.
  for (const bool flow : {true, false})
    for (const std::size_t depth : {plantnbv::io::kMaxYamlDepth,
                                    plantnbv::io::kMaxYamlDepth + 1, std::size_t(5000)}) {
      std::string text;
      if (flow)
        text = std::string(depth, '[') + "1" + std::string(depth, ']');
      else
        for (std::size_t d = 0; d < depth; ++d)
          text += std::string(2 * d, ' ') + "-\n";
      const std::string e = parseError(text);
      if (depth <= plantnbv::io::kMaxYamlDepth && flow)
        EXPECT_EQ(e, "") << depth;
      else if (depth <= plantnbv::io::kMaxYamlDepth)
        EXPECT_EQ(e.find("nested"), std::string::npos) << e;
      else
        EXPECT_FALSE(e.empty()) << depth << (flow ? " flow" : " block");
    }
  // Aliases that multiply: 10 lists of 10 aliases of the one before are 10^10 values.
  std::string laughs = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i < 10; ++i) {
    laughs += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [";
    for (int k = 0; k < 10; ++k)
      laughs += (k ? ", *a" : "*a") + std::to_string(i - 1);
    laughs += "]\n";
  }
  EXPECT_NE(parseError(laughs).find("aliases expand the document"), std::string::npos);
  // Sharing that stays small is fine.
  EXPECT_EQ(parseError("base: &b {x: 1}\nother: *b\nthird: [*b, *b]\n"), "");
}

TEST(YamlReader, AKeyRepeatedInOneMapIsRefusedWithBothLines)
{
  EXPECT_NE(parseError("seed: 1\nviews: 3\nseed: 2\n")
                .find("(line 3): key 'seed' appears twice (first on line 1)"),
            std::string::npos);
  EXPECT_NE(parseError("a:\n  b: 1\n  c: 2\n  b: 3\n").find("key 'b' appears twice"),
            std::string::npos);
  EXPECT_NE(parseError("l: [{k: 1, k: 1}]\n").find("key 'k'"), std::string::npos);
  // The same key in two maps is no repetition.
  EXPECT_EQ(parseError("a: {k: 1}\nb: {k: 1}\n"), "");
}

TEST(YamlReader, CanonicalTextIgnoresCommentsOrderQuotingAndStyle)
{
  const auto canonical = [](const std::string& text) {
    return YamlReader::canonical(YamlReader("f.yaml").parse(text));
  };
  const std::string a =
      canonical("name: x\nseed: 3\nlist: [1, 'two']\nmap: {p: 1, q: 2}\n");
  EXPECT_EQ(a, canonical("# a comment\nseed: 3 # why\nmap:\n  q: 2\n  p: 1\nname: \"x\"\n"
                         "list:\n  - 1\n  - two\n"));
  EXPECT_EQ(a, canonical("anchor: &s 3\nname: x\nseed: *s\nlist: [1, two]\n"
                         "map: {p: 1, q: 2}\n")
                   .replace(0, std::string("{\"anchor\":\"3\",").size(), "{"));
  EXPECT_NE(a, canonical("name: x\nseed: 4\nlist: [1, two]\nmap: {p: 1, q: 2}\n"));
  EXPECT_NE(a, canonical("name: x\nseed: 3\nlist: [two, 1]\nmap: {p: 1, q: 2}\n"));
  // No scalar can imitate the punctuation of another document's text.
  EXPECT_NE(canonical("a: 'b\",\"c'\n"), canonical("a: b\nc: ~\n"));
  EXPECT_NE(canonical("a: ~\n"), canonical("a: '~'\n"));
}

TEST(YamlReader, CrlfLineEndingsReadAsLf)
{
  // A trial config as a Windows editor saves it.
  const std::string lf = "# a trial\n"
                         "trial:\n"
                         "  map:\n"
                         "    resolution: 0.005\n"
                         "    frame: \"world\"\n"
                         "  views: [1, 2,\n"
                         "          3]\n"
                         "planners:\n"
                         "  - name: attention\n"
                         "    rois: [main_stem, leaf_nodes]\n"
                         "  - name: 'random'\n"
                         "note: |\n"
                         "  two\n"
                         "  lines\n"
                         "folded: >\n"
                         "  one\n"
                         "  line\n";
  std::string crlf;
  for (char c : lf)
    crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  const YamlReader r("c.yaml");
  const YAML::Node root = r.parse(crlf);
  EXPECT_EQ(YamlReader::canonical(root), YamlReader::canonical(r.parse(lf)));
  EXPECT_EQ(r.read<double>(root["trial"]["map"]["resolution"], "r", "a number"), 0.005);
  EXPECT_EQ(r.read<std::string>(root["trial"]["map"]["frame"], "f", "a name"), "world");
  EXPECT_EQ(r.readList<int>(root["trial"]["views"], "v", "integers"),
            (std::vector<int>{1, 2, 3}));
  ASSERT_TRUE(root["planners"].IsSequence());
  ASSERT_EQ(root["planners"].size(), 2u);
  EXPECT_EQ(r.read<std::string>(root["planners"][0]["name"], "n", "a name"), "attention");
  EXPECT_EQ(r.readList<std::string>(root["planners"][0]["rois"], "r", "names"),
            (std::vector<std::string>{"main_stem", "leaf_nodes"}));
  EXPECT_EQ(r.read<std::string>(root["planners"][1]["name"], "n", "a name"), "random");
  // Block scalars: line breaks come out as "\n" (YAML 1.2, 5.4: line break
  // normalization).
  EXPECT_EQ(root["note"].Scalar(), "two\nlines\n");
  EXPECT_EQ(root["folded"].Scalar(), "one line\n");
  // Keys are found without a trailing '\r', and every key is known.
  std::vector<std::string> keys;
  r.forEach(
      root, "",
      {{"trial", [&](const YAML::Node&, const std::string& k) { keys.push_back(k); }},
       {"planners", [&](const YAML::Node&, const std::string& k) { keys.push_back(k); }},
       {"note", [&](const YAML::Node&, const std::string& k) { keys.push_back(k); }},
       {"folded", [&](const YAML::Node&, const std::string& k) { keys.push_back(k); }}});
  EXPECT_EQ(keys, (std::vector<std::string>{"trial", "planners", "note", "folded"}));
}
