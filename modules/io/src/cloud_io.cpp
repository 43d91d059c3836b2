// Our own PCD and PLY point cloud readers and writers. PCL's (pcl_io) crashed on
// malformed files in many ways (found by fuzzing, tests/fuzz/regressions), and pcl_io
// loads VTK into every program that links it: a robot program that reads frames
// folders through this module should not carry a renderer.

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/number_text.h>
#include <plantnbv/io/cloud_io.h>
#include <plantnbv/io/file_kind.h>

#include "io_util.h"
#include "ply_format.h"

namespace plantnbv {
namespace io {

namespace {

const char* const kCloudExtensions = "expected .pcd or .ply";

/// a * b, or false when it overflows 64 bits.
bool multiply(std::uint64_t a, std::uint64_t b, std::uint64_t& product)
{
  return !__builtin_mul_overflow(a, b, &product);
}

std::uint32_t littleEndianU32(const std::uint8_t* b)
{
  return std::uint32_t{b[0]} | std::uint32_t{b[1]} << 8 | std::uint32_t{b[2]} << 16 |
         std::uint32_t{b[3]} << 24;
}

/// The values a cloud keeps of each point, as read (any stored type, as a double).
struct PointValues {
  double x = 0.0, y = 0.0, z = 0.0, label = 0.0;
};

/// Receives the points of a file in order; width x height is known before the first.
template <typename PointT>
class CloudFiller {
public:
  CloudFiller(const std::string& path, pcl::PointCloud<PointT>& cloud)
      : path_(path), cloud_(cloud)
  {
  }

  void resize(std::uint64_t width, std::uint64_t height)
  {
    cloud_.points.clear();
    cloud_.points.resize(static_cast<std::size_t>(width * height));
    cloud_.width = static_cast<std::uint32_t>(width);
    cloud_.height = static_cast<std::uint32_t>(height);
    cloud_.is_dense = true;
  }

