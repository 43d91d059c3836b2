#include <algorithm>
#include <cmath>
#include <map>

#include <plantnbv/io/input_limits.h>
#include <plantnbv/io/yaml_reader.h>

#include "io_util.h"

namespace plantnbv {
namespace io {

namespace {

/// A scalar in double quotes with '"' and '\\' escaped, so that no scalar can imitate
/// the canonical text's punctuation.
std::string quoted(const std::string& scalar)
{
  std::string out = "\"";
  for (char c : scalar) {
    if (c == '"' || c == '\\')
      out += '\\';
    out += c;
  }
  return out + "\"";
}

/// Walks the document as its readers will (aliases followed) without recursion, and
/// refuses what would make them recurse without end or visit without end: a value that
/// holds an alias of itself, nesting deeper than kMaxYamlDepth, and aliases that
/// multiply a document past kMaxYamlNodes visited nodes ("billion laughs").
void checkDocumentShape(const YAML::Node& root, const std::string& file)
{
  struct Visit {
    YAML::Node node;
    std::size_t depth;
  };
  std::vector<Visit> stack{{root, 0}};
  std::vector<YAML::Node> path; // path[d]: the open collection at depth d
  std::size_t visited = 0;
  auto where = [](const YAML::Node& n) {
    return n.Mark().is_null() ? std::string()
                              : " (line " + std::to_string(n.Mark().line + 1) + ")";
  };
  while (!stack.empty()) {
    Visit v = std::move(stack.back());
    stack.pop_back();
    if (++visited > kMaxYamlNodes)
      throw FormatError("'" + file + "': aliases expand the document to more than " +
                        std::to_string(kMaxYamlNodes) + " values");
    if (!v.node.IsSequence() && !v.node.IsMap())
      continue;
    path.resize(v.depth);
    for (const YAML::Node& open : path)
      if (open.is(v.node))
        throw FormatError("'" + file + "'" + where(v.node) +
                          ": a value holds an alias of itself");
    if (v.depth >= kMaxYamlDepth)
      throw FormatError("'" + file + "'" + where(v.node) + ": nested deeper than " +
                        std::to_string(kMaxYamlDepth) + " levels");
    path.push_back(v.node);
    std::map<std::string, std::size_t> keys; // scalar key -> its line
    for (const auto& item : v.node) {
      if (v.node.IsMap()) {
        // yaml-cpp keeps both entries of a repeated key, and a lookup finds the first.
        if (item.first.IsScalar()) {
          const auto [seen, fresh] =
              keys.emplace(item.first.Scalar(), item.first.Mark().line + 1);
          if (!fresh)
            throw FormatError("'" + file + "'" + where(item.first) + ": key '" +
                              item.first.Scalar() + "' appears twice (first on line " +
                              std::to_string(seen->second) + ")");
        }
        stack.push_back({item.first, v.depth + 1});
        stack.push_back({item.second, v.depth + 1});
      } else {
        stack.push_back({item, v.depth + 1});
      }
    }
  }
}

} // namespace

YAML::Node YamlReader::parse(const std::string& text) const
{
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw FormatError("'" + file_ + "' is not valid YAML: " + e.what());
  }
  checkDocumentShape(root, file_);
  return root;
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

namespace {

void canonicalInto(const YAML::Node& node, std::string& out)
{
  switch (node.Type()) {
  case YAML::NodeType::Undefined:
  case YAML::NodeType::Null:
    out += "~";
    return;
  case YAML::NodeType::Scalar:
    out += quoted(node.Scalar());
    return;
  case YAML::NodeType::Sequence:
    out += "[";
    for (std::size_t i = 0; i < node.size(); ++i) {
      out += i ? "," : "";
      canonicalInto(node[i], out);
    }
    out += "]";
    return;
  case YAML::NodeType::Map: {
    std::vector<std::pair<std::string, std::string>> items;
    for (const auto& kv : node) {
      items.emplace_back();
      canonicalInto(kv.first, items.back().first);
      canonicalInto(kv.second, items.back().second);
    }
    std::sort(items.begin(), items.end());
    out += "{";
    for (std::size_t i = 0; i < items.size(); ++i)
      out += (i ? "," : "") + items[i].first + ":" + items[i].second;
    out += "}";
    return;
  }
  }
}

} // namespace

std::string YamlReader::canonical(const YAML::Node& node)
{
  std::string out;
  canonicalInto(node, out);
  return out;
}

std::string YamlReader::describe(const YAML::Node& node)
{
  std::string out;
  describeInto(node, 0, out);
  return out;
}

} // namespace io
} // namespace plantnbv
