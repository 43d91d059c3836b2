#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

#include <gtest/gtest.h>

#include <plantnbv/common/error.h>
#include <plantnbv/viz/display.h>

#include "viz_test_util.h"

using plantnbv::test::ScopedEnv;

namespace {

struct CommandResult {
  int status = -1;
  std::string output;
};

/// Runs a shell command, returning its exit status and standard output.
CommandResult run(const std::string& command)
{
  CommandResult result;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr)
    return result;
  std::array<char, 256> buffer;
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr)
    result.output += buffer.data();
  const int status = ::pclose(pipe);
  result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

const std::string kProbe = VIZ_DISPLAY_PROBE;

} // namespace

TEST(Display, AvailableOnlyWithAnAnsweringServer)
{
  std::string reason;
  ASSERT_TRUE(plantnbv::viz::displayAvailable(&reason))
      << "the viz tests run under xvfb-run: " << reason;
  EXPECT_NO_THROW(plantnbv::viz::requireDisplay());
  {
    ScopedEnv env("DISPLAY", std::nullopt);
    EXPECT_FALSE(plantnbv::viz::displayAvailable(&reason));
    EXPECT_EQ(reason, "DISPLAY is not set");
    EXPECT_THROW(plantnbv::viz::requireDisplay(), plantnbv::Error);
  }
  {
    ScopedEnv env("DISPLAY", std::string(""));
    EXPECT_FALSE(plantnbv::viz::displayAvailable(&reason));
  }
  {
    ScopedEnv env("DISPLAY", std::string(":4987"));
    EXPECT_FALSE(plantnbv::viz::displayAvailable(&reason));
    EXPECT_EQ(reason, "no X server answers at DISPLAY=:4987");
  }
}

TEST(Display, ReexecIsNotNeededWithADisplay)
{
  const CommandResult r = run("env -u PLANTNBV_XVFB_REEXEC '" + kProbe + "' a");
  EXPECT_EQ(r.status, 0) << r.output;
  const char* display = std::getenv("DISPLAY");
  EXPECT_EQ(r.output,
            std::string("display ") + (display ? display : "") + " marker  args a\n");
}

TEST(Display, ReexecRunsTheProgramAgainUnderXvfb)
{
  // Arguments with spaces and an empty one pass through unchanged.
  const CommandResult r =
      run("env -u DISPLAY -u PLANTNBV_XVFB_REEXEC '" + kProbe + "' a 'b c' ''");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.rfind("display :", 0), 0u) << r.output;
  EXPECT_NE(r.output.find(" marker 1 args a|b c|\n"), std::string::npos) << r.output;
}

TEST(Display, ReexecReportsWhenItCannotHelp)
{
  // No xvfb-run on PATH.
  CommandResult r =
      run("env -u DISPLAY -u PLANTNBV_XVFB_REEXEC PATH=/nonexistent '" + kProbe + "'");
  EXPECT_EQ(r.status, 3);
  EXPECT_EQ(r.output, "rendering needs an X display: run the command under `xvfb-run "
                      "-a`, or set DISPLAY\n");
  // Already re-executed once: no second attempt (no loop).
  r = run("env -u DISPLAY PLANTNBV_XVFB_REEXEC=1 '" + kProbe + "'");
  EXPECT_EQ(r.status, 3);
  EXPECT_NE(r.output.find("rendering needs an X display"), std::string::npos);
}
