#pragma once
// --frames-out of capture and reconstruct: the camera of a frames folder written by the
// simulated sensor.

#include <filesystem>
#include <optional>
#include <string>

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/common/error.h>
#include <plantnbv/common/number_text.h>
#include <plantnbv/io/frames_folder.h>

namespace plantnbv {
namespace app {

/// The camera that frames of `intrinsics` get in `folder`: the depth scale given, else
/// that of the folder's camera.yaml, else 1000 (millimetres).
inline io::CameraInfo framesCamera(const std::string& folder,
                                   const CameraIntrinsics& intrinsics,
                                   std::optional<double> depth_scale)
{
  io::CameraInfo camera;
  camera.intrinsics = intrinsics;
  const std::string yaml = (std::filesystem::path(folder) / "camera.yaml").string();
  std::error_code ec;
  if (depth_scale)
    camera.depth_scale = *depth_scale;
  else if (std::filesystem::exists(yaml, ec))
    camera.depth_scale = io::readCameraInfo(yaml).depth_scale;
  if (!(camera.depth_scale > 0.0))
    throw InvalidArgumentError("--depth-scale " + shortestText(camera.depth_scale) +
                               ": expected units per metre > 0 (1000: millimetres)");
  return camera;
}

} // namespace app
} // namespace plantnbv
