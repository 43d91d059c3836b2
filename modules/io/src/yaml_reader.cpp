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

std::string YamlReader::describe(const YAML::Node& node)
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

} // namespace io
} // namespace plantnbv