  void set(std::size_t i, const PointValues& v)
  {
    PointT& q = cloud_.points[i];
    q.x = static_cast<float>(v.x);
    q.y = static_cast<float>(v.y);
    q.z = static_cast<float>(v.z);
    // From the points, not the file's word: PCL's filters skip their finiteness checks
    // on a dense cloud, and NaNs must never reach OctoMap.
    cloud_.is_dense =
        cloud_.is_dense && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
    if constexpr (std::is_same_v<PointT, pcl::PointXYZL>) {
      if (!(v.label >= 0.0 && v.label <= 4294967295.0 && v.label == std::floor(v.label)))
        throw FormatError(detail::where(path_) + "point " + std::to_string(i) +
                          " has label " + shortestText(v.label) +
                          ", expected a non-negative whole number");
      q.label = static_cast<std::uint32_t>(v.label);
    }
  }

private:
  const std::string& path_;
  pcl::PointCloud<PointT>& cloud_;
};

FormatError missingAxis(const std::string& path, const char* axis)
{
  return FormatError(detail::where(path) + "has no '" + axis +
                     "' field (a point cloud needs x, y and z)");
}

// ---- PCD ------------------------------------------------------------------------------

/// Decodes one value of a field from its bytes in the file.
using ValueDecoder = double (*)(const std::uint8_t*);

struct PcdField {
  std::string name;
  char type = 'F';               ///< I (signed), U (unsigned) or F (floating point)
  std::uint64_t size = 4;        ///< bytes of one value: 1, 2, 4 or 8 (F: 4 or 8)
  std::uint64_t count = 1;       ///< values per point
  std::uint64_t offset = 0;      ///< bytes from the start of a point record
  ValueDecoder decode = nullptr; ///< chosen once per file (decoderOf)
};

struct PcdHeader {
  std::vector<PcdField> fields;
  std::uint64_t width = 0, height = 1, points = 0;
  std::uint64_t point_size = 0;           ///< bytes of one point record
  std::uint64_t values = 0;               ///< values of one point (the sum of the counts)
  std::string data;                       ///< ascii, binary or binary_compressed
  int x = -1, y = -1, z = -1, label = -1; ///< the fields the cloud keeps; -1: none
};

/// A value of type T from its little-endian bytes (PCD binary data is written in the
/// byte order of x86 and ARM), as a double (exact for every type but 64-bit integers
/// beyond 2^53).
template <typename T>
double littleEndianValue(const std::uint8_t* p)
{
  static const bool swap = !detail::hostIsLittleEndian();
  std::uint8_t b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (swap)
    std::reverse(b, b + sizeof(T));
  T v;
  std::memcpy(&v, b, sizeof(T));
  return static_cast<double>(v);
}

/// The decoder of a field's values, chosen once per file.
ValueDecoder decoderOf(char type, std::uint64_t size)
{
  if (type == 'F')
    return size == 4 ? littleEndianValue<float> : littleEndianValue<double>;
  if (type == 'I')
    return size == 1   ? littleEndianValue<std::int8_t>
           : size == 2 ? littleEndianValue<std::int16_t>
           : size == 4 ? littleEndianValue<std::int32_t>
                       : littleEndianValue<std::int64_t>;
  return size == 1   ? littleEndianValue<std::uint8_t>
         : size == 2 ? littleEndianValue<std::uint16_t>
         : size == 4 ? littleEndianValue<std::uint32_t>
                     : littleEndianValue<std::uint64_t>;
}

/// Reads and checks a PCD header, `in` left at the data; nothing is allocated for the
/// points before the file is known to be long enough for them.
PcdHeader readPcdHeader(const std::string& path, std::ifstream& in,
                        const InputLimits& limits)
{
  auto bad = [&](const std::string& why) {
    return FormatError(detail::where(path) + "bad PCD header: " + why);
  };
  PcdHeader h;
  std::vector<std::string> names;
  std::vector<std::uint64_t> sizes, counts;
  std::string types;
  bool have_width = false, have_points = false, have_types = false;
  std::string line;
  while (h.data.empty()) {
    if (!detail::readHeaderLine(path, in, line))
      throw bad("no DATA line (not a PCD file?)");
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key.empty() || key[0] == '#' || key == "VERSION" || key == "VIEWPOINT")
      continue;
    std::vector<std::string> values;
    for (std::string w; words >> w;)
      values.push_back(w);
    auto number = [&](const std::string& w) {
      std::uint64_t v = 0;
      const auto r = std::from_chars(w.data(), w.data() + w.size(), v);
      if (r.ec != std::errc() || r.ptr != w.data() + w.size())
        throw bad(key + " value '" + w + "' is not a non-negative integer");
      return v;
    };
    if (key == "FIELDS" || key == "COLUMNS")
      names = values;
    else if (key == "SIZE")
      for (const auto& w : values)
        sizes.push_back(number(w));
    else if (key == "COUNT")
      for (const auto& w : values)
        counts.push_back(number(w));
    else if (key == "TYPE") {
      for (const auto& w : values)
        types += w;
      have_types = true;
    } else if (key == "WIDTH" && values.size() == 1) {
      h.width = number(values[0]);
      have_width = true;
    } else if (key == "HEIGHT" && values.size() == 1)
      h.height = number(values[0]);
    else if (key == "POINTS" && values.size() == 1) {
      h.points = number(values[0]);
      have_points = true;
    } else if (key == "DATA" && values.size() == 1)
      h.data = values[0];
    else
      throw bad("unexpected line '" + line + "'");
  }
  const std::size_t fields = names.size();
  if (fields == 0 || sizes.size() != fields || !have_types || types.size() != fields ||
      (!counts.empty() && counts.size() != fields))
    throw bad("FIELDS, SIZE, TYPE and COUNT must list the same number of fields");
  if (types.find_first_not_of("IUF") != std::string::npos)
    throw bad("TYPE must be I, U or F");
  if (!have_width)
    throw bad("no WIDTH");
  std::uint64_t width_x_height = 0;
  if (!multiply(h.width, h.height, width_x_height))
    throw bad("WIDTH x HEIGHT overflows");
  if (!have_points)
    h.points = width_x_height;
  if (h.points != width_x_height)
    throw bad("POINTS " + std::to_string(h.points) + " is not WIDTH x HEIGHT (" +
              std::to_string(h.width) + " x " + std::to_string(h.height) + ")");
  detail::checkLimit(path, h.points, "points", limits.max_points, "max_points");
  if (h.data != "ascii" && h.data != "binary" && h.data != "binary_compressed")
    throw bad("DATA must be ascii, binary or binary_compressed, got '" + h.data + "'");
  // Counts as large as PCL's widest descriptors (e.g. ESF, 640 values) with room to
  // spare.
  constexpr std::uint64_t kMaxCount = 1 << 16;
  for (std::size_t i = 0; i < fields; ++i) {
    PcdField f{names[i], types[i], sizes[i], counts.empty() ? 1 : counts[i],
               h.point_size};
    if (f.size != 1 && f.size != 2 && f.size != 4 && f.size != 8)
      throw bad("SIZE " + std::to_string(f.size) + " is not 1, 2, 4 or 8");
    if (f.type == 'F' && f.size != 4 && f.size != 8)
      throw bad("SIZE " + std::to_string(f.size) + " of an F field is not 4 or 8");
    if (f.count < 1 || f.count > kMaxCount)
      throw bad("COUNT " + std::to_string(f.count) + " is not in 1.." +
                std::to_string(kMaxCount));
    f.decode = decoderOf(f.type, f.size);
    h.point_size += f.size * f.count;
    h.values += f.count;
    // The first field of each name counts, and its first value.
    for (auto [name, role] : {std::pair{"x", &h.x}, std::pair{"y", &h.y},
                              std::pair{"z", &h.z}, std::pair{"label", &h.label}})
      if (f.name == name && *role < 0)
        *role = static_cast<int>(i);
    h.fields.push_back(std::move(f));
  }
  if (h.x < 0)
    throw missingAxis(path, "x");
  if (h.y < 0)
    throw missingAxis(path, "y");
  if (h.z < 0)
    throw missingAxis(path, "z");

