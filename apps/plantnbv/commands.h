#pragma once
// The subcommands of the plantnbv tool: each adds itself to the app and runs from its
// callback. Apps are thin: parse, call the modules, print.

#include <chrono>

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

/// Milliseconds since construction, for the timings the tools print.
class Stopwatch {
public:
  double ms() const
  {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() -
                                                     start_)
        .count();
  }

private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

} // namespace app
} // namespace plantnbv
