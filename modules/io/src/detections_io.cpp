#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <plantnbv/common/error.h>
#include <plantnbv/common/file_io.h>
#include <plantnbv/common/number_text.h>
#include <plantnbv/io/depth_image_io.h>
#include <plantnbv/io/detections_io.h>

#include "io_util.h"

namespace plantnbv {
namespace io {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// A detection file is small (about 100 bytes an entry); a larger one is not one.
constexpr std::uint64_t kMaxDetectionsFileBytes = std::uint64_t{64} << 20;
/// The largest side of an image (CameraIntrinsics::validate).
constexpr std::uint32_t kMaxImageSide = 16384;
/// A string value is quoted in messages up to this many characters.
constexpr std::size_t kMaxQuotedChars = 40;

const char* const kEntryKeys = "box, class, mask, score";

std::string inQuotes(const std::string& path)
{
  return "'" + path + "'";
}

/// A JSON string as JSON text, ASCII only (control characters and non-ASCII escaped):
/// always one line.
std::string jsonText(const std::string& s)
{
  return json(s).dump(-1, ' ', true, json::error_handler_t::replace);
}

/// A key in a message path: as it is when it is a plain name, else as JSON text.
std::string keyText(const std::string& key)
{
  const bool plain = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
           c == '_' || c == '-';
  });
  return plain ? key : jsonText(key);
}

/// A JSON value for "got ..." in messages: short, one line, and without walking a nested
/// value (which could be deep).
std::string describe(const json& v)
{
  switch (v.type()) {
  case json::value_t::null:
    return "null";
  case json::value_t::boolean:
    return v.get<bool>() ? "true" : "false";
  case json::value_t::string: {
    const std::string text = jsonText(v.get_ref<const std::string&>());
    return text.size() <= kMaxQuotedChars ? text
                                          : text.substr(0, kMaxQuotedChars) + "...\"";
  }
  case json::value_t::array:
    return "a list of " + std::to_string(v.size());
  case json::value_t::object:
    return "an object";
  case json::value_t::number_integer:
  case json::value_t::number_unsigned:
  case json::value_t::number_float:
    return v.dump();
  default:
    return "binary data";
  }
}

std::string boxText(const Eigen::Vector4d& b)
{
  return "[" + shortestText(b[0]) + ", " + shortestText(b[1]) + ", " +
         shortestText(b[2]) + ", " + shortestText(b[3]) + "]";
}

/// Why a score is refused ("1.5 is not in [0, 1]"), empty if it is not.
std::string scoreProblem(double score)
{
  if (score >= 0.0 && score <= 1.0)
    return "";
  return shortestText(score) + " is not in [0, 1]";
}

/// Why a box is refused for a width x height image, empty if it is not.
std::string boxProblem(const Eigen::Vector4d& b, std::uint32_t width,
                       std::uint32_t height)
{
  if (!b.allFinite())
    return boxText(b) + " has a non-finite number";
  if (b[0] > b[2])
    return boxText(b) + ": u0 " + shortestText(b[0]) + " > u1 " + shortestText(b[2]) +
           " (expected [u0, v0, u1, v1], u0 <= u1)";
  if (b[1] > b[3])
    return boxText(b) + ": v0 " + shortestText(b[1]) + " > v1 " + shortestText(b[3]) +
           " (expected [u0, v0, u1, v1], v0 <= v1)";
  if (b[0] < 0.0 || b[1] < 0.0 || b[2] > width || b[3] > height)
    return boxText(b) + " is outside the " + std::to_string(width) + "x" +
           std::to_string(height) +
           " image (expected 0 <= u0 <= u1 <= " + std::to_string(width) +
           ", 0 <= v0 <= v1 <= " + std::to_string(height) + ")";
  return "";
}

