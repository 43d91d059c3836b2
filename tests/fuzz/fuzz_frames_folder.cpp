// Frames folders (TUM RGB-D layout, ROS camera_info YAML): io::readCameraInfo,
// readTumTrajectory, readTumFileList, FramesFolder (with and without skip_unmatched, and
// loadDepth on its first frames) and FramesFolderWriter's checks of an existing folder.
// The input is up to four files separated by NUL bytes: camera.yaml, groundtruth.txt,
// depth.txt and depth/000000.png; a file the input does not reach is absent.
#include <algorithm>
#include <filesystem>
#include <fstream>

#include <plantnbv/camera/depth_image.h>
#include <plantnbv/io/frames_folder.h>

#include "fuzz_util.h"

namespace {

const char* const kFiles[] = {"camera.yaml", "groundtruth.txt", "depth.txt",
                              "depth/000000.png"};

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  namespace fs = std::filesystem;
  namespace io = plantnbv::io;
  using plantnbv::fuzz::run;
  plantnbv::fuzz::useSmallLimits();
  static const plantnbv::fuzz::InputDir dir;
  const fs::path folder = dir.path() / "frames";
  fs::remove_all(folder);
  fs::create_directories(folder / "depth");

  const char* const bytes = reinterpret_cast<const char*>(data);
  std::size_t at = 0;
  for (std::size_t f = 0; f < 4 && at <= size; ++f) {
    // The last file takes the rest (a PNG holds NUL bytes).
    const std::size_t stop =
        f == 3 ? size : std::size_t(std::find(bytes + at, bytes + size, '\0') - bytes);
    std::ofstream(folder / kFiles[f], std::ios::binary)
        .write(bytes + at, static_cast<std::streamsize>(stop - at));
    at = stop + 1;
  }

  const std::string path = folder.string();
  run([&] { io::readCameraInfo(path + "/camera.yaml"); });
  run([&] { io::readTumTrajectory(path + "/groundtruth.txt"); });
  run([&] { io::readTumFileList(path + "/depth.txt"); });
  for (const bool skip : {false, true}) {
    run([&] {
      io::FramesFolderOptions options;
      options.skip_unmatched = skip;
      const io::FramesFolder frames(path, options);
      plantnbv::DepthImage depth;
      for (std::size_t i = 0; i < std::min<std::size_t>(frames.frames().size(), 4); ++i)
        run([&] { frames.loadDepth(i, depth); });
    });
  }
  // A writer opening the folder checks its camera and reads depth.txt (appends nothing).
  run([&] {
    const io::CameraInfo camera = io::readCameraInfo(path + "/camera.yaml");
    io::FramesFolderWriter writer(path, camera);
  });
  return 0;
}
