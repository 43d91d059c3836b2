#include <cmath>

#include <plantnbv/io/input_limits.h>
#include <plantnbv/io/yaml_reader.h>

#include "io_util.h"

namespace plantnbv {
namespace io {

YAML::Node YamlReader::parse(const std::string& text) const
{
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw FormatError("'" + file_ + "' is not valid YAML: " + e.what());
  }
}

std::string YamlReader::readText(const std::string& path)
{
  return detail::readFileToString(path, defaultInputLimits());
}

void YamlReader::fail(const std::string& path, const std::string& message) const
{
  throw FormatError("'" + file_ + "' " + (path.empty() ? "(top level)" : path) + ": " +
                    message);
}

std::vector<double> YamlReader::readNumbers(const YAML::Node& node,
                                            const std::string& path, std::size_t n,
                                            bool non_negative) const
{
  const std::string expected = "expected " + std::to_string(n) + " " +
                               (non_negative ? "non-negative " : "") + "numbers, got " +
                               describe(node);
  if (!node.IsSequence() || node.size() != n)
    fail(path, expected);
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    bool ok = node[i].IsScalar();
    if (ok) {
      try {
        out[i] = node[i].as<double>();
      } catch (const YAML::Exception&) {
        ok = false;
      }
    }
    if (!ok || !std::isfinite(out[i]) || (non_negative && out[i] < 0.0))
      fail(path, expected);
  }
  return out;
}

void YamlReader::forEach(const YAML::Node& map, const std::string& path,
                         const std::map<std::string, Handler>& handlers) const
{
  if (!map.IsMap())
    fail(path, "expected a map of keys, got " + describe(map));
  for (const auto& item : map) {
    // YAML allows lists and maps as keys ("? [a]: 1"); as<std::string>() would throw a
    // YAML exception on them (found by fuzzing).
    if (!item.first.IsScalar())
      fail(path, "a key must be a name, not " + describe(item.first));
    const std::string key = item.first.Scalar();
    const auto handler = handlers.find(key);
    if (handler == handlers.end()) {
      std::string known;
      for (const auto& h : handlers)
        known += (known.empty() ? "" : ", ") + h.first;
      fail(child(path, key), "unknown key (expected one of " + known + ")");
    }
    handler->second(item.second, child(path, key));
  }
}

std::string YamlReader::child(const std::string& path, const std::string& key)
{
  return path.empty() ? key : path + "." + key;
}

std::string YamlReader::index(const std::string& path, std::size_t i)
{
  return path + "[" + std::to_string(i) + "]";
}

namespace {

/// Appends `node` as YAML-like text, at most 4 levels deep and about 160 characters
/// ("..." beyond): a value that contains itself (an alias of an enclosing anchor) or a
/// huge one still gives a short, one-line message instead of endless recursion.
void describeInto(const YAML::Node& node, int depth, std::string& out)
{
  constexpr std::size_t kMaxChars = 160;
  if (out.size() > kMaxChars || depth > 4) {
    out += "...";
    return;
  }
  switch (node.Type()) {
  case YAML::NodeType::Undefined:
  case YAML::NodeType::Null:
    out += "nothing";
    return;
  case YAML::NodeType::Scalar:
    out += node.Scalar().size() > kMaxChars ? node.Scalar().substr(0, kMaxChars) + "..."
                                            : node.Scalar();
    return;
  case YAML::NodeType::Sequence:
    out += "[";
    for (std::size_t i = 0; i < node.size() && out.size() <= kMaxChars; ++i) {
      out += i ? ", " : "";
      describeInto(node[i], depth + 1, out);
    }
    out += out.size() > kMaxChars ? "...]" : "]";
    return;
  case YAML::NodeType::Map: {
    out += "{";
    bool first = true;
    for (const auto& kv : node) {
      if (out.size() > kMaxChars)
        break;
      out += first ? "" : ", ";
      describeInto(kv.first, depth + 1, out);
      out += ": ";
      describeInto(kv.second, depth + 1, out);
      first = false;
    }
    out += out.size() > kMaxChars ? "...}" : "}";
    return;
  }
  }
  out += "?";
}

} // namespace

std::string YamlReader::describe(const YAML::Node& node)
{
  std::string out;
  describeInto(node, 0, out);
  return out;
}

} // namespace io
} // namespace plantnbv
