#pragma once
// Map files of the commands: the extension rule, checked before any work.

#include <string>

#include <plantnbv/common/error.h>
#include <plantnbv/io/file_kind.h>

namespace plantnbv {
namespace app {

/// Throws FormatError unless `path` ends in .ot or .bt; `what` names the option.
inline void requireMapExtension(const std::string& path, const char* what)
{
  const std::string ext = io::extensionOf(path);
  if (ext != ".ot" && ext != ".bt")
    throw FormatError(std::string(what) + " '" + path +
                      "': expected a .ot (log-odds) or .bt (occupied / free) map file");
}

} // namespace app
} // namespace plantnbv
