// plantnbv: one tool, one subcommand per file. Exit codes: 0 success, 1 bad input or a
// failed operation (one line on stderr), 2 usage error (CLI11's own codes are mapped).

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <new>
#include <string>

#include <CLI/CLI.hpp>

#include <plantnbv/common/error.h>
#include <plantnbv/viz/display.h>

#include "commands.h"

namespace plantnbv {
namespace app {

namespace {
int g_argc = 0;
char** g_argv = nullptr;
} // namespace

void setCommandLine(int argc, char** argv)
{
  g_argc = argc;
  g_argv = argv;
}

void requireDisplayOrReexec()
{
  // Without a display: run again under xvfb-run (this process ends there); where that
  // cannot be done, the one-line error of requireDisplay().
  if (!viz::reexecUnderXvfbIfNeeded(g_argc, g_argv))
    viz::requireDisplay();
}

} // namespace app
} // namespace plantnbv

int main(int argc, char** argv)
{
  // Past a file-size limit (ulimit -f) a write then fails with EFBIG and is reported,
  // naming the file, instead of the process being killed in the middle of it.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{
      "plantnbv: attention-driven next-best-view planning for plant reconstruction",
      "plantnbv"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("plantnbv ") +
                                        plantnbv::app::toolVersion() + " (commit " +
                                        plantnbv::app::toolCommit() + ")");
  plantnbv::app::addSampleCommand(app);
  plantnbv::app::addEvalCommand(app);
  plantnbv::app::addPlantCommand(app);
  plantnbv::app::addCaptureCommand(app);
  plantnbv::app::addReconstructCommand(app);
  plantnbv::app::addIntegrateCommand(app);
  plantnbv::app::addPlanCommand(app);
  plantnbv::app::addCampaignCommand(app);

  plantnbv::app::setCommandLine(argc, argv); // for requireDisplayOrReexec()
  // CLI11 reports an unknown command as "a subcommand is required": name it instead.
  if (argc > 1 && argv[1][0] != '-') {
    const auto known = app.get_subcommands([](CLI::App*) { return true; });
    std::string names;
    bool found = false;
    for (const CLI::App* sub : known) {
      found = found || sub->check_name(argv[1]);
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (!found) {
      std::cerr << "plantnbv: unknown command '" << argv[1] << "' (expected one of "
                << names << "; see --help)\n";
      return 2;
    }
  }
  const std::string command = argc > 1 ? std::string("plantnbv ") + argv[1] : "plantnbv";
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) { // --help, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "plantnbv: " << e.what() << " (see --help)\n";
    return 2;
  } catch (const plantnbv::Error& e) {
    std::cerr << "plantnbv: error: " << e.what() << "\n";
    return 1;
  } catch (const std::bad_alloc&) {
    // The commands estimate what they allocate and refuse over a cap first; this is
    // what is left (e.g. a cap set above the machine's memory).
    std::cerr << "plantnbv: error: " << command
              << ": out of memory (the inputs and options ask for more than this "
                 "machine has)\n";
    return 1;
  } catch (const std::exception& e) { // still one line, no abort
    std::cerr << "plantnbv: error: " << command << ": " << e.what() << "\n";
    return 1;
  }
  // What went to standard output must have arrived (a full disk, a closed pipe).
  errno = 0;
  std::cout.flush();
  if (!std::cout || std::fflush(stdout) != 0 || std::ferror(stdout)) {
    std::cerr << "plantnbv: error: cannot write standard output"
              << (errno ? std::string(": ") + std::strerror(errno) : std::string())
              << "\n";
    return 1;
  }
  return 0;
}
