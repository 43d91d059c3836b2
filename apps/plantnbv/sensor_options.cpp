#include "sensor_options.h"

#include <CLI/CLI.hpp>

#include <plantnbv/common/error.h>

namespace plantnbv {
namespace app {

void addSensorOptions(CLI::App& cmd, SensorOptions& o, const std::string& default_camera,
                      const std::string& noise_seed)
{
  cmd.add_option("--intrinsics", o.intrinsics,
                 "Camera: l515 (1024x768), l515-640, l515-320, or WxH:fx,fy,cx,cy "
                 "(default: " +
                     default_camera + ")");
  cmd.add_flag("--noise", o.noise,
               "L515-like depth noise, seeded by " + noise_seed +
                   " (off: the paper's sensor)");
  cmd.add_flag("--no-background", o.no_background,
               "Leave out the floor and the support under the plant");
}

std::optional<CameraIntrinsics> intrinsicsOf(const SensorOptions& o)
{
  if (o.intrinsics.empty())
    return std::nullopt;
  try {
    return parseCameraIntrinsics(o.intrinsics);
  } catch (const InvalidArgumentError& e) {
    throw InvalidArgumentError(std::string("--intrinsics: ") + e.what());
  }
}

} // namespace app
} // namespace plantnbv