  const auto body = static_cast<std::uint64_t>(in.tellg());
  const std::uint64_t file_size = std::filesystem::file_size(path);
  if (!in || body > file_size)
    throw IoError(detail::where(path) + "cannot determine the file size");
  const std::uint64_t left = file_size - body;
  auto truncated = [&](const std::string& need) {
    return FormatError(detail::where(path) + "truncated: " + std::to_string(h.points) +
                       " points need " + need + ", more than the " +
                       std::to_string(left) + " bytes left");
  };
  // ASCII: each value takes at least one character and a separator.
  if (h.data == "ascii" && h.points > (left + 1) / (2 * h.values))
    throw truncated("at least " + std::to_string(2 * h.values) + " bytes each");
  if (h.data == "binary" && left / h.point_size < h.points)
    throw truncated(std::to_string(h.point_size) + " bytes each");
  if (h.data == "binary_compressed") {
    std::uint8_t sizes[8];
    std::uint64_t bytes = 0;
    // LZF expands 3 bytes into at most 264: a larger ratio cannot be real data.
    if (!in.read(reinterpret_cast<char*>(sizes), 8) ||
        littleEndianU32(sizes) > left - std::min<std::uint64_t>(left, 8) ||
        !multiply(h.points, h.point_size, bytes) || littleEndianU32(sizes + 4) != bytes ||
        bytes > 88 * std::uint64_t{littleEndianU32(sizes)} + 8)
      throw FormatError(detail::where(path) +
                        "truncated or inconsistent compressed data");
    in.seekg(static_cast<std::streamoff>(body));
  }
  if (h.width > std::numeric_limits<std::uint32_t>::max() ||
      h.height > std::numeric_limits<std::uint32_t>::max())
    throw bad("WIDTH or HEIGHT exceeds 2^32 - 1");
  return h;
}

/// Decompresses LZF data (the format of liblzf, which PCD's binary_compressed uses)
/// into exactly out.size() bytes; false if the data is malformed or of another size.
bool lzfDecompress(const std::vector<std::uint8_t>& in, std::vector<std::uint8_t>& out)
{
  std::size_t ip = 0, op = 0;
  while (ip < in.size()) {
    std::size_t ctrl = in[ip++];
    if (ctrl < 32) { // a literal run of ctrl + 1 bytes
      const std::size_t n = ctrl + 1;
      if (n > in.size() - ip || n > out.size() - op)
        return false;
      std::memcpy(out.data() + op, in.data() + ip, n);
      ip += n;
      op += n;
    } else { // a back reference: len + 2 bytes from distance back
      std::size_t len = ctrl >> 5;
      if (len == 7) {
        if (ip >= in.size())
          return false;
        len += in[ip++];
      }
      if (ip >= in.size())
        return false;
      const std::size_t distance = ((ctrl & 0x1f) << 8) + in[ip++] + 1;
      len += 2;
      if (distance > op || len > out.size() - op)
        return false;
      for (std::size_t k = 0; k < len; ++k, ++op) // overlapping copies repeat bytes
        out[op] = out[op - distance];
    }
  }
  return op == out.size();
}

/// One value of ASCII PCD data; true if the token is a number (nan and inf included).
bool parseAsciiValue(std::string_view token, const PcdField& f, double& v)
{
  if (!token.empty() && token.front() == '+')
    token.remove_prefix(1);
  const auto r = std::from_chars(token.data(), token.data() + token.size(), v);
  if (r.ec != std::errc() || r.ptr != token.data() + token.size())
    return false;
  return f.type == 'F' || v == std::floor(v);
}

template <typename PointT>
void readPcdAscii(const std::string& path, std::ifstream& in, const PcdHeader& h,
                  CloudFiller<PointT>& filler)
{
  // Where each field's values start in a line. Nothing is sized by the header's counts
  // (up to 65536 per field): a line's values are held once the line has them all.
  std::vector<std::size_t> first_value(h.fields.size());
  for (std::size_t f = 1; f < h.fields.size(); ++f)
    first_value[f] = first_value[f - 1] + h.fields[f - 1].count;
  std::string line;
  std::vector<std::string_view> tokens;
  std::vector<double> values;
  std::uint64_t point = 0;
  for (std::uint64_t n = 1; std::getline(in, line); ++n) {
    tokens.clear();
    for (std::size_t at = line.find_first_not_of(" \t\r"); at != std::string::npos;) {
      const std::size_t end = std::min(line.find_first_of(" \t\r", at), line.size());
      tokens.emplace_back(line.data() + at, end - at);
      at = line.find_first_not_of(" \t\r", end);
    }
    if (tokens.empty())
      continue;
    auto fail = [&](const std::string& why) {
      throw FormatError(detail::where(path) + "line " + std::to_string(n) +
                        " of the ASCII data: " + why);
    };
    if (point == h.points)
      fail("more data lines than the " + std::to_string(h.points) + " POINTS");
    if (tokens.size() != h.values)
      fail(std::to_string(tokens.size()) + " values, expected " +
           std::to_string(h.values));
    values.resize(tokens.size());
    for (std::size_t t = 0, field = 0; t < tokens.size(); ++t) {
      while (field + 1 < first_value.size() && first_value[field + 1] <= t)
        ++field;
      const PcdField& f = h.fields[field];
      if (!parseAsciiValue(tokens[t], f, values[t])) {
        std::string shown(tokens[t].substr(0, 32));
        for (char& c : shown)
          if (!std::isprint(static_cast<unsigned char>(c)))
            c = '?';
        fail("'" + shown + "' is not a" + (f.type == 'F' ? " number" : " whole number") +
             " (field '" + f.name + "')");
      }
    }
    auto value = [&](int field) {
      return values[first_value[static_cast<std::size_t>(field)]];
    };
    filler.set(static_cast<std::size_t>(point++),
               {value(h.x), value(h.y), value(h.z), h.label >= 0 ? value(h.label) : 0.0});
  }
  if (point < h.points)
    throw FormatError(detail::where(path) + "truncated: " + std::to_string(point) +
                      " data lines of " + std::to_string(h.points) + " POINTS");
}

/// Binary data: one record of point_size bytes per point, in order.
template <typename PointT>
void readPcdBinary(const std::string& path, std::ifstream& in, const PcdHeader& h,
                   CloudFiller<PointT>& filler)
{
  const std::uint64_t per_block = std::max<std::uint64_t>(1, (1 << 20) / h.point_size);
  std::vector<std::uint8_t> block;
  for (std::uint64_t first = 0; first < h.points; first += per_block) {
    const std::uint64_t n = std::min(per_block, h.points - first);
    block.resize(static_cast<std::size_t>(n * h.point_size));
    if (!in.read(reinterpret_cast<char*>(block.data()),
                 static_cast<std::streamsize>(block.size())))
      throw FormatError(detail::where(path) + "truncated binary data");
    for (std::uint64_t i = 0; i < n; ++i) {
      const std::uint8_t* record = block.data() + i * h.point_size;
      auto value = [&](int field) {
        const PcdField& f = h.fields[static_cast<std::size_t>(field)];
        return f.decode(record + f.offset);
      };
      filler.set(
          static_cast<std::size_t>(first + i),
          {value(h.x), value(h.y), value(h.z), h.label >= 0 ? value(h.label) : 0.0});
    }
  }
}

/// binary_compressed: the compressed and the uncompressed size (uint32 each), then LZF
/// data that expands to each field's values for all points in turn (field after field).
template <typename PointT>
void readPcdCompressed(const std::string& path, std::ifstream& in, const PcdHeader& h,
                       CloudFiller<PointT>& filler)
{
  // The sizes were checked with the header (readPcdHeader).
  std::uint8_t sizes[8];
  in.read(reinterpret_cast<char*>(sizes), 8);
  const std::uint32_t compressed = littleEndianU32(sizes),
                      uncompressed = littleEndianU32(sizes + 4);
  std::vector<std::uint8_t> packed(static_cast<std::size_t>(compressed));
  std::vector<std::uint8_t> data(static_cast<std::size_t>(uncompressed));
  if (!in.read(reinterpret_cast<char*>(packed.data()),
               static_cast<std::streamsize>(packed.size())) ||
      !lzfDecompress(packed, data))
    throw FormatError(detail::where(path) + "malformed compressed data");
  packed = {};
  auto value = [&](int field, std::uint64_t i) {
    const PcdField& f = h.fields[static_cast<std::size_t>(field)];
    // Field f's values start after the values of the fields before it, for all points.
    const std::uint64_t start = h.points * f.offset;
    return f.decode(data.data() + start + i * f.size * f.count);
  };
  for (std::uint64_t i = 0; i < h.points; ++i)
    filler.set(static_cast<std::size_t>(i), {value(h.x, i), value(h.y, i), value(h.z, i),
                                             h.label >= 0 ? value(h.label, i) : 0.0});
}

template <typename PointT>
void readPcd(const std::string& path, const InputLimits& limits,
             pcl::PointCloud<PointT>& cloud)
{
  std::ifstream in(path, std::ios::binary);
  const PcdHeader h = readPcdHeader(path, in, limits);
  CloudFiller<PointT> filler(path, cloud);
  filler.resize(h.width, h.height);
  if (h.data == "ascii")
    readPcdAscii(path, in, h, filler);
  else if (h.data == "binary")
    readPcdBinary(path, in, h, filler);
  else
    readPcdCompressed(path, in, h, filler);
}

// ---- PLY ------------------------------------------------------------------------------

/// A PLY cloud: the points of the vertex element (elements before it are skipped, those
/// after it ignored); x, y, z and label must be scalar properties of any type.
template <typename PointT>
void readPly(const std::string& path, const InputLimits& limits,
             pcl::PointCloud<PointT>& cloud)
{
  std::ifstream in(path, std::ios::binary);
  const detail::PlyHeader header = detail::readPlyHeader(path, in);
  const detail::PlyElement* vertex = detail::findElement(header, "vertex");
  if (!vertex)
    throw FormatError(detail::where(path) + "no vertex element");
  detail::checkLimit(path, vertex->count, "points", limits.max_points, "max_points");
  if (vertex->count > std::numeric_limits<std::uint32_t>::max())
    throw FormatError(detail::where(path) + "more than 2^32 - 1 vertices");
  // The role of each vertex property: 0..2 x, y, z, 3 label, -1 skipped.
  std::vector<int> roles(vertex->properties.size(), -1);
  const char* const kNames[] = {"x", "y", "z", "label"};
  for (int role = 0; role < 4; ++role) {
    const auto& ps = vertex->properties;
    const auto it = std::find_if(ps.begin(), ps.end(), [&](const detail::PlyProperty& p) {
      return p.name == kNames[role];
    });
    if (it == ps.end()) {
      if (role < 3)
        throw missingAxis(path, kNames[role]);
      continue;
    }
    if (it->is_list)
      throw FormatError(detail::where(path) + "vertex property '" + it->name +
                        "' is a list; it must be one value");
    roles[static_cast<std::size_t>(it - ps.begin())] = role;
  }
  detail::checkPlyBodySize(path, in, header);
  detail::PlyBody body(path, in, header.format);
  for (const detail::PlyElement& e : header.elements) {
    if (&e != vertex) {
      for (std::uint64_t k = 0; k < e.count; ++k)
        for (const auto& p : e.properties)
          body.skip(p, "element data");
      continue;
    }
    CloudFiller<PointT> filler(path, cloud);
    filler.resize(e.count, 1);
    for (std::uint64_t i = 0; i < e.count; ++i) {
      double v[4] = {0.0, 0.0, 0.0, 0.0};
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        if (roles[k] < 0)
          body.skip(e.properties[k], "vertex data");
        else
          v[roles[k]] = body.read(e.properties[k].type, "vertex data");
      }
      filler.set(static_cast<std::size_t>(i), {v[0], v[1], v[2], v[3]});
    }
    return;
  }
}

template <typename PointT>
void load(const std::string& path, pcl::PointCloud<PointT>& cloud,
          const InputLimits& limits)
{
  const std::string ext = extensionOf(path);
  if (ext != ".pcd" && ext != ".ply")
    throw FormatError(detail::where(path) + "unknown point cloud extension '" + ext +
                      "' (" + kCloudExtensions + ")");
  requireRegularFile(path);
  detail::checkFileSize(path, limits);
  // Into a new cloud: the caller's is left as it was if the file is refused.
  pcl::PointCloud<PointT> read;
  if (ext == ".pcd")
    readPcd(path, limits, read);
  else
    readPly(path, limits, read);
  cloud = std::move(read);
}

/// Appends the little-endian bytes of v.
template <typename T>
void putLittleEndian(std::string& out, T v)
{
  std::uint8_t bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));
  if (!detail::hostIsLittleEndian())
    std::reverse(bytes, bytes + sizeof(T));
  out.append(reinterpret_cast<const char*>(bytes), sizeof(T));
}

