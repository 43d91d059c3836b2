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

#include <pcl/PCLPointCloud2.h>
#include <pcl/conversions.h>
#include <pcl/exceptions.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/io/cloud_io.h>
#include <plantnbv/io/file_kind.h>

#include "io_util.h"
#include "ply_format.h"

namespace plantnbv {
namespace io {

namespace {

const char* const kCloudExtensions = "expected .pcd or .ply";

/// One field of the PCL blob, or none (offset < 0).
struct FieldRef {
  std::int64_t offset = -1;
  std::uint8_t datatype = 0;
  bool found() const { return offset >= 0; }
};

FieldRef findField(const pcl::PCLPointCloud2& blob, const char* name)
{
  for (const auto& f : blob.fields)
    if (f.name == name && f.count >= 1)
      return {static_cast<std::int64_t>(f.offset), f.datatype};
  return {};
}

template <typename T>
double readAs(const std::uint8_t* p)
{
  T v;
  std::memcpy(&v, p, sizeof(T));
  return static_cast<double>(v);
}

/// The value of a field of any PCL datatype, as a double (exact for all but 64-bit
/// integers beyond 2^53, which no coordinate or label uses).
double fieldValue(const std::uint8_t* point, const FieldRef& f)
{
  const std::uint8_t* p = point + f.offset;
  switch (f.datatype) {
  case pcl::PCLPointField::INT8:
    return readAs<std::int8_t>(p);
  case pcl::PCLPointField::UINT8:
  case pcl::PCLPointField::BOOL:
    return readAs<std::uint8_t>(p);
  case pcl::PCLPointField::INT16:
    return readAs<std::int16_t>(p);
  case pcl::PCLPointField::UINT16:
    return readAs<std::uint16_t>(p);
  case pcl::PCLPointField::INT32:
    return readAs<std::int32_t>(p);
  case pcl::PCLPointField::UINT32:
    return readAs<std::uint32_t>(p);
  case pcl::PCLPointField::INT64:
    return readAs<std::int64_t>(p);
  case pcl::PCLPointField::UINT64:
    return readAs<std::uint64_t>(p);
  case pcl::PCLPointField::FLOAT32:
    return readAs<float>(p);
  case pcl::PCLPointField::FLOAT64:
    return readAs<double>(p);
  default:
    return std::numeric_limits<double>::quiet_NaN();
  }
}

/// a * b, or false when it overflows 64 bits.
bool multiply(std::uint64_t a, std::uint64_t b, std::uint64_t& product)
{
  return !__builtin_mul_overflow(a, b, &product);
}

/// Checks that each line of ASCII PCD data starts like a number (or nan, inf): PCL 1.13
/// reads a data line that starts with FIELDS or COLUMNS as a header line and then
/// writes past its buffers (found by fuzzing).
void checkPcdAsciiLines(const std::string& path, std::istream& in)
{
  std::string line;
  for (std::uint64_t n = 1; std::getline(in, line); ++n) {
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first != std::string::npos &&
        std::string("0123456789+-.nNiI").find(line[first]) == std::string::npos) {
      std::string shown = line.substr(first, 32);
      for (char& c : shown)
        if (!std::isprint(static_cast<unsigned char>(c)))
          c = '?';
      throw FormatError(detail::where(path) + "line " + std::to_string(n) +
                        " of the ASCII data does not start with a number: '" + shown +
                        "'");
    }
  }
}

/// PCL 1.13 goes on reading header lines after DATA until it meets a line that is not
/// one (empty lines skipped): data whose first line starts like a header line (FIELDS,
/// POINTS, DATA, ... even in binary data) changes the layout PCL reads the data with;
/// FIELDS there made it write past its buffers (found by fuzzing). `in` is at the data.
void checkPcdDataStart(const std::string& path, std::istream& in)
{
  static const char* const kHeaderWords[] = {"#",      "VERSION",   "FIELDS", "COLUMNS",
                                             "SIZE",   "TYPE",      "COUNT",  "WIDTH",
                                             "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
  std::string word;
  for (int c; (c = in.get()) != std::istream::traits_type::eof();) {
    if (c == '\n' && word.empty())
      continue; // a blank line: PCL skips an empty one, and stops at one of blanks
    if (word.empty() && (c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'))
      continue;
    if (c == '\n' || word.size() == 9)
      break;
    word += static_cast<char>(c);
  }
  for (const char* header_word : kHeaderWords)
    if (word.rfind(header_word, 0) == 0)
      throw FormatError(detail::where(path) + "the data starts with '" + header_word +
                        "', which PCL would read as a header line");
}

/// Checks a PCD header and that the file is long enough for its data. PCL 1.13's
/// PCDReader crashes on some malformed files (e.g. text without a DATA line) and
/// allocates for the declared point count before it reads any point, so it only gets
/// files that pass.
void checkPcd(const std::string& path, const InputLimits& limits)
{
  std::ifstream in(path, std::ios::binary);
  auto bad = [&](const std::string& why) {
    return FormatError(detail::where(path) + "bad PCD header: " + why);
  };
  std::size_t fields = 0;
  std::vector<std::uint64_t> sizes, counts;
  std::string types, data;
  std::uint64_t width = 0, height = 1, points = 0;
  bool have_width = false, have_points = false, have_types = false;
  std::string line;
  while (data.empty()) {
    const bool starts_with_cr = in.peek() == '\r'; // readHeaderLine drops a final \r
    if (!detail::readHeaderLine(path, in, line))
      throw bad("no DATA line (not a PCD file?)");
    // PCL 1.13 dereferences a null pointer on a header line of blanks only, "\r" (an
    // empty line of a Windows file) included (found by fuzzing), and reads a line that
    // starts with a blank differently from us.
    if (starts_with_cr ||
        (!line.empty() && std::isspace(static_cast<unsigned char>(line[0]))))
      throw bad("a line starts with a blank");
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
    if (key == "FIELDS")
      fields = values.size();
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
      width = number(values[0]);
      have_width = true;
    } else if (key == "HEIGHT" && values.size() == 1)
      height = number(values[0]);
    else if (key == "POINTS" && values.size() == 1) {
      points = number(values[0]);
      have_points = true;
    } else if (key == "DATA" && values.size() == 1)
      data = values[0];
    else
      throw bad("unexpected line '" + line + "'");
  }
  if (fields == 0 || sizes.size() != fields || !have_types || types.size() != fields ||
      (!counts.empty() && counts.size() != fields))
    throw bad("FIELDS, SIZE, TYPE and COUNT must list the same number of fields");
  if (types.find_first_not_of("IUF") != std::string::npos)
    throw bad("TYPE must be I, U or F");
  if (!have_width)
    throw bad("no WIDTH");
  std::uint64_t width_x_height = 0;
  if (!multiply(width, height, width_x_height))
    throw bad("WIDTH x HEIGHT overflows");
  if (!have_points)
    points = width_x_height;
  detail::checkLimit(path, std::max(points, width_x_height), "points", limits.max_points,
                     "max_points");
  if (data != "ascii" && data != "binary" && data != "binary_compressed")
    throw bad("DATA must be ascii, binary or binary_compressed, got '" + data + "'");
  // Sizes are those of I, U and F values; counts as large as PCL's widest descriptors
  // (e.g. ESF, 640 values) with room to spare.
  constexpr std::uint64_t kMaxCount = 1 << 16;
  std::uint64_t point_size = 0, values = 0;
  for (std::size_t i = 0; i < fields; ++i) {
    const std::uint64_t count = counts.empty() ? 1 : counts[i];
    if (sizes[i] != 1 && sizes[i] != 2 && sizes[i] != 4 && sizes[i] != 8)
      throw bad("SIZE " + std::to_string(sizes[i]) + " is not 1, 2, 4 or 8");
    if (types[i] == 'F' && sizes[i] != 4 && sizes[i] != 8)
      throw bad("SIZE " + std::to_string(sizes[i]) + " of an F field is not 4 or 8");
    if (count < 1 || count > kMaxCount)
      throw bad("COUNT " + std::to_string(count) + " is not in 1.." +
                std::to_string(kMaxCount));
    point_size += sizes[i] * count;
    values += count;
  }
  const auto body = static_cast<std::uint64_t>(in.tellg());
  const std::uint64_t file_size = std::filesystem::file_size(path);
  if (!in || body > file_size)
    throw IoError(detail::where(path) + "cannot determine the file size");
  const std::uint64_t left = file_size - body;
  auto truncated = [&](const std::string& need) {
    return FormatError(detail::where(path) + "truncated: " + std::to_string(points) +
                       " points need " + need + ", more than the " +
                       std::to_string(left) + " bytes left");
  };
  // ASCII: each value takes at least one character and a separator.
  if (data == "ascii" && points > (left + 1) / (2 * values))
    throw truncated("at least " + std::to_string(2 * values) + " bytes each");
  if (data == "binary" && left / point_size < points)
    throw truncated(std::to_string(point_size) + " bytes each");
  if (data == "binary_compressed") {
    std::uint32_t sizes_of_block[2] = {0, 0}; // compressed, uncompressed
    std::uint64_t bytes = 0;
    // LZF expands 3 bytes into at most 264: a larger ratio cannot be real data.
    if (!in.read(reinterpret_cast<char*>(sizes_of_block), 8) ||
        sizes_of_block[0] > left - std::min<std::uint64_t>(left, 8) ||
        !multiply(points, point_size, bytes) || sizes_of_block[1] != bytes ||
        bytes > 88 * std::uint64_t{sizes_of_block[0]} + 8)
      throw FormatError(detail::where(path) +
                        "truncated or inconsistent compressed data");
  }
  in.clear();
  in.seekg(static_cast<std::streamoff>(body));
  checkPcdDataStart(path, in);
  if (data == "ascii") {
    in.clear();
    in.seekg(static_cast<std::streamoff>(body));
    checkPcdAsciiLines(path, in);
  }
}

/// PCL 1.13 packs uchar red, green and blue (or diffuse_red, ...) into one rgb field as
/// it reads them, and abort()s (an assert) on any other arrangement, e.g. green without
/// red (found by fuzzing). Accepts what it reads: no colour, or one red-green-blue run,
/// optionally followed at once by alpha.
void checkPlyColours(const std::string& path, const detail::PlyElement& vertex)
{
  auto role = [](const detail::PlyProperty& p) {
    if (p.type != detail::PlyType::uint8)
      return -1;
    for (const char* prefix : {"", "diffuse_"}) {
      const std::string base(prefix);
      if (p.name == base + "red")
        return 0;
      if (p.name == base + "green")
        return 1;
      if (p.name == base + "blue")
        return 2;
    }
    return p.name == "alpha" ? 3 : -1;
  };
  int previous = -1; // the role of the previous property
  bool have_rgb = false;
  for (const detail::PlyProperty& p : vertex.properties) {
    const int r = role(p);
    const bool ok = r == -1   ? previous != 0 && previous != 1
                    : r == 0  ? !have_rgb
                    : r == 3  ? previous == 2
                              : previous == r - 1;
    if (!ok)
      throw FormatError(detail::where(path) + "vertex colour properties must be uchar "
                        "red, green, blue in that order, alpha only right after blue (at '" +
                        p.name + "')");
    have_rgb = have_rgb || r == 0;
    previous = r;
  }
  if (previous == 0 || previous == 1)
    throw FormatError(detail::where(path) + "vertex colour properties must be uchar red, "
                      "green, blue in that order (no blue after '" +
                      vertex.properties.back().name + "')");
}

/// Checks a PLY header: a vertex element of scalar properties within the limits, and a
/// body long enough for its counts.
void checkPly(const std::string& path, const InputLimits& limits)
{
  std::ifstream in(path, std::ios::binary);
  const detail::PlyHeader header = detail::readPlyHeader(path, in);
  const detail::PlyElement* vertex = detail::findElement(header, "vertex");
  if (!vertex)
    throw FormatError(detail::where(path) + "no vertex element");
  detail::checkLimit(path, vertex->count, "points", limits.max_points, "max_points");
  // PCL 1.13 sizes a vertex list by the first vertex's and abort()s on a longer one
  // (found by fuzzing).
  for (const detail::PlyProperty& p : vertex->properties)
    if (p.is_list)
      throw FormatError(detail::where(path) + "vertex property '" + p.name +
                        "' is a list; a point cloud's vertex properties must be scalars");
  checkPlyColours(path, *vertex);
  detail::checkPlyBodySize(path, in, header);
}

/// Reads the file into a blob with PCL's readers; checks that x, y and z exist.
pcl::PCLPointCloud2 readBlob(const std::string& path, const InputLimits& limits)
{
  const std::string ext = extensionOf(path);
  if (ext != ".pcd" && ext != ".ply")
    throw FormatError(detail::where(path) + "unknown point cloud extension '" + ext +
                      "' (" + kCloudExtensions + ")");
  detail::requireReadableFile(path);
  detail::checkFileSize(path, limits);
  if (ext == ".pcd")
    checkPcd(path, limits);
  else
    checkPly(path, limits);
  pcl::PCLPointCloud2 blob;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  int status = -1;
  // PCL reports the details of a failure on the console; we add a one-line summary.
  try {
    if (ext == ".pcd") {
      pcl::PCDReader reader;
      int version = 0;
      status = reader.read(path, blob, origin, orientation, version);
    } else {
      pcl::PLYReader reader;
      int version = 0;
      status = reader.read(path, blob, origin, orientation, version);
    }
  } catch (const std::exception& e) {
    throw FormatError(detail::where(path) + "cannot be parsed as " + ext.substr(1) +
                      ": " + e.what());
  }
  if (status < 0)
    throw FormatError(detail::where(path) + "cannot be parsed as a " + ext.substr(1) +
                      " point cloud (PCL reader error " + std::to_string(status) + ")");
  for (const char* axis : {"x", "y", "z"})
    if (!findField(blob, axis).found())
      throw FormatError(detail::where(path) + "has no '" + axis +
                        "' field (a point cloud needs x, y and z)");
  const std::uint64_t points = std::uint64_t{blob.width} * blob.height;
  if (blob.data.size() < points * blob.point_step ||
      (blob.height > 1 && blob.row_step < std::uint64_t{blob.width} * blob.point_step))
    throw FormatError(detail::where(path) + "holds less data than its header declares");
  return blob;
}

/// Copies x, y, z (and label) out of the blob whatever their stored types: PCL's own
/// fromPCLPointCloud2 silently leaves zeros where a type differs (e.g. double x).
template <typename PointT>
void fromBlob(const std::string& path, const pcl::PCLPointCloud2& blob,
              pcl::PointCloud<PointT>& cloud, bool with_label)
{
  const FieldRef fx = findField(blob, "x"), fy = findField(blob, "y"),
                 fz = findField(blob, "z");
  const FieldRef fl = with_label ? findField(blob, "label") : FieldRef{};
  cloud.width = blob.width;
  cloud.height = blob.height;
  cloud.header.frame_id = blob.header.frame_id;
  cloud.points.resize(std::size_t{blob.width} * blob.height);
  // From the points, not the file's word: PCL's filters skip their finiteness checks
  // on a dense cloud, and NaNs must never reach OctoMap.
  bool dense = true;
  std::size_t i = 0;
  for (std::uint32_t row = 0; row < blob.height; ++row)
    for (std::uint32_t col = 0; col < blob.width; ++col, ++i) {
      const std::uint8_t* p = blob.data.data() + std::size_t{row} * blob.row_step +
                              std::size_t{col} * blob.point_step;
      PointT& q = cloud.points[i];
      q.x = static_cast<float>(fieldValue(p, fx));
      q.y = static_cast<float>(fieldValue(p, fy));
      q.z = static_cast<float>(fieldValue(p, fz));
      dense = dense && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
      if constexpr (std::is_same_v<PointT, pcl::PointXYZL>) {
        q.label = 0;
        if (fl.found()) {
          const double label = fieldValue(p, fl);
          if (!(label >= 0.0 && label <= 4294967295.0 && label == std::floor(label)))
            throw FormatError(detail::where(path) + "point " + std::to_string(i) +
                              " has label " + std::to_string(label) +
                              ", expected a non-negative whole number");
          q.label = static_cast<std::uint32_t>(label);
        }
      }
    }
  cloud.is_dense = dense;
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

/// Appends the shortest text that reads back as exactly v.
void putText(std::string& out, float v)
{
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);
  out.append(buf, r.ptr);
}

/// Our PLY cloud writer: PCL 1.13's PLYWriter ignores the precision of ASCII files (6
/// digits) and adds camera and face elements that other tools do not expect.
template <typename PointT>
void writePly(const std::string& path, const pcl::PointCloud<PointT>& cloud, bool binary)
{
  constexpr bool kLabel = std::is_same_v<PointT, pcl::PointXYZL>;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out)
    throw IoError(detail::where(path) + "cannot open for writing");
  out << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\n"
      << "comment written by plantnbv\n"
      << "element vertex " << cloud.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\n"
      << (kLabel ? "property uint label\n" : "") << "end_header\n";
  std::string block;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const PointT& p = cloud[i];
    if (binary) {
      putLittleEndian(block, p.x);
      putLittleEndian(block, p.y);
      putLittleEndian(block, p.z);
      if constexpr (kLabel)
        putLittleEndian(block, static_cast<std::uint32_t>(p.label));
    } else {
      putText(block, p.x);
      block += ' ';
      putText(block, p.y);
      block += ' ';
      putText(block, p.z);
      if constexpr (kLabel)
        block += ' ' + std::to_string(p.label);
      block += '\n';
    }
    if (block.size() >= (1u << 20) || i + 1 == cloud.size()) {
      out.write(block.data(), static_cast<std::streamsize>(block.size()));
      block.clear();
    }
  }
  out.close();
  if (!out)
    throw IoError(detail::where(path) + "write error");
}

template <typename PointT>
void save(const std::string& path, const pcl::PointCloud<PointT>& cloud, bool binary)
{
  const std::string ext = extensionOf(path);
  if (ext != ".pcd" && ext != ".ply")
    throw FormatError(detail::where(path) + "unknown point cloud extension '" + ext +
                      "' (" + kCloudExtensions + ")");
  if (ext == ".ply") {
    writePly(path, cloud, binary);
    return;
  }
  // PCL reports a file it cannot open only as an error code.
  {
    std::ofstream probe(path, std::ios::binary | std::ios::app);
    if (!probe)
      throw IoError(detail::where(path) + "cannot open for writing");
  }
  pcl::PCLPointCloud2 blob;
  pcl::toPCLPointCloud2(cloud, blob);
  // 9 significant digits: every float reads back exactly from ASCII.
  constexpr int kFloatDigits = std::numeric_limits<float>::max_digits10;
  pcl::PCDWriter writer;
  int status = -1;
  try {
    status = binary ? writer.writeBinary(path, blob, Eigen::Vector4f::Zero(),
                                         Eigen::Quaternionf::Identity())
                    : writer.writeASCII(path, blob, Eigen::Vector4f::Zero(),
                                        Eigen::Quaternionf::Identity(), kFloatDigits);
  } catch (const std::exception& e) {
    throw IoError(detail::where(path) + "cannot be written: " + e.what());
  }
  if (status < 0)
    throw IoError(detail::where(path) + "cannot be written (PCL writer error " +
                  std::to_string(status) + ")");
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
  fromBlob(path, readBlob(path, limits), cloud, false);
}

void loadCloud(const std::string& path, CloudXYZL& cloud, const InputLimits& limits)
{
  fromBlob(path, readBlob(path, limits), cloud, true);
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
