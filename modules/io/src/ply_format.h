#pragma once
// The PLY header, shared by our mesh reader and the header checks of the cloud reader
// (internal, not installed).

#include <cstdint>
#include <istream>
#include <string>
#include <vector>

namespace plantnbv {
namespace io {
namespace detail {

enum class PlyFormat { ascii, binary_le, binary_be };
enum class PlyType { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::float32; // of the values (list items for a list)
  bool is_list = false;
  PlyType count_type = PlyType::uint8;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

/// Bytes of one binary value.
inline std::size_t sizeOf(PlyType t)
{
  switch (t) {
  case PlyType::int8:
  case PlyType::uint8:
    return 1;
  case PlyType::int16:
  case PlyType::uint16:
    return 2;
  case PlyType::int32:
  case PlyType::uint32:
  case PlyType::float32:
    return 4;
  case PlyType::float64:
    return 8;
  }
  return 0;
}

inline bool isInteger(PlyType t)
{
  return t != PlyType::float32 && t != PlyType::float64;
}

struct PlyHeader {
  PlyFormat format = PlyFormat::ascii;
  std::vector<PlyElement> elements;
};

/// Reads the header up to and including "end_header"; `in` is left at the body.
/// \throws FormatError naming what is wrong.
PlyHeader readPlyHeader(const std::string& path, std::istream& in);

/// Throws FormatError if the body, from the current position of `in` to the end of the
/// file, is too short for the element counts of the header (checked before anything is
/// allocated for them).
void checkPlyBodySize(const std::string& path, std::istream& in, const PlyHeader& header);

/// The element named `name`, or nullptr.
const PlyElement* findElement(const PlyHeader& header, const std::string& name);

} // namespace detail
} // namespace io
} // namespace plantnbv