/// Appends the shortest text that reads back as exactly v; NaN as "nan" (what PCL's
/// readers take), whatever its sign bit.
void putText(std::string& out, float v)
{
  if (std::isnan(v)) {
    out += "nan";
    return;
  }
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);
  out.append(buf, r.ptr);
}

/// Writes a file: the header, then x y z (float) and, for XYZL, label (uint) of each
/// point, little-endian binary or one text line a point (the same layout in PCD and
/// PLY).
template <typename PointT>
void writeCloudFile(const std::string& path, const std::string& header,
                    const pcl::PointCloud<PointT>& cloud, bool binary)
{
  AtomicFile file(path); // a failed write leaves the previous file whole
  std::ostream& out = file.stream();
  out << header;
  std::string block;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const PointT& p = cloud[i];
    if (binary) {
      putLittleEndian(block, p.x);
      putLittleEndian(block, p.y);
      putLittleEndian(block, p.z);
      if constexpr (std::is_same_v<PointT, pcl::PointXYZL>)
        putLittleEndian(block, static_cast<std::uint32_t>(p.label));
    } else {
      putText(block, p.x);
      block += ' ';
      putText(block, p.y);
      block += ' ';
      putText(block, p.z);
      if constexpr (std::is_same_v<PointT, pcl::PointXYZL>)
        block += ' ' + std::to_string(p.label);
      block += '\n';
    }
    if (block.size() >= (1u << 20) || i + 1 == cloud.size()) {
      out.write(block.data(), static_cast<std::streamsize>(block.size()));
      block.clear();
    }
  }
  file.commit();
}

