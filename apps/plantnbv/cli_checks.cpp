#include "cli_checks.h"

#include <charconv>
#include <cstdint>

namespace plantnbv {
namespace app {

const CLI::Validator& unsignedInteger()
{
  static const CLI::Validator check(
      [](std::string& text) -> std::string {
        std::uint64_t value = 0;
        const char* end = text.data() + text.size();
        const auto [last, error] = std::from_chars(text.data(), end, value);
        if (text.empty() || text.front() == '-' || error != std::errc() || last != end)
          return "expected a whole number from 0 to 18446744073709551615, got '" + text +
                 "'";
        return {};
      },
      "");
  return check;
}

} // namespace app
} // namespace plantnbv
