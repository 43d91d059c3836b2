#include "io_util.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include <plantnbv/common/error.h>

namespace plantnbv {
namespace io {
namespace detail {

void requireReadableFile(const std::string& path)
{
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status))
    throw IoError(where(path) + "no such file");
  if (std::filesystem::is_directory(status))
    throw IoError(where(path) + "is a directory, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw IoError(where(path) + "cannot open for reading");
}

std::string readFileToString(const std::string& path)
{
  requireReadableFile(path);
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

} // namespace detail
} // namespace io
} // namespace plantnbv