/// A PLY header of one vertex element, nothing else (PCL 1.13's PLYWriter ignores the
/// precision of ASCII files and adds camera and face elements other tools do not
/// expect).
template <typename PointT>
std::string plyHeader(const pcl::PointCloud<PointT>& cloud, bool binary)
{
  constexpr bool kLabel = std::is_same_v<PointT, pcl::PointXYZL>;
  std::ostringstream h;
  h << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\n"
    << "comment written by plantnbv\n"
    << "element vertex " << cloud.size() << "\n"
    << "property float x\nproperty float y\nproperty float z\n"
    << (kLabel ? "property uint label\n" : "") << "end_header\n";
  return h.str();
}

/// A PCD header; organized clouds keep their width and height.
template <typename PointT>
std::string pcdHeader(const pcl::PointCloud<PointT>& cloud, bool binary)
{
  constexpr bool kLabel = std::is_same_v<PointT, pcl::PointXYZL>;
  const bool organized =
      cloud.height > 1 && std::uint64_t{cloud.width} * cloud.height == cloud.size();
  std::ostringstream h;
  h << "# .PCD v0.7 - Point Cloud Data file format, written by plantnbv\n"
    << "VERSION 0.7\nFIELDS x y z" << (kLabel ? " label" : "") << "\nSIZE 4 4 4"
    << (kLabel ? " 4" : "") << "\nTYPE F F F" << (kLabel ? " U" : "") << "\nCOUNT 1 1 1"
    << (kLabel ? " 1" : "") << "\nWIDTH " << (organized ? cloud.width : cloud.size())
    << "\nHEIGHT " << (organized ? cloud.height : 1)
    << "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << cloud.size() << "\nDATA "
    << (binary ? "binary" : "ascii") << "\n";
  return h.str();
}