/// Why `masks` masks of width x height are refused, empty if they are not.
std::string maskBytesProblem(std::uint64_t masks, std::uint32_t width,
                             std::uint32_t height)
{
  const std::uint64_t bytes = masks * width * height;
  if (bytes <= kMaxMaskBytesPerFrame)
    return "";
  return std::to_string(masks) + " masks of " + std::to_string(width) + "x" +
         std::to_string(height) + " take " + std::to_string(bytes) +
         " bytes, more than " + std::to_string(kMaxMaskBytesPerFrame) +
         " (kMaxMaskBytesPerFrame)";
}

void checkImageSize(const char* function, std::uint32_t width, std::uint32_t height)
{
  if (width < 1 || width > kMaxImageSide || height < 1 || height > kMaxImageSide)
    throw InvalidArgumentError(std::string(function) + ": image " +
                               std::to_string(width) + "x" + std::to_string(height) +
                               " is not 1 to 16384 pixels per side");
}

/// Where the parser is, to name a repeated key: a stack of the containers it is in.
class KeyTracker {
public:
  explicit KeyTracker(const std::string& file) : file_(file) {}

  bool operator()(int /*depth*/, json::parse_event_t event, json& parsed)
  {
    switch (event) {
    case json::parse_event_t::object_start:
      stack_.push_back(Frame{false, 0, "", {}});
      break;
    case json::parse_event_t::array_start:
      stack_.push_back(Frame{true, 0, "", {}});
      break;
    case json::parse_event_t::key: {
      Frame& top = stack_.back();
      top.key = parsed.get<std::string>();
      if (!top.keys.insert(top.key).second)
        throw FormatError(file_ + " " + path() +
                          ": repeated key (a key may appear once in an object)");
      break;
    }
    case json::parse_event_t::object_end:
    case json::parse_event_t::array_end:
      stack_.pop_back();
      elementDone();
      break;
    case json::parse_event_t::value:
      elementDone();
      break;
    }
    return true;
  }

private:
  struct Frame {
    bool array;
    std::size_t index; ///< arrays: elements read so far
    std::string key;   ///< objects: the key being read
    std::set<std::string> keys;
  };

  void elementDone()
  {
    if (!stack_.empty() && stack_.back().array)
      ++stack_.back().index;
  }

  std::string path() const
  {
    std::string p;
    for (const Frame& f : stack_)
      p += f.array ? "[" + std::to_string(f.index) + "]"
                   : (p.empty() ? "" : ".") + keyText(f.key);
    return p;
  }

  std::string file_;
  std::vector<Frame> stack_;
};

json parseJson(const std::string& path, const std::string& text)
{
  KeyTracker tracker(inQuotes(path));
  try {
    return json::parse(text, std::ref(tracker));
  } catch (const json::exception& e) {
    // parse_error, and out_of_range for a number beyond double.
    throw FormatError(inQuotes(path) + ": not JSON (" + e.what() + ")");
  }
}

/// Reads one entry of a detection file (its keys checked), its mask loaded.
class EntryReader {
public:
  EntryReader(const std::string& path, std::uint32_t width, std::uint32_t height)
      : path_(path), width_(width), height_(height)
  {
  }

