#pragma once
// The subcommands of the plantnbv tool: each adds itself to the app and runs from its
// callback. Apps are thin: parse, call the modules, print.

#include <plantnbv/common/stopwatch.h>

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
void addCampaignCommand(CLI::App& app);

} // namespace app
} // namespace plantnbv
