#pragma once
/// \file display.h
/// \brief The X display that rendering needs, and a helper that gives a program a virtual
/// one.
///
/// VTK 9.1 as Debian builds it renders through GLX, even offscreen, so it needs an X
/// server; without one it calls abort(). SceneSnapshot::render() therefore opens the
/// display itself first and throws an Error instead. On a machine without a screen, run
/// the program under `xvfb-run -a` (package xvfb), or let it re-execute itself there with
/// reexecUnderXvfbIfNeeded().
///
/// If the X server dies in the middle of a render, Xlib ends the process (its I/O error
/// handler exits with status 1; in one of five tries here Mesa crashed instead); no
/// library can turn that into an exception. Between renders its death gives the Error.

#include <string>

namespace plantnbv {
namespace viz {

/// \brief Whether an X server accepts a connection at $DISPLAY (opens one and closes it
/// again, about a millisecond for a local server). A refused connection is tried again
/// for about a second (X servers refuse connections while they reset, which xvfb-run's
/// server does whenever its last client leaves), so a DISPLAY where nothing answers takes
/// that long to report; an unset DISPLAY is reported at once.
/// \param[out] reason when not null and the answer is false: why, e.g. "DISPLAY is not
/// set" or "no X server answers at DISPLAY=:7".
bool displayAvailable(std::string* reason = nullptr);

/// \brief Does nothing when displayAvailable(), else throws Error with the message
/// "rendering needs an X display: run the command under `xvfb-run -a`, or set DISPLAY"
/// (when DISPLAY is not set) or "rendering needs an X display, and no X server answers at
/// DISPLAY=:7: run the command under `xvfb-run -a`, or set DISPLAY to a running X
/// server".
void requireDisplay();

/// \brief For a program's main(): makes sure a display is there for rendering, by
/// re-executing the program under a virtual X server when there is none.
///
/// When displayAvailable(), returns true and does nothing else. Otherwise, if `xvfb-run`
/// and `xauth` are on PATH, replaces the process (execv) by
/// `xvfb-run -a -s "-screen 0 1600x1200x24 -noreset" <program> argv[1..]`, which runs
/// the program again with DISPLAY set and exits with its status; the program is argv[0]
/// when it holds a '/', else /proc/self/exe. Standard streams are flushed first. The
/// environment variable PLANTNBV_XVFB_REEXEC marks the second run, so a virtual server
/// that still gives no display does not loop. Returns false when a display is needed but
/// none can be had this way (no xvfb-run or xauth, already re-executed, execv failed), so
/// that the caller can report requireDisplay()'s error. Call it before starting threads.
/// \code
/// int main(int argc, char** argv) {
///   if (!plantnbv::viz::reexecUnderXvfbIfNeeded(argc, argv)) { ... print, return 1 }
///   ...
/// \endcode
bool reexecUnderXvfbIfNeeded(int argc, char** argv);

} // namespace viz
} // namespace plantnbv
