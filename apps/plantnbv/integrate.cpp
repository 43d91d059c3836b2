// plantnbv integrate: insert the depth frames of a frames folder (TUM layout, ROS
// camera_info) into a new occupancy map or onto an existing one, and write it.

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <plantnbv/common/error.h>
#include <plantnbv/common/memory_cap.h>
#include <plantnbv/common/stopwatch.h>
#include <plantnbv/experiment/trial.h>
#include <plantnbv/io/file_kind.h>
#include <plantnbv/io/frames_folder.h>
#include <plantnbv/io/roi_io.h>
#include <plantnbv/scenario/trial_config_file.h>
#include <plantnbv/session/active_vision_session.h>
#include <plantnbv/session/detection_fusion.h>
#include <plantnbv/session/memory_estimate.h>

#include "cli_checks.h"
#include "commands.h"
#include "frames_out.h"
#include "map_file.h"

namespace plantnbv {
namespace app {

namespace {

struct IntegrateOptions {
  std::string frames;
  std::string output;
  std::string map_in;
  std::string config_file;
  std::optional<double> resolution;
  std::optional<double> max_range;
  std::optional<double> depth_scale;
  std::string frame_list;
  bool skip_unmatched = false;
  std::optional<int> threads;
  std::string roi_out;
  std::string roi_class = "leaf_node";
};

/// The frame indices of LIST ("0,2,5-7": positions in the folder's frame list).
std::vector<std::size_t> selectFrames(const std::string& list, std::size_t count)
{
  std::vector<std::size_t> out;
  if (list.empty()) {
    for (std::size_t i = 0; i < count; ++i)
      out.push_back(i);
    return out;
  }
  std::istringstream items(list);
  std::string item;
  const auto bad = [&](const std::string& why) {
    throw InvalidArgumentError("--frames '" + list + "': " + why +
                               " (expected indices and ranges like 0,2,5-7 of the " +
                               std::to_string(count) + " frames, from 0)");
  };
  while (std::getline(items, item, ',')) {
    const std::size_t dash = item.find('-');
    std::size_t first = 0, last = 0;
    try {
      std::size_t used = 0;
      first = std::stoul(item.substr(0, dash), &used);
      if (used != dash && dash != std::string::npos)
        bad("'" + item + "' is not an index or a range");
      last = dash == std::string::npos ? first : std::stoul(item.substr(dash + 1), &used);
      if (dash == std::string::npos ? used != item.size()
                                    : used != item.size() - dash - 1)
        bad("'" + item + "' is not an index or a range");
    } catch (const std::logic_error&) {
      bad("'" + item + "' is not an index or a range");
    }
    if (item[0] == '-' || first > last || last >= count)
      bad("'" + item + "' is out of range");
    for (std::size_t i = first; i <= last; ++i)
      out.push_back(i);
  }
  if (out.empty())
    bad("no frame selected");
  return out;
}

void runIntegrate(const IntegrateOptions& o)
{
  // Everything that can be checked is checked before the first frame is read.
  requireMapExtension(o.output, "-o");
  TrialConfig config;
  if (!o.config_file.empty())
    scenario::loadTrialConfig(o.config_file, config);
  if (o.resolution)
    config.map.resolution_m = *o.resolution;
  if (o.max_range)
    config.map.max_range_m = *o.max_range;
  if (o.threads)
    config.threads = *o.threads;
  config.map.validate();
  if (!o.roi_out.empty() && io::extensionOf(o.roi_out) != ".yaml")
    throw InvalidArgumentError("--roi-out '" + o.roi_out +
                               "': expected a file name ending in .yaml");
  DetectionFusion fusion;
  if (!o.roi_out.empty()) {
    DetectionFusion::Config fusion_config;
    fusion_config.class_name = o.roi_class;
    try {
      fusion.setConfig(fusion_config);
    } catch (const InvalidArgumentError& e) {
      throw InvalidArgumentError("--roi-class '" + o.roi_class + "': " + e.what());
    }
  }
  io::FramesFolderOptions folder_options;
  folder_options.skip_unmatched = o.skip_unmatched;
  if (o.depth_scale) {
    if (!(*o.depth_scale > 0.0))
      throw InvalidArgumentError("--depth-scale " + shortestText(*o.depth_scale) +
                                 ": expected units per metre > 0 (1000: millimetres)");
    folder_options.depth_scale = *o.depth_scale;
  }
  const io::FramesFolder folder(o.frames, folder_options);
  const std::vector<std::size_t> selected =
      selectFrames(o.frame_list, folder.frames().size());
  const io::CameraInfo& camera = folder.camera();
  // One view's map and frame, before the first frame is read (TrialConfig's rule).
  std::ostringstream what;
  what << "the map at " << config.map.resolution_m << " m (range "
       << config.map.max_range_m << " m) of the " << camera.intrinsics.width << "x"
       << camera.intrinsics.height << " camera of '" << o.frames << "'";
  requireWithinMemoryCap(estimatedViewMemoryBytes(config.map, camera.intrinsics),
                         config.memory_cap_bytes, what.str(),
                         " (memory_cap_gib in --config raises it)");

  ActiveVisionSession session(sessionConfigOf(config));
  if (!o.map_in.empty()) {
    if (!session.readMap(o.map_in))
      std::cerr << "warning: '" << o.map_in
                << "' is a .bt (occupied / free only): its voxels' probabilities are "
                   "lost; frames are added to that\n";
    const double file_resolution = session.getMap()->getConfig().resolution_m;
    if (o.resolution && *o.resolution != file_resolution)
      throw InvalidArgumentError("--resolution " + std::to_string(*o.resolution) +
                                 " differs from the resolution of --map-in '" + o.map_in +
                                 "' (" + std::to_string(file_resolution) + ")");
  }
  const OccupancyMap& map = *session.getMap();
  std::cout << "frames folder '" << o.frames << "': " << folder.frames().size()
            << " frames";
  if (folder.skippedFrames() > 0)
    std::cout << " (" << folder.skippedFrames()
              << " without a pose within 0.02 s skipped)";
  std::cout << ", camera " << camera.intrinsics.toString() << ", depth_scale "
            << camera.depth_scale << "; map " << map.getConfig().resolution_m * 1000.0
            << " mm, max range " << map.getConfig().max_range_m << " m"
            << (o.map_in.empty() ? std::string(", new") : ", onto '" + o.map_in + "'")
            << "\n";

  Stopwatch total_clock;
  DepthImage depth;
  std::vector<Detection> detections;
  std::size_t frames_with_detections = 0;
  std::size_t returns = 0;
  double decode_ms = 0.0, insert_ms = 0.0;
  for (std::size_t i : selected) {
    const io::FrameRecord& frame = folder.frames()[i];
    Stopwatch decode_clock;
    folder.loadDepth(i, depth);
    const double frame_decode_ms = decode_clock.ms();
    Stopwatch insert_clock;
    session.integrate(depth, camera.intrinsics, frame.T_W_O);
    const double frame_insert_ms = insert_clock.ms();
    if (!o.roi_out.empty() && !frame.detections_path.empty()) {
      folder.loadDetections(i, detections);
      fusion.addFrame(detections, depth, camera.intrinsics, frame.T_W_O);
      ++frames_with_detections;
    }
    const OccupancyMap::InsertStats& stats = map.getLastInsertStats();
    const std::size_t frame_returns = stats.points - stats.non_finite;
    returns += frame_returns;
    decode_ms += frame_decode_ms;
    insert_ms += frame_insert_ms;
    std::cout << std::fixed << std::setprecision(1) << "frame " << std::setw(3) << i
              << " '" << frame.depth_path << "' at " << std::setprecision(6)
              << frame.stamp_s << " s: " << frame_returns << " returns ("
              << stats.beyond_range << " beyond range), decode " << std::setprecision(1)
              << frame_decode_ms << " ms, insert " << frame_insert_ms << " ms"
              << std::endl;
  }
  Stopwatch write_clock;
  session.writeMap(o.output); // replaces an existing file whole or not at all
  const OccupancyMap::VoxelCounts counts = map.countVoxels();
  std::cout << std::fixed << std::setprecision(1) << "integrated " << selected.size()
            << " frames (" << returns << " returns) in " << total_clock.ms()
            << " ms (decode " << decode_ms << " ms, insert " << insert_ms << " ms, write "
            << write_clock.ms() << " ms); wrote '" << o.output << "': " << counts.occupied
            << " occupied, " << counts.free << " free voxels\n";
  if (o.roi_out.empty())
    return;
  const Roi roi = fusion.getRoi();
  const DetectionFusion::Counts& c = fusion.getCounts();
  std::cout << "fused " << c.detections << " detections of " << frames_with_detections
            << " frames into " << fusion.getInstances().size() << " '" << o.roi_class
            << "' instances (" << c.other_class << " of other classes, " << c.low_score
            << " under score " << fusion.getConfig().min_score << ", " << c.too_few_points
            << " with too few points left out)";
  if (!roi.empty()) {
    io::saveRoi(o.roi_out, roi);
    std::cout << "; wrote '" << o.roi_out << "': " << roi.size() << " boxes\n";
    return;
  }
  // Nothing found: no ROI file (an ROI file holds boxes), and none from an earlier run.
  std::error_code ec;
  const bool removed = std::filesystem::remove(o.roi_out, ec);
  std::cout << "\n";
  std::cerr << "warning: no '" << o.roi_class << "' found in '" << o.frames
            << (frames_with_detections == 0 ? "' (it has no detections.txt)" : "'")
            << ": no ROI written to '" << o.roi_out << "'"
            << (removed ? " (an earlier run's file removed)" : "")
            << "; `plan` without --roi attends to the whole plant's box\n";
}

} // namespace

void addIntegrateCommand(CLI::App& app)
{
  auto o = std::make_shared<IntegrateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "integrate", "Insert the depth frames of a frames folder (camera.yaml, depth.txt, "
                   "groundtruth.txt, depth/*.png; docs/real-robot.md) into an occupancy "
                   "map and write it");
  cmd->add_option("frames", o->frames, "Frames folder")->required();
  cmd->add_option(
         "-o,--output", o->output,
         "Map to write: .ot (log-odds, what `plan` needs) or .bt (occupied / free "
         "only)")
      ->required();
  cmd->add_option("--map-in", o->map_in,
                  "Start from this map (.ot) instead of an empty one");
  cmd->add_option("--config", o->config_file,
                  "Trial config (YAML, e.g. data/paper.yaml) for the map's parameters");
  cmd->add_option("--resolution", o->resolution, "Voxel size in metres (0.003)");
  cmd->add_option("--max-range", o->max_range,
                  "Returns farther than this carve free space only (metres, 0.75)");
  cmd->add_option("--depth-scale", o->depth_scale,
                  "Depth PNG units per metre, instead of camera.yaml's depth_scale");
  cmd->add_option(
      "--frames", o->frame_list,
      "Only these frames: indices and ranges of depth.txt's frames, e.g. 0,2,5-7");
  cmd->add_flag("--skip-unmatched", o->skip_unmatched,
                "Skip frames with no pose within 0.02 s (default: an error)");
  cmd->add_option("--roi-out", o->roi_out,
                  "Also fuse the frames' detections (detections.txt) into 3D boxes and "
                  "write them as an ROI file for `plan --roi` (.yaml)");
  cmd->add_option("--roi-class", o->roi_class,
                  "The detection class --roi-out fuses (default leaf_node)");
  cmd->add_option("--threads", o->threads, "Threads (default: all cores)")
      ->transform(threadCount("--threads"));
  cmd->callback([o]() { runIntegrate(*o); });
}

} // namespace app
} // namespace plantnbv
