#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include <plantnbv/common/error.h>
#include <plantnbv/io/roi_io.h>

#include "io_util.h"

namespace plantnbv {
namespace io {

namespace {

/// The node as the user wrote it, in flow style, for error messages.
std::string describe(const YAML::Node& node)
{
  switch (node.Type()) {
  case YAML::NodeType::Undefined:
  case YAML::NodeType::Null:
    return "nothing";
  case YAML::NodeType::Scalar:
    return node.Scalar();
  case YAML::NodeType::Sequence: {
    std::string s = "[";
    for (std::size_t i = 0; i < node.size(); ++i)
      s += (i ? ", " : "") + describe(node[i]);
    return s + "]";
  }
  case YAML::NodeType::Map: {
    std::string s = "{";
    bool first = true;
    for (const auto& kv : node) {
      s += (first ? "" : ", ") + describe(kv.first) + ": " + describe(kv.second);
      first = false;
    }
    return s + "}";
  }
  }
  return "?";
}

/// Parses a YAML scalar as a double with the C locale; false if it is not a number.
bool parseNumber(const YAML::Node& node, double& value)
{
  if (!node.IsScalar())
    return false;
  std::string text = node.Scalar();
  if (!text.empty() && text.front() == '+')
    text.erase(0, 1);
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, value);
  return !text.empty() && result.ec == std::errc() && result.ptr == end;
}

/// Reads `key` of a box as exactly three finite (and, for sizes, non-negative) numbers.
Eigen::Vector3d readVector(const std::string& prefix, const YAML::Node& box,
                           const char* key, bool non_negative)
{
  const YAML::Node node = box[key];
  if (!node)
    throw FormatError(prefix + "missing key '" + key + "'");
  const std::string expected = std::string(key) + " must be 3 " +
                               (non_negative ? "non-negative " : "") + "numbers, got " +
                               describe(node);
  if (!node.IsSequence() || node.size() != 3)
    throw FormatError(prefix + expected);
  Eigen::Vector3d v;
  for (std::size_t i = 0; i < 3; ++i) {
    double x = 0.0;
    if (!parseNumber(node[i], x) || !std::isfinite(x) || (non_negative && x < 0.0))
      throw FormatError(prefix + expected);
    v[static_cast<Eigen::Index>(i)] = x;
  }
  return v;
}

Box readBox(const std::string& path, std::size_t index, const YAML::Node& node)
{
  const std::string prefix = detail::where(path) + "box " + std::to_string(index) + ": ";
  if (!node.IsMap())
    throw FormatError(prefix +
                      "expected a map with center, size and an optional name, got " +
                      describe(node));
  for (const auto& kv : node) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : describe(kv.first);
    if (key != "name" && key != "center" && key != "size")
      throw FormatError(prefix + "unknown key '" + key +
                        "' (expected name, center, size)");
  }
  std::string name;
  if (const YAML::Node n = node["name"]) {
    if (!n.IsScalar())
      throw FormatError(prefix + "name must be a string, got " + describe(n));
    name = n.Scalar();
  }
  const Eigen::Vector3d center = readVector(prefix, node, "center", false);
  const Eigen::Vector3d size = readVector(prefix, node, "size", true);
  // Finite numbers can still overflow to an infinite corner (e.g. size 1e308 at 1e308).
  const Box box(center, size, name);
  if (!box.min().allFinite() || !box.max().allFinite())
    throw FormatError(prefix + "center +- size/2 overflows: center " +
                      describe(node["center"]) + ", size " + describe(node["size"]));
  return box;
}

/// The shortest decimal text that reads back as exactly `v` (at most 17 digits).
std::string exactNumber(double v)
{
  std::array<char, 32> buf{};
  const auto result = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), result.ptr);
}

/// A name as a YAML scalar: plain when it cannot be misread, double-quoted otherwise.
std::string yamlString(const std::string& s)
{
  static const char* const kSpecial[] = {"null", "true", "false", "yes", "no",
                                         "on",   "off",  "y",     "n"};
  bool plain =
      !s.empty() && (std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_');
  for (char c : s)
    plain = plain && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' ||
                      c == '-' || c == '.');
  std::string lower;
  for (char c : s)
    lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* word : kSpecial)
    plain = plain && lower != word;
  if (plain)
    return s;
  std::string q = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') {
      q += '\\';
      q += static_cast<char>(c);
    } else if (c < 0x20 || c == 0x7f) {
      static const char* const kHex = "0123456789abcdef";
      q += "\\x";
      q += kHex[c >> 4];
      q += kHex[c & 15];
    } else
      q += static_cast<char>(c);
  }
  return q + "\"";
}

std::string yamlVector(const Eigen::Vector3d& v)
{
  return "[" + exactNumber(v.x()) + ", " + exactNumber(v.y()) + ", " +
         exactNumber(v.z()) + "]";
}

} // namespace

namespace {

Roi parseRoi(const std::string& path, const std::string& text)
{
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw FormatError(detail::where(path) + "not valid YAML: " + e.what());
  }
  if (!root || root.IsNull())
    throw FormatError(detail::where(path) + "no boxes (the file is empty)");
  if (!root.IsMap())
    throw FormatError(detail::where(path) + "expected a map with the key 'boxes', got " +
                      describe(root));
  for (const auto& kv : root) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : describe(kv.first);
    if (key != "boxes")
      throw FormatError(detail::where(path) + "unknown key '" + key +
                        "' (expected boxes)");
  }
  const YAML::Node boxes = root["boxes"];
  if (!boxes)
    throw FormatError(detail::where(path) + "no boxes (missing key 'boxes')");
  if (!boxes.IsSequence() && !boxes.IsNull())
    throw FormatError(detail::where(path) + "boxes must be a list, got " +
                      describe(boxes));
  if (boxes.IsNull() || boxes.size() == 0)
    throw FormatError(detail::where(path) + "no boxes");
  Roi roi;
  for (std::size_t i = 0; i < boxes.size(); ++i)
    roi.addBox(readBox(path, i, boxes[i]));
  return roi;
}

} // namespace

Roi loadRoi(const std::string& path)
{
  const std::string text = detail::readFileToString(path, defaultInputLimits());
  try {
    return parseRoi(path, text);
  } catch (const YAML::Exception& e) {
    // A safety net: every case we know of is reported above with a clearer message.
    throw FormatError(detail::where(path) + "malformed ROI file: " + e.what());
  }
}

void saveRoi(const std::string& path, const Roi& roi)
{
  if (roi.empty())
    throw InvalidArgumentError(detail::where(path) +
                               "an empty ROI cannot be saved (an ROI file needs boxes)");
  std::ostringstream out;
  out << "boxes:\n";
  for (std::size_t i = 0; i < roi.size(); ++i) {
    const Box& b = roi.boxes()[i];
    if (!b.center.allFinite() || !b.size.allFinite())
      throw InvalidArgumentError(detail::where(path) + "box " + std::to_string(i) +
                                 " has a non-finite centre or size");
    out << "  - ";
    if (!b.name.empty())
      out << "name: " << yamlString(b.name) << "\n    ";
    out << "center: " << yamlVector(b.center) << "\n";
    out << "    size: " << yamlVector(b.size) << "\n";
  }
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file)
    throw IoError(detail::where(path) + "cannot open for writing");
  file << out.str();
  file.close();
  if (!file)
    throw IoError(detail::where(path) + "write error");
}

} // namespace io
} // namespace plantnbv
