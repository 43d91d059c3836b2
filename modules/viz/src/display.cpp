#include <X11/Xlib.h>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <limits.h>
#include <string>
#include <sys/stat.h>
#include <thread>
#include <unistd.h>
#include <vector>

#include <plantnbv/common/error.h>
#include <plantnbv/viz/display.h>

#include "x_display.h"

// In builds with AddressSanitizer (PLANTNBV_SANITIZE): see XDisplayConnection.
#if defined(__SANITIZE_ADDRESS__)
#define PLANTNBV_HAS_LSAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PLANTNBV_HAS_LSAN 1
#endif
#endif
#ifdef PLANTNBV_HAS_LSAN
#include <sanitizer/lsan_interface.h>
#endif

namespace plantnbv {
namespace viz {

namespace {

constexpr const char* kReexecMarker = "PLANTNBV_XVFB_REEXEC";

/// The connection to $DISPLAY, or null with the reason.
Display* openDisplay(std::string& reason)
{
  const char* name = std::getenv("DISPLAY");
  if (name == nullptr || *name == '\0') {
    reason = "DISPLAY is not set";
    return nullptr;
  }
  // An X server without -noreset (xvfb-run's default) resets when its last client
  // leaves and refuses connections meanwhile: a render right after another one can hit
  // that window, so try again for about a second before giving up.
  Display* display = XOpenDisplay(name);
  for (int wait_ms = 10; display == nullptr && wait_ms <= 320; wait_ms *= 2) {
    std::this_thread::sleep_for(std::chrono::milliseconds(wait_ms));
    display = XOpenDisplay(name);
  }
  if (display == nullptr)
    reason = std::string("no X server answers at DISPLAY=") + name;
  return display;
}

std::string displayErrorMessage(const std::string& reason)
{
  if (reason == "DISPLAY is not set")
    return "rendering needs an X display: run the command under `xvfb-run -a`, or set "
           "DISPLAY";
  return "rendering needs an X display, and " + reason +
         ": run the command under `xvfb-run -a`, or set DISPLAY to a running X server";
}

/// The executable file `name` in a directory of PATH, or "".
std::string findOnPath(const std::string& name)
{
  const char* path = std::getenv("PATH");
  if (path == nullptr)
    return "";
  const std::string dirs = path;
  std::size_t begin = 0;
  while (begin <= dirs.size()) {
    std::size_t end = dirs.find(':', begin);
    if (end == std::string::npos)
      end = dirs.size();
    // An empty PATH entry means the current directory.
    const std::string dir = end > begin ? dirs.substr(begin, end - begin) : ".";
    const std::string candidate = dir + "/" + name;
    struct stat st;
    if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
        ::access(candidate.c_str(), X_OK) == 0)
      return candidate;
    begin = end + 1;
  }
  return "";
}

/// The program to run again: argv[0] when it is a path (kept as the user wrote it, so
/// usage messages stay the same), else the executable of this process.
std::string programPath(const char* argv0)
{
  if (std::string(argv0).find('/') != std::string::npos)
    return argv0;
  char buffer[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", buffer, sizeof(buffer) - 1);
  if (n <= 0)
    return "";
  return std::string(buffer, static_cast<std::size_t>(n));
}

} // namespace

namespace detail {

XDisplayConnection::XDisplayConnection()
{
  std::string reason;
  display_ = openDisplay(reason);
  if (display_ == nullptr)
    throw Error(displayErrorMessage(reason));
#ifdef PLANTNBV_HAS_LSAN
  // Mesa's swrast_dri.so, which VTK renders with, keeps blocks until it is unloaded,
  // and it is unloaded before LeakSanitizer looks at exit: no suppression can name its
  // frames then. So what is allocated on this thread while the connection is open (the
  // rendering) is not leak-checked; memory errors still are (docs/reliability.md).
  __lsan_disable();
#endif
}

XDisplayConnection::~XDisplayConnection()
{
  XCloseDisplay(static_cast<Display*>(display_));
#ifdef PLANTNBV_HAS_LSAN
  __lsan_enable();
#endif
}

} // namespace detail

bool displayAvailable(std::string* reason)
{
  std::string why;
  Display* display = openDisplay(why);
  if (display == nullptr) {
    if (reason != nullptr)
      *reason = why;
    return false;
  }
  XCloseDisplay(display);
  return true;
}

void requireDisplay()
{
  std::string reason;
  if (!displayAvailable(&reason))
    throw Error(displayErrorMessage(reason));
}

bool reexecUnderXvfbIfNeeded(int argc, char** argv)
{
  if (displayAvailable())
    return true;
  if (argc < 1 || argv == nullptr || argv[0] == nullptr)
    return false;
  // Already re-executed once: Xvfb gave no usable display, so a second try would loop.
  const char* marker = std::getenv(kReexecMarker);
  if (marker != nullptr && *marker != '\0')
    return false;
  const std::string xvfb_run = findOnPath("xvfb-run");
  // xvfb-run exits with an error of its own when xauth is missing; check here instead,
  // while the caller can still report it.
  if (xvfb_run.empty() || findOnPath("xauth").empty())
    return false;
  const std::string program = programPath(argv[0]);
  if (program.empty())
    return false;

  // -noreset: an X server that resets when its last client leaves signals xvfb-run
  // (SIGUSR1) again just as xvfb-run cleans up after the program, which can make
  // xvfb-run fail its cleanup and exit 5 after a program that succeeded (seen in CI).
  std::vector<std::string> args = {xvfb_run, "-a", "-s",
                                   "-screen 0 1600x1200x24 -noreset", program};
  for (int i = 1; i < argc; ++i)
    args.emplace_back(argv[i] != nullptr ? argv[i] : "");
  std::vector<char*> c_args;
  for (auto& arg : args)
    c_args.push_back(arg.data());
  c_args.push_back(nullptr);

  if (::setenv(kReexecMarker, "1", 1) != 0)
    return false;
  // Output buffered so far would otherwise be lost with the old process image.
  std::fflush(nullptr);
  ::execv(xvfb_run.c_str(), c_args.data());
  ::unsetenv(kReexecMarker);
  return false;
}

} // namespace viz
} // namespace plantnbv
