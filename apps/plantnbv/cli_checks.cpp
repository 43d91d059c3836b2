#include "cli_checks.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>
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

namespace {

/// Reads a count (0: all cores) from `text`; false if it is not one.
bool readCoreCount(const std::string& text, unsigned long& count)
{
  const char* end = text.data() + text.size();
  const auto [last, error] = std::from_chars(text.data(), end, count);
  return !text.empty() && error == std::errc() && last == end &&
         count <= std::numeric_limits<int>::max();
}

} // namespace

CLI::Validator workerCount(const std::string& what)
{
  return CLI::Validator(
      [what](std::string& text) -> std::string {
        unsigned long count = 0;
        if (!readCoreCount(text, count))
          return "expected 0 (all cores) or a number of " + what + ", got '" + text + "'";
        return {};
      },
      "");
}

CLI::Validator threadCount(const std::string& option)
{
  return CLI::Validator(
      [option](std::string& text) -> std::string {
        unsigned long threads = 0;
        if (!readCoreCount(text, threads))
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

CLI::Validator magnitudeAtMost(double max, const std::string& unit)
{
  return CLI::Validator(
      [max, unit](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !(std::abs(value) <= max)) {
          std::ostringstream s;
          s << "expected a number from " << -max << " to " << max << " (" << unit
            << "), got '" << text << "'";
          return s.str();
        }
        return {};
      },
      "");
}

const CLI::Validator& pngPath()
{
  static const CLI::Validator check(
      [](std::string& text) -> std::string {
        std::string ext = std::filesystem::path(text).extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(),
                       [](unsigned char c) { return char(std::tolower(c)); });
        if (ext != ".png")
          return "expected a file name ending in .png (the image is written as PNG), got "
                 "'" +
                 text + "'";
        return {};
      },
      "");
  return check;
}

} // namespace app
} // namespace plantnbv
