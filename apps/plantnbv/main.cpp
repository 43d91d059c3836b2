// plantnbv: one tool, one subcommand per file. Exit codes: 0 success, 1 bad input or a
// failed operation (one line on stderr), 2 usage error (CLI11's own codes are mapped).

#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include <plantnbv/common/error.h>
#include <plantnbv/viz/display.h>

#include "commands.h"

namespace {

/// Whether the command renders (a --snapshot option, or the figures of `campaign
/// report`): rendering needs an X display.
bool rendersPictures(int argc, char** argv)
{
  bool campaign = false, report = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--snapshot", 0) == 0)
      return true;
    if (arg == "--no-figures" || arg == "--help" || arg == "-h")
      return false;
    campaign = campaign || (i == 1 && arg == "campaign");
    report = report || (i == 2 && arg == "report");
  }
  return campaign && report;
}

} // namespace

int main(int argc, char** argv)
{
  CLI::App app{
      "plantnbv: attention-driven next-best-view planning for plant reconstruction",
      "plantnbv"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "plantnbv 0.1.0");
  plantnbv::app::addSampleCommand(app);
  plantnbv::app::addEvalCommand(app);
  plantnbv::app::addPlantCommand(app);
  plantnbv::app::addCaptureCommand(app);
  plantnbv::app::addReconstructCommand(app);
  plantnbv::app::addCampaignCommand(app);

  // Rendering needs X: without a display, run again under xvfb-run (when installed;
  // otherwise the renderer reports the missing display as a one-line error).
  if (rendersPictures(argc, argv))
    plantnbv::viz::reexecUnderXvfbIfNeeded(argc, argv);

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
  } catch (const std::exception& e) { // e.g. std::bad_alloc: still one line, no abort
    std::cerr << "plantnbv: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
