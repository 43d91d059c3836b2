#include "cli_checks.h"

#include <charconv>
#include <cstdint>
#include <iostream>
#include <thread>

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

CLI::Validator threadCount(const std::string& option)
{
  return CLI::Validator(
      [option](std::string& text) -> std::string {
        unsigned long threads = 0;
        const char* end = text.data() + text.size();
        const auto [last, error] = std::from_chars(text.data(), end, threads);
        if (text.empty() || error != std::errc() || last != end)
          return "expected 0 (all cores) or a number of threads, got '" + text + "'";
        const unsigned cores = std::thread::hardware_concurrency();
        if (cores > 0 && threads > cores) {
          std::cerr << "plantnbv: warning: " << option << " " << text
                    << " is more than the " << cores << " cores of this machine; using "
                    << cores << "\n";
          text = std::to_string(cores);
        }
        return {};
      },
      "");
}

} // namespace app
} // namespace plantnbv
