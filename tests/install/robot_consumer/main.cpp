// A robot's 3-frame loop without the simulator: three depth frames of a flat board
// 0.5 m in front of the camera, written to a frames folder, read back, integrated into
// an ActiveVisionSession, then one planning step. Prints
// "frames=3 candidates=27 best_gain>0=1 occupied>0=1".
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>
#include <unistd.h>

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/camera/depth_image.h>
#include <plantnbv/camera/optical_frame.h>
#include <plantnbv/common/pose.h>
#include <plantnbv/io/frames_folder.h>
#include <plantnbv/session/active_vision_session.h>

int main()
{
  namespace fs = std::filesystem;
  using namespace plantnbv;
  const fs::path folder =
      fs::temp_directory_path() / ("robot_consumer_" + std::to_string(::getpid()));
  fs::remove_all(folder);

  io::CameraInfo camera;
  camera.intrinsics = CameraIntrinsics::custom(160, 120, 114.25, 114.25, 81.0, 58.5);
  camera.depth_scale = 1000.0;
  const CameraIntrinsics& K = camera.intrinsics;

  // The camera on the paper's sector (0.4 m in front of the stem axis at (1, 0, 0.8),
  // facing +x); the board, 0.4 m x 0.4 m, 0.5 m ahead at x = 1.1.
  {
    io::FramesFolderWriter writer(folder.string(), camera);
    for (int i = 0; i < 3; ++i) {
      const double y = 0.05 * (i - 1);
      const Pose T_W_O = opticalFrame(
          Pose(Eigen::Vector3d(0.6, y, 1.1), Eigen::Quaterniond::Identity()));
      DepthImage depth;
      depth.width = K.width;
      depth.height = K.height;
      depth.depth_m.assign(K.pixelCount(), std::numeric_limits<float>::quiet_NaN());
      for (std::uint32_t v = 0; v < K.height; ++v)
        for (std::uint32_t u = 0; u < K.width; ++u) {
          const double x_right = (u - K.cx) / K.fx * 0.5; // metres, at the board
          const double y_down = (v - K.cy) / K.fy * 0.5;
          const double world_y = y - x_right;
          if (std::abs(world_y) < 0.2 && std::abs(y_down) < 0.2)
            depth.depth_m[std::size_t(v) * K.width + u] = 0.5f;
        }
      writer.append(depth, T_W_O, 100.0 + 0.5 * i);
    }
  }

  const io::FramesFolder frames(folder.string());
  ActiveVisionSession session;
  session.setCamera(frames.camera().intrinsics);
  DepthImage depth;
  for (std::size_t i = 0; i < frames.frames().size(); ++i) {
    frames.loadDepth(i, depth);
    session.integrate(depth, frames.camera().intrinsics, frames.frames()[i].T_W_O);
  }
  NextBestView next;
  session.nextBestView(next);
  const OccupancyMap::VoxelCounts counts = session.getMap()->countVoxels();
  fs::remove_all(folder);

  const bool gain = !next.ranking.empty() && next.ranking[0].gain.gain > 0.0;
  std::cout << "frames=" << frames.frames().size()
            << " candidates=" << next.result.candidates.size() << " best_gain>0=" << gain
            << " occupied>0=" << (counts.occupied > 0) << "\n";
  return frames.frames().size() == 3 && gain && counts.occupied > 0 ? 0 : 1;
}
