#include "io_util.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include <plantnbv/common/error.h>
#include <plantnbv/common/file_io.h>

namespace plantnbv {
namespace io {
namespace detail {

void checkFileSize(const std::string& path, const InputLimits& limits)
{
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec)
    throw IoError(where(path) + "cannot determine the file size");
  checkLimit(path, size, "bytes", limits.max_file_bytes, "max_file_bytes");
}

void checkLimit(const std::string& path, std::uint64_t count, const char* what,
                std::uint64_t cap, const char* cap_name)
{
  if (cap > 0 && count > cap)
    throw FormatError(where(path) + std::to_string(count) + " " + what +
                      " exceed the limit of " + std::to_string(cap) +
                      " (InputLimits::" + cap_name + ")");
}

std::string readFileToString(const std::string& path, const InputLimits& limits)
{
  requireRegularFile(path);
  checkFileSize(path, limits);
  std::ifstream in(path, std::ios::binary);
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad())
    throw IoError(where(path) + "read error");
  return content.str();
}

bool readHeaderLine(const std::string& path, std::istream& in, std::string& line)
{
  constexpr std::size_t kMaxLine = 4096;
  line.clear();
  std::istream::int_type c;
  bool any = false;
  while ((c = in.get()) != std::istream::traits_type::eof()) {
    any = true;
    if (c == '\n')
      break;
    if (line.size() >= kMaxLine)
      throw FormatError(where(path) + "header line longer than " +
                        std::to_string(kMaxLine) + " characters (not a text header)");
    line += static_cast<char>(c);
  }
  if (!line.empty() && line.back() == '\r')
    line.pop_back();
  return any;
}

bool hostIsLittleEndian()
{
  const std::uint16_t one = 1;
  std::uint8_t first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

Eigen::Matrix3d upToZ(Up up)
{
  Eigen::Matrix3d r;
  switch (up) {
  case Up::z:
    r.setIdentity();
    break;
  case Up::y:
    r << 1, 0, 0, //
        0, 0, -1, //
        0, 1, 0;
    break;
  case Up::x:
    r << 0, -1, 0, //
        0, 0, -1,  //
        1, 0, 0;
    break;
  }
  return r;
}

bool staysInside(const std::string& file)
{
  const std::filesystem::path p(file);
  if (p.is_absolute() || p.has_root_name())
    return false;
  for (const std::filesystem::path& part : p)
    if (part == "..")
      return false;
  return true;
}

} // namespace detail
} // namespace io
} // namespace plantnbv