  Detection read(const json& entry, std::size_t i) const
  {
    const std::string at = "detections[" + std::to_string(i) + "]";
    if (!entry.is_object())
      fail(at, "expected an object {\"class\", \"score\", \"box\"[, \"mask\"]}, got " +
                   describe(entry));
    for (const auto& item : entry.items()) {
      const std::string& key = item.key();
      if (key != "class" && key != "score" && key != "box" && key != "mask")
        fail(at + "." + keyText(key),
             std::string("unknown key (expected one of ") + kEntryKeys + ")");
    }
    Detection d;
    const json* v =
        find(entry, "class", at + ".class", "the object's class, e.g. \"leaf_node\"");
    if (!v->is_string())
      fail(at + ".class", "expected a non-empty string, got " + describe(*v));
    d.class_name = v->get<std::string>();
    if (d.class_name.empty())
      fail(at + ".class", "is empty (expected the object's class, e.g. \"leaf_node\")");

    v = find(entry, "score", at + ".score", "a number in [0, 1]");
    if (!v->is_number())
      fail(at + ".score", "expected a number in [0, 1], got " + describe(*v));
    d.score = v->get<double>();
    const std::string score = scoreProblem(d.score);
    if (!score.empty())
      fail(at + ".score", score);

    v = find(entry, "box", at + ".box", "[u0, v0, u1, v1] in pixels");
    if (!v->is_array() || v->size() != 4)
      fail(at + ".box",
           "expected 4 numbers [u0, v0, u1, v1] in pixels, got " + describe(*v));
    for (std::size_t k = 0; k < 4; ++k) {
      const json& n = (*v)[k];
      if (!n.is_number())
        fail(at + ".box[" + std::to_string(k) + "]",
             "expected a number of pixels, got " + describe(n));
      d.box_px[Eigen::Index(k)] = n.get<double>();
    }
    const std::string box = boxProblem(d.box_px, width_, height_);
    if (!box.empty())
      fail(at + ".box", box);

    const auto mask = entry.find("mask");
    if (mask != entry.end())
      readMask(*mask, at + ".mask", d.mask);
    return d;
  }

private:
  [[noreturn]] void fail(const std::string& at, const std::string& what) const
  {
    throw FormatError(inQuotes(path_) + " " + at + ": " + what);
  }

  /// The value of a required key; `at` names it in messages.
  const json* find(const json& entry, const char* key, const std::string& at,
                   const char* expected) const
  {
    const auto it = entry.find(key);
    if (it == entry.end())
      fail(at, std::string("missing (") + expected + ")");
    return &*it;
  }

  void readMask(const json& v, const std::string& at,
                std::vector<std::uint8_t>& mask) const
  {
    if (!v.is_string() || v.get_ref<const std::string&>().empty())
      fail(at, "expected the name of an 8-bit grey PNG, got " + describe(v));
    const std::string& name = v.get_ref<const std::string&>();
    if (std::any_of(name.begin(), name.end(),
                    [](char c) { return static_cast<unsigned char>(c) < 0x20; }))
      fail(at, "expected a file name without control characters, got " + describe(v));
    if (!detail::staysInside(name))
      fail(at, inQuotes(name) +
                   " must be a path inside the JSON file's folder (relative, no '..')");
    const std::string mask_path = (fs::path(path_).parent_path() / name).string();
    const std::string prefix = inQuotes(path_) + " " + at + ": ";
    std::uint32_t w = 0, h = 0;
    try {
      loadMaskPng(mask_path, w, h, mask, width_, height_);
    } catch (const FileNotFoundError& e) {
      throw FileNotFoundError(prefix + e.what());
    } catch (const IoError& e) {
      throw IoError(prefix + e.what());
    } catch (const FormatError& e) {
      throw FormatError(prefix + e.what());
    }
  }

  const std::string& path_;
  std::uint32_t width_, height_;
};

} // namespace

std::vector<Detection> readDetections(const std::string& path, std::uint32_t width,
                                      std::uint32_t height)
{
  checkImageSize("readDetections", width, height);
  InputLimits limits = defaultInputLimits();
  if (limits.max_file_bytes == 0 || limits.max_file_bytes > kMaxDetectionsFileBytes)
    limits.max_file_bytes = kMaxDetectionsFileBytes;
  const json root = parseJson(path, detail::readFileToString(path, limits));
  const std::string file = inQuotes(path);
  if (!root.is_object())
    throw FormatError(file + ": expected an object {\"detections\": [...]}, got " +
                      describe(root));
  for (const auto& item : root.items())
    if (item.key() != "detections")
      throw FormatError(file + " " + keyText(item.key()) +
                        ": unknown key (expected detections)");
  const auto list = root.find("detections");
  if (list == root.end())
    throw FormatError(file + " detections: missing (a list of {\"class\", \"score\", "
                             "\"box\"[, \"mask\"]})");
  if (!list->is_array())
    throw FormatError(file + " detections: expected a list, got " + describe(*list));
  if (list->size() > kMaxDetectionsPerFrame)
    throw FormatError(file + " detections: " + std::to_string(list->size()) +
                      " entries, more than " + std::to_string(kMaxDetectionsPerFrame) +
                      " (kMaxDetectionsPerFrame)");
  // The masks' memory, before any is read.
  std::uint64_t masks = 0;
  for (const json& entry : *list)
    masks += entry.is_object() && entry.contains("mask");
  const std::string too_much = maskBytesProblem(masks, width, height);
  if (!too_much.empty())
    throw FormatError(file + " detections: " + too_much);
  const EntryReader reader(path, width, height);
  std::vector<Detection> detections;
  detections.reserve(list->size());
  for (std::size_t i = 0; i < list->size(); ++i)
    detections.push_back(reader.read((*list)[i], i));
  return detections;
}

