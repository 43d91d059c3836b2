#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include <plantnbv/common/error.h>
#include <plantnbv/common/number_text.h>
#include <plantnbv/io/roi_io.h>
#include <plantnbv/io/yaml_reader.h>

#include "io_util.h"

namespace plantnbv {
namespace io {

namespace {

/// The box at `path` given by its centre and size (the form saveRoi writes).
Box readCenterSizeBox(const YamlReader& r, const YAML::Node& node,
                      const std::string& path)
{
  std::string name;
  std::vector<double> center, size;
  r.forEach(node, path,
            {{"name",
              [&](const YAML::Node& n, const std::string& k) {
                name = r.read<std::string>(n, k, "a name");
              }},
             {"center", [&](const YAML::Node& n,
                            const std::string& k) { center = r.readNumbers(n, k, 3); }},
             {"size", [&](const YAML::Node& n, const std::string& k) {
                size = r.readNumbers(n, k, 3, /*non_negative=*/true);
              }}});
  if (center.empty())
    r.fail(path, "missing key 'center'");
  if (size.empty())
    r.fail(path, "missing key 'size'");
  // A box without volume holds almost nothing, and a score over it (F1 of one point)
  // means nothing: every side must be > 0.
  if (std::any_of(size.begin(), size.end(), [](double v) { return !(v > 0.0); }))
    r.fail(YamlReader::child(path, "size"),
           "expected 3 sizes > 0 (metres), got " + YamlReader::describe(node["size"]));
  // Finite numbers can still overflow to an infinite corner (e.g. size 1e308 at 1e308).
  const Box box(Eigen::Vector3d(center[0], center[1], center[2]),
                Eigen::Vector3d(size[0], size[1], size[2]), name);
  if (!box.min().allFinite() || !box.max().allFinite())
    r.fail(path, "center +- size/2 overflows: center " +
                     YamlReader::describe(node["center"]) + ", size " +
                     YamlReader::describe(node["size"]));
  return box;
}

/// The box at `path` given by its lowest and highest corners (the ROI viewpoint
/// planner's form): centre (min + max) / 2, size max - min.
Box readMinMaxBox(const YamlReader& r, const YAML::Node& node, const std::string& path)
{
  std::string name;
  std::vector<double> lo, hi;
  r.forEach(node, path,
            {{"name",
              [&](const YAML::Node& n, const std::string& k) {
                name = r.read<std::string>(n, k, "a name");
              }},
             {"min", [&](const YAML::Node& n,
                         const std::string& k) { lo = r.readNumbers(n, k, 3); }},
             {"max", [&](const YAML::Node& n, const std::string& k) {
                hi = r.readNumbers(n, k, 3);
              }}});
  if (lo.empty())
    r.fail(path, "missing key 'min'");
  if (hi.empty())
    r.fail(path, "missing key 'max'");
  const Eigen::Vector3d min(lo[0], lo[1], lo[2]), max(hi[0], hi[1], hi[2]);
  // A box without volume means nothing (see readCenterSizeBox): min < max on every axis.
  if (!(min.array() < max.array()).all())
    r.fail(path, "expected min < max on every axis, got min " +
                     YamlReader::describe(node["min"]) + ", max " +
                     YamlReader::describe(node["max"]));
  // (min + max) / 2 is the rounded midpoint unless the sum overflows (corners near the
  // largest double); halving each corner first then keeps it finite. max - min can
  // overflow too (-1e308 to 1e308): a box no double can hold is refused.
  Eigen::Vector3d center = 0.5 * (min + max);
  if (!center.allFinite())
    center = 0.5 * min + 0.5 * max;
  const Eigen::Vector3d size = max - min;
  if (!size.allFinite())
    r.fail(path, "max - min overflows: min " + YamlReader::describe(node["min"]) +
                     ", max " + YamlReader::describe(node["max"]));
  return Box(center, size, name);
}

/// The box at `path`: center and size, or min and max (never a mix).
Box readBox(const YamlReader& r, const YAML::Node& node, const std::string& path)
{
  if (!node.IsMap())
    r.fail(path, "expected a map with center and size (or min and max) and an optional "
                 "name, got " +
                     YamlReader::describe(node));
  const bool center_size = node["center"] || node["size"];
  const bool min_max = node["min"] || node["max"];
  if (center_size && min_max)
    r.fail(path, "give center and size, or min and max, not both");
  return min_max ? readMinMaxBox(r, node, path) : readCenterSizeBox(r, node, path);
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
  return "[" + shortestText(v.x()) + ", " + shortestText(v.y()) + ", " +
         shortestText(v.z()) + "]";
}

Roi parseRoi(const std::string& path, const std::string& text)
{
  const YamlReader r(path);
  const YAML::Node root = r.parse(text);
  if (!root || root.IsNull())
    r.fail("", "no boxes (the file is empty)");
  Roi roi;
  // The ROI viewpoint planner's form: the list of boxes is the whole document.
  if (root.IsSequence()) {
    for (std::size_t i = 0; i < root.size(); ++i)
      roi.addBox(readBox(r, root[i], YamlReader::index("", i)));
    if (roi.empty())
      r.fail("", "no boxes (the list is empty)");
    return roi;
  }
  bool has_boxes = false;
  r.forEach(root, "",
            {{"boxes", [&](const YAML::Node& boxes, const std::string& k) {
                has_boxes = true;
                if (!boxes.IsSequence() && !boxes.IsNull())
                  r.fail(k,
                         "expected a list of boxes, got " + YamlReader::describe(boxes));
                for (std::size_t i = 0; boxes.IsSequence() && i < boxes.size(); ++i)
                  roi.addBox(readBox(r, boxes[i], YamlReader::index(k, i)));
              }}});
  if (!has_boxes)
    r.fail("", "no boxes (missing key 'boxes')");
  if (roi.empty())
    r.fail("boxes", "no boxes");
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
  writeFileAtomically(path, out.str());
}

} // namespace io
} // namespace plantnbv
