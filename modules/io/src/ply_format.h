#pragma once
// The PLY header and a reader of the body, shared by our mesh and cloud readers
// (internal, not installed).

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <istream>
#include <string>
#include <vector>

#include <plantnbv/common/error.h>
#include <plantnbv/common/number_text.h>

#include "io_util.h"

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

/// Buffered reading of the PLY body, binary or ASCII.
class PlyBody {
public:
  PlyBody(const std::string& path, std::ifstream& in, PlyFormat format)
      : path_(path), in_(in), format_(format),
        swap_((format == PlyFormat::binary_le) != detail::hostIsLittleEndian()),
        buffer_(1 << 20)
  {
  }

  /// Reads one value of type t as a double (exact for every PLY type).
  double read(PlyType t, const char* what)
  {
    if (format_ == PlyFormat::ascii)
      return readAscii(t, what);
    std::uint8_t bytes[8];
    const std::size_t n = sizeOf(t);
    if (!readBytes(bytes, n))
      throw truncated(what);
    if (swap_)
      std::reverse(bytes, bytes + n);
    switch (t) {
    case PlyType::int8:
      return get<std::int8_t>(bytes);
    case PlyType::uint8:
      return get<std::uint8_t>(bytes);
    case PlyType::int16:
      return get<std::int16_t>(bytes);
    case PlyType::uint16:
      return get<std::uint16_t>(bytes);
    case PlyType::int32:
      return get<std::int32_t>(bytes);
    case PlyType::uint32:
      return get<std::uint32_t>(bytes);
    case PlyType::float32:
      return get<float>(bytes);
    case PlyType::float64:
      return get<double>(bytes);
    }
    return 0.0;
  }

  /// Reads a list length: a non-negative whole number.
  std::uint64_t readCount(PlyType t, const char* what)
  {
    // An ASCII count can be any whole number, 1e300 included: bounded before the cast.
    const double n = read(t, what);
    if (!(n >= 0.0 && n <= 4294967295.0 && n == std::floor(n)))
      throw FormatError(detail::where(path_) + what + ": invalid list length " +
                        shortestText(n));
    return static_cast<std::uint64_t>(n);
  }

  void skip(const PlyProperty& p, const char* what)
  {
    if (!p.is_list) {
      skipValues(p.type, 1, what);
      return;
    }
    skipValues(p.type, readCount(p.count_type, what), what);
  }

  FormatError truncated(const char* what) const
  {
    return FormatError(detail::where(path_) + "unexpected end of file in " + what);
  }

private:
  template <typename T>
  static double get(const std::uint8_t* bytes)
  {
    T v;
    std::memcpy(&v, bytes, sizeof(T));
    return static_cast<double>(v);
  }

  bool fill()
  {
    if (pos_ < end_)
      return true;
    in_.read(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    pos_ = 0;
    end_ = static_cast<std::size_t>(in_.gcount());
    return end_ > 0;
  }

  bool readBytes(std::uint8_t* dst, std::size_t n)
  {
    while (n > 0) {
      if (!fill())
        return false;
      const std::size_t k = std::min(n, end_ - pos_);
      std::memcpy(dst, buffer_.data() + pos_, k);
      pos_ += k;
      dst += k;
      n -= k;
    }
    return true;
  }

  void skipValues(PlyType t, std::uint64_t count, const char* what)
  {
    if (format_ == PlyFormat::ascii) {
      for (std::uint64_t i = 0; i < count; ++i)
        if (!nextToken())
          throw truncated(what);
      return;
    }
    std::uint64_t n = count * sizeOf(t);
    while (n > 0) {
      if (!fill())
        throw truncated(what);
      const std::size_t k =
          static_cast<std::size_t>(std::min<std::uint64_t>(n, end_ - pos_));
      pos_ += k;
      n -= k;
    }
  }

  /// The next whitespace-separated token into token_; false at the end of the file.
  bool nextToken()
  {
    token_.clear();
    while (fill()) {
      const char c = buffer_[pos_];
      if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
        ++pos_;
        if (!token_.empty())
          return true;
        continue;
      }
      token_ += c;
      ++pos_;
    }
    return !token_.empty();
  }

  double readAscii(PlyType t, const char* what)
  {
    if (!nextToken())
      throw truncated(what);
    double v = 0.0;
    const char* begin = token_.data();
    const char* end = begin + token_.size();
    if (*begin == '+')
      ++begin;
    const auto r = std::from_chars(begin, end, v);
    if (r.ec != std::errc() || r.ptr != end || (isInteger(t) && v != std::floor(v)))
      throw FormatError(detail::where(path_) + what + ": '" + token_ + "' is not a " +
                        (isInteger(t) ? "whole number" : "number"));
    return v;
  }

  const std::string& path_;
  std::ifstream& in_;
  PlyFormat format_;
  bool swap_;
  std::vector<char> buffer_;
  std::size_t pos_ = 0, end_ = 0;
  std::string token_;
};

} // namespace detail
} // namespace io
} // namespace plantnbv