void writeDetections(const std::string& path, const std::vector<Detection>& detections,
                     std::uint32_t width, std::uint32_t height)
{
  checkImageSize("writeDetections", width, height);
  const std::string file = inQuotes(path);
  const auto fail = [&](const std::string& at, const std::string& what) {
    throw InvalidArgumentError(file + " " + at + ": " + what);
  };
  if (detections.size() > kMaxDetectionsPerFrame)
    fail("detections", std::to_string(detections.size()) + " entries, more than " +
                           std::to_string(kMaxDetectionsPerFrame) +
                           " (kMaxDetectionsPerFrame)");
  const std::size_t size = std::size_t(width) * height;
  const std::string too_much = maskBytesProblem(
      std::uint64_t(std::count_if(detections.begin(), detections.end(),
                                  [](const Detection& d) { return !d.mask.empty(); })),
      width, height);
  if (!too_much.empty())
    fail("detections", too_much);
  std::vector<std::string> classes(detections.size());
  for (std::size_t i = 0; i < detections.size(); ++i) {
    const Detection& d = detections[i];
    const std::string at = "detections[" + std::to_string(i) + "]";
    if (d.class_name.empty())
      fail(at + ".class", "is empty (expected the object's class, e.g. \"leaf_node\")");
    try {
      classes[i] = json(d.class_name).dump();
    } catch (const json::exception&) {
      fail(at + ".class", "is not UTF-8 text");
    }
    const std::string score = scoreProblem(d.score);
    if (!score.empty())
      fail(at + ".score", score);
    const std::string box = boxProblem(d.box_px, width, height);
    if (!box.empty())
      fail(at + ".box", box);
    if (!d.mask.empty()) {
      if (d.mask.size() != size)
        fail(at + ".mask", "has " + std::to_string(d.mask.size()) +
                               " bytes, expected 0 (no mask) or " +
                               std::to_string(width) + " x " + std::to_string(height) +
                               " = " + std::to_string(size));
    }
  }

  const fs::path json_path(path);
  const std::string stem = json_path.stem().string();
  std::string text = "{\"detections\": [";
  for (std::size_t i = 0; i < detections.size(); ++i) {
    const Detection& d = detections[i];
    // Numbers as nlohmann::json writes them: the shortest text that reads back exactly.
    text += (i == 0 ? "\n  " : ",\n  ");
    text += "{\"class\": " + classes[i] + ", \"score\": " + json(d.score).dump() +
            ", \"box\": [" + json(d.box_px[0]).dump() + ", " + json(d.box_px[1]).dump() +
            ", " + json(d.box_px[2]).dump() + ", " + json(d.box_px[3]).dump() + "]";
    if (!d.mask.empty()) {
      const std::string name = stem + "_" + std::to_string(i) + ".png";
      saveMaskPng((json_path.parent_path() / name).string(), width, height, d.mask);
      text += ", \"mask\": " + jsonText(name);
    }
    text += "}";
  }
  text += detections.empty() ? "]}\n" : "\n]}\n";
  writeFileAtomically(path, text);
}

} // namespace io
} // namespace plantnbv