template <typename PointT>
void save(const std::string& path, const pcl::PointCloud<PointT>& cloud, bool binary)
{
  const std::string ext = extensionOf(path);
  if (ext != ".pcd" && ext != ".ply")
    throw FormatError(detail::where(path) + "unknown point cloud extension '" + ext +
                      "' (" + kCloudExtensions + ")");
  writeCloudFile(path,
                 ext == ".ply" ? plyHeader(cloud, binary) : pcdHeader(cloud, binary),
                 cloud, binary);
}

} // namespace

void loadCloud(const std::string& path, CloudXYZ& cloud)
{
  loadCloud(path, cloud, defaultInputLimits());
}

void loadCloud(const std::string& path, CloudXYZL& cloud)
{
  loadCloud(path, cloud, defaultInputLimits());
}

void loadCloud(const std::string& path, CloudXYZ& cloud, const InputLimits& limits)
{
  load(path, cloud, limits);
}

void loadCloud(const std::string& path, CloudXYZL& cloud, const InputLimits& limits)
{
  load(path, cloud, limits);
}

void saveCloud(const std::string& path, const CloudXYZ& cloud, bool binary)
{
  save(path, cloud, binary);
}

void saveCloud(const std::string& path, const CloudXYZL& cloud, bool binary)
{
  save(path, cloud, binary);
}

} // namespace io
} // namespace plantnbv
