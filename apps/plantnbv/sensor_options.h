#pragma once
// The simulated sensor's options, the same in capture and reconstruct: --intrinsics,
// --noise, --no-background.

#include <optional>
#include <string>

#include <plantnbv/camera/camera_intrinsics.h>

namespace CLI {
class App;
}

namespace plantnbv {
namespace app {

struct SensorOptions {
  std::string intrinsics; ///< as parseCameraIntrinsics reads it; empty: the default
  bool noise = false;
  bool no_background = false;
};

/// Adds the options to a subcommand. `default_camera` and `noise_seed` complete the help
/// texts: where the default camera comes from, and what seeds the noise.
void addSensorOptions(CLI::App& cmd, SensorOptions& options,
                      const std::string& default_camera, const std::string& noise_seed);

/// The camera of --intrinsics; nothing when it was not given.
/// \throws InvalidArgumentError naming --intrinsics for a spec parseCameraIntrinsics
/// refuses.
std::optional<CameraIntrinsics> intrinsicsOf(const SensorOptions& options);

} // namespace app
} // namespace plantnbv
