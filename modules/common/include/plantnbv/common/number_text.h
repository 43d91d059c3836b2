#pragma once
/// \file number_text.h
/// \brief Numbers as text that reads back exactly: files, messages and fingerprints
/// write doubles one way.

#include <charconv>
#include <string>

namespace plantnbv {

/// \brief The shortest decimal text that reads back as exactly `x` (std::to_chars: "0.4",
/// not "0.40000000000000002"; at most 17 significant digits); "inf", "-inf" and "nan"
/// for the values that are not finite (callers that write formats without them decide
/// before).
inline std::string shortestText(double x)
{
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof(buffer), x).ptr);
}

} // namespace plantnbv
