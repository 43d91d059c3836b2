#include "ply_format.h"

#include <algorithm>
#include <sstream>

#include <plantnbv/common/error.h>

#include "io_util.h"

namespace plantnbv {
namespace io {
namespace detail {

namespace {

bool parseType(const std::string& s, PlyType& t)
{
  static const std::pair<const char*, PlyType> kNames[] = {
      {"char", PlyType::int8},      {"int8", PlyType::int8},
      {"uchar", PlyType::uint8},    {"uint8", PlyType::uint8},
      {"short", PlyType::int16},    {"int16", PlyType::int16},
      {"ushort", PlyType::uint16},  {"uint16", PlyType::uint16},
      {"int", PlyType::int32},      {"int32", PlyType::int32},
      {"uint", PlyType::uint32},    {"uint32", PlyType::uint32},
      {"float", PlyType::float32},  {"float32", PlyType::float32},
      {"double", PlyType::float64}, {"float64", PlyType::float64}};
  for (const auto& [name, type] : kNames)
    if (s == name) {
      t = type;
      return true;
    }
  return false;
}

/// The fewest bytes one instance of the element can take in the file body.
std::uint64_t minInstanceBytes(const PlyElement& e, PlyFormat format)
{
  std::uint64_t bytes = 0;
  for (const auto& p : e.properties)
    bytes += format == PlyFormat::ascii ? 2 : sizeOf(p.is_list ? p.count_type : p.type);
  return std::max<std::uint64_t>(bytes, 1);
}

} // namespace

PlyHeader readPlyHeader(const std::string& path, std::istream& in)
{
  PlyHeader h;
  std::string line;
  auto bad = [&](const std::string& why) {
    return FormatError(where(path) + "bad PLY header: " + why);
  };
  if (!readHeaderLine(path, in, line) || line != "ply")
    throw FormatError(where(path) + "not a PLY file (no 'ply' magic line)");
  bool have_format = false;
  for (int n = 0; n < 100000; ++n) {
    if (!readHeaderLine(path, in, line))
      throw bad("no 'end_header'");
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword.empty() || keyword == "comment" || keyword == "obj_info")
      continue;
    if (keyword == "end_header") {
      if (!have_format)
        throw bad("no 'format' line");
      return h;
    }
    if (keyword == "format") {
      std::string f;
      words >> f;
      if (f == "ascii")
        h.format = PlyFormat::ascii;
      else if (f == "binary_little_endian")
        h.format = PlyFormat::binary_le;
      else if (f == "binary_big_endian")
        h.format = PlyFormat::binary_be;
      else
        throw bad("unknown format '" + f + "'");
      have_format = true;
    } else if (keyword == "element") {
      PlyElement e;
      if (!(words >> e.name >> e.count))
        throw bad("malformed line '" + line + "'");
      h.elements.push_back(e);
    } else if (keyword == "property") {
      if (h.elements.empty())
        throw bad("property before any element: '" + line + "'");
      PlyProperty p;
      std::string type;
      words >> type;
      if (type == "list") {
        std::string count_type, item_type;
        words >> count_type >> item_type >> p.name;
        p.is_list = true;
        if (!parseType(count_type, p.count_type) || !parseType(item_type, p.type) ||
            !isInteger(p.count_type) || p.name.empty())
          throw bad("malformed line '" + line + "'");
      } else {
        words >> p.name;
        if (!parseType(type, p.type) || p.name.empty())
          throw bad("malformed line '" + line + "'");
      }
      h.elements.back().properties.push_back(p);
    } else
      throw bad("unknown keyword '" + keyword + "'");
  }
  throw bad("no 'end_header' in the first 100000 lines");
}

void checkPlyBodySize(const std::string& path, std::istream& in, const PlyHeader& header)
{
  const std::streampos body = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streampos end = in.tellg();
  in.seekg(body);
  if (body < 0 || end < 0 || !in)
    throw IoError(where(path) + "cannot determine the file size");
  const auto body_size = static_cast<std::uint64_t>(end - body);
  // + 1: the last ASCII value needs no separator after it.
  for (const auto& e : header.elements)
    if (e.count > (body_size + 1) / minInstanceBytes(e, header.format))
      throw FormatError(where(path) + "the header declares " + std::to_string(e.count) +
                        " " + e.name +
                        " elements but the file is too short to hold them");
}

const PlyElement* findElement(const PlyHeader& header, const std::string& name)
{
  for (const auto& e : header.elements)
    if (e.name == name)
      return &e;
  return nullptr;
}

} // namespace detail
} // namespace io
} // namespace plantnbv
