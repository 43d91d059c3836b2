#pragma once
/// \file yaml_reader.h
/// \brief The one strict reader of our YAML files (ROI files, trial configs, campaign
/// files): every key known, every value of the expected type, every message naming the
/// file and the key path, e.g. "'quick.yaml' studies[1].planners[0].attention: unknown
/// ROI 'leaf'".
///
/// Include it only where yaml-cpp is linked (io and scenario link it privately; it is
/// not part of the API a robot links).

#include <functional>
#include <map>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include <plantnbv/common/error.h>

namespace plantnbv {
namespace io {

/// \brief The deepest nesting of lists and maps a YAML file we read may have (ours need
/// 5; yaml-cpp's parser stops at 2000, but walking 2000 levels is not our files' shape).
constexpr std::size_t kMaxYamlDepth = 32;
/// \brief The most values a document may have with its aliases expanded (a 1 MiB file
/// holds about 500,000 without aliases).
constexpr std::size_t kMaxYamlNodes = 4'000'000;

/// \brief Reads the nodes of one YAML document; `file` names it in every message.
///
/// Key paths are written as in the file: "trial.map.resolution", "boxes[2].size"; the
/// empty path is the document's top level. Errors are FormatError "'file' path:
/// message". Not thread-safe to share across threads while reading (it holds nothing
/// mutable, but YAML::Node is not thread-safe).
class YamlReader {
public:
  /// A key's handler: its value and its key path.
  using Handler = std::function<void(const YAML::Node& value, const std::string& path)>;

  /// \param[in] file the name messages give the document (its path, as the user wrote
  /// it).
  explicit YamlReader(std::string file) : file_(std::move(file)) {}
  /// \brief The name messages give the document.
  const std::string& file() const { return file_; }

  /// \brief Parses a document and checks its shape before any reader walks it.
  /// \throws FormatError "'file' is not valid YAML: ...", or naming the line: a value
  /// that holds an alias of itself, nesting deeper than kMaxYamlDepth, aliases that
  /// expand it past kMaxYamlNodes values, a key repeated in one map (YAML forbids it;
  /// yaml-cpp would keep the first silently).
  YAML::Node parse(const std::string& text) const;

  /// \brief The text of the YAML file at `path`, refused over
  /// defaultInputLimits().max_file_bytes before it is read.
  /// \throws IoError naming the path if it is missing or unreadable; FormatError over
  /// the limit.
  static std::string readText(const std::string& path);

  /// \brief Throws FormatError "'file' path: message" ("(top level)" for the empty path).
  [[noreturn]] void fail(const std::string& path, const std::string& message) const;

  /// \brief A scalar as T (yaml-cpp's conversion: the whole text must convert).
  /// \param[in] expected what it should be, for the message ("an integer").
  template <typename T>
  T read(const YAML::Node& node, const std::string& path, const char* expected) const
  {
    if (!node.IsScalar())
      fail(path, std::string("expected ") + expected + ", got " + describe(node));
    try {
      return node.as<T>();
    } catch (const YAML::Exception&) {
      fail(path, "'" + node.Scalar() + "' is not " + expected);
    }
  }

  /// \brief A list of scalars as T. \param[in] expected names the elements.
  template <typename T>
  std::vector<T> readList(const YAML::Node& node, const std::string& path,
                          const char* expected) const
  {
    if (!node.IsSequence())
      fail(path,
           std::string("expected a list of ") + expected + ", got " + describe(node));
    std::vector<T> out;
    for (std::size_t i = 0; i < node.size(); ++i)
      out.push_back(read<T>(node[i], index(path, i), expected));
    return out;
  }

  /// \brief Exactly `n` finite numbers (non-negative ones with `non_negative`).
  std::vector<double> readNumbers(const YAML::Node& node, const std::string& path,
                                  std::size_t n, bool non_negative = false) const;

  /// \brief Calls handlers[key] for every key of the map at `path`; a key without a
  /// handler is an error listing the known keys, and so is a key that is a list or a
  /// map (YAML allows them; ours are names).
  void forEach(const YAML::Node& map, const std::string& path,
               const std::map<std::string, Handler>& handlers) const;

  /// \brief "path.key" ("key" at the top level).
  static std::string child(const std::string& path, const std::string& key);
  /// \brief "path[i]".
  static std::string index(const std::string& path, std::size_t i);
  /// \brief The node's content as one text that ignores how it was written: maps with
  /// their keys sorted, scalars quoted, aliases expanded; documents that differ only in
  /// comments, key order, quoting, flow or block style and anchors give the same text
  /// (numbers are compared as written: 0.003 and 3e-3 differ). \pre parse() checked it.
  static std::string canonical(const YAML::Node& node);

  /// \brief The node as the user wrote it, in flow style, for messages ("nothing" for
  /// a missing or null node); at most 4 levels and about 160 characters, "..." beyond,
  /// so that a value holding an alias of itself gives a short message.
  static std::string describe(const YAML::Node& node);

private:
  std::string file_;
};

} // namespace io
} // namespace plantnbv
