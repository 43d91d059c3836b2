#pragma once
/// \file memory_cap.h
/// \brief The memory cap: what a command or a trial plans to allocate is estimated from
/// its inputs first and refused over the cap, with the estimate in the message, so that
/// a tiny file or a small number never runs out of memory (std::bad_alloc) half way.

#include <iomanip>
#include <sstream>
#include <string>

#include <plantnbv/common/error.h>

namespace plantnbv {

/// \brief Bytes in a GiB (2^30).
constexpr double kBytesPerGib = 1024.0 * 1024.0 * 1024.0;

/// \brief The memory, in bytes, that commands and trials may plan to allocate unless
/// told otherwise (TrialConfig::memory_cap_bytes, memory_cap_gib in a trial config): 8
/// GiB.
constexpr double kDefaultMemoryCapBytes = 8.0 * kBytesPerGib;

/// \brief The one message for going over the cap: throws InvalidArgumentError
/// "WHAT need(s) about X GiB, over the memory cap of Y GiB HINT" unless
/// need_bytes <= cap_bytes (NaN is over).
/// \param[in] what names the input and its numbers, e.g. "--points 1000000000".
/// \param[in] hint appended as it is, e.g. " (memory_cap_gib raises it)".
inline void requireWithinMemoryCap(double need_bytes, double cap_bytes,
                                   const std::string& what, const std::string& hint = "")
{
  if (need_bytes <= cap_bytes)
    return;
  std::ostringstream s;
  s << std::setprecision(3) << what << " need about " << need_bytes / kBytesPerGib
    << " GiB, over the memory cap of " << cap_bytes / kBytesPerGib << " GiB" << hint;
  throw InvalidArgumentError(s.str());
}

} // namespace plantnbv
