// Detection files (per-frame JSON, detections_io.h): io::readDetections for an 8 x 6
// depth image, and detectionPixels of what it reads. Masks are looked up beside the
// input: "mask.png" is a valid 8 x 6 mask, "small.png" a 4 x 3 one, "text.png" not a PNG.
#include <filesystem>
#include <fstream>
#include <vector>

#include <plantnbv/io/depth_image_io.h>
#include <plantnbv/io/detections_io.h>

#include "fuzz_util.h"

namespace {

constexpr std::uint32_t kWidth = 8, kHeight = 6;

/// The folder of the input and its mask files, made once.
const std::filesystem::path& maskFolder()
{
  static const plantnbv::fuzz::InputDir dir;
  static const bool made = [] {
    std::vector<std::uint8_t> mask(kWidth * kHeight, 0);
    mask[3] = 255;
    mask[20] = 1;
    plantnbv::io::saveMaskPng((dir.path() / "mask.png").string(), kWidth, kHeight, mask);
    plantnbv::io::saveMaskPng((dir.path() / "small.png").string(), 4, 3,
                              std::vector<std::uint8_t>(12, 255));
    std::ofstream(dir.path() / "text.png") << "not a PNG";
    return true;
  }();
  (void)made;
  return dir.path();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  plantnbv::fuzz::useSmallLimits();
  const std::string path = (maskFolder() / "input.json").string();
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  std::vector<plantnbv::Detection> detections;
  plantnbv::fuzz::run(
      [&] { detections = plantnbv::io::readDetections(path, kWidth, kHeight); });
  // What the reader accepts, its consumers take: an exception here escapes (a finding).
  for (const plantnbv::Detection& d : detections)
    if (plantnbv::detectionPixels(d, kWidth, kHeight).size() >
        std::size_t(kWidth) * kHeight)
      __builtin_trap();
  return 0;
}
