#pragma once
// The subcommands of the plantnbv tool: each adds itself to the app and runs from its
// callback. Apps are thin: parse, call the modules, print.

namespace CLI {
class App;
}

namespace plantnbv {
namespace app {

void addSampleCommand(CLI::App& app);
void addEvalCommand(CLI::App& app);
void addPlantCommand(CLI::App& app);
void addCaptureCommand(CLI::App& app);
void addReconstructCommand(CLI::App& app);
void addIntegrateCommand(CLI::App& app);
void addPlanCommand(CLI::App& app);
void addCampaignCommand(CLI::App& app);

/// The tool's version ("0.1.0") and the commit it was built from ("0123456789ab",
/// "+dirty" appended for a modified checkout, "unknown" outside git).
const char* toolVersion();
const char* toolCommit();

/// The command line, kept by main() for requireDisplayOrReexec().
void setCommandLine(int argc, char** argv);
/// For a command about to render (a snapshot, figures), before it prints or starts
/// threads: without an X display, runs the whole command again under xvfb-run (when
/// installed), else throws the renderer's one-line Error.
void requireDisplayOrReexec();

} // namespace app
} // namespace plantnbv
