#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/number_text.h>
#include <plantnbv/io/depth_image_io.h>
#include <plantnbv/io/frames_folder.h>
#include <plantnbv/io/yaml_reader.h>

#include "io_util.h"

namespace plantnbv {
namespace io {

namespace fs = std::filesystem;

namespace {

/// Text files of a folder are small; a larger one is not a frame list.
constexpr std::uint64_t kMaxListBytes = std::uint64_t{256} << 20;

/// A quaternion is normalized when its norm is this close to 1, refused otherwise.
constexpr double kQuaternionNormTolerance = 1e-3;
/// The norm of a normalized quaternion is 1 within this (its rounding: 1.5 epsilon seen).
constexpr double kUnitNormRounding = 4 * std::numeric_limits<double>::epsilon();

std::string inQuotes(const std::string& path)
{
  return "'" + path + "'";
}

[[noreturn]] void failLine(const std::string& path, std::size_t line,
                           const std::string& message)
{
  throw FormatError(inQuotes(path) + " line " + std::to_string(line) + ": " + message);
}

/// A whole field as a finite number, else a message naming it. An overflow reads as
/// inf and is refused; an underflow (ERANGE with a subnormal or 0, such as the
/// 4.9406564584124654e-324 that FramesFolderWriter writes) is the nearest double, kept.
double finiteNumber(const std::string& path, std::size_t line, const std::string& field,
                    const char* what)
{
  const char* begin = field.c_str();
  char* end = nullptr;
  const double value = std::strtod(begin, &end);
  if (end == begin || *end != '\0')
    failLine(path, line, std::string(what) + " '" + field + "' is not a number");
  if (!std::isfinite(value))
    failLine(path, line, std::string(what) + " '" + field + "' is not a finite number");
  return value;
}

/// A line of a TUM text file that holds data: its number (from 1) and its
/// whitespace-separated fields.
struct Record {
  std::size_t line = 0;
  std::vector<std::string> fields;
};

/// The records of a small text file (refused over kMaxListBytes): blank lines and lines
/// whose first field starts with '#' are skipped; a Windows line end is one.
std::vector<Record> readRecords(const std::string& path)
{
  InputLimits limits = defaultInputLimits();
  if (limits.max_file_bytes == 0 || limits.max_file_bytes > kMaxListBytes)
    limits.max_file_bytes = kMaxListBytes;
  std::istringstream in(detail::readFileToString(path, limits));
  std::vector<Record> records;
  std::string text;
  for (std::size_t line = 1; std::getline(in, text); ++line) {
    std::istringstream words(text); // '\r' is whitespace
    Record r;
    r.line = line;
    for (std::string field; words >> field;) {
      if (r.fields.empty() && field[0] == '#')
        break;
      r.fields.push_back(field);
    }
    if (!r.fields.empty())
      records.push_back(std::move(r));
  }
  return records;
}

void readPinholeMatrix(const YamlReader& reader, const YAML::Node& node,
                       const std::string& path, CameraIntrinsics& K)
{
  std::vector<double> data;
  reader.forEach(node, path,
                 {{"rows",
                   [&](const YAML::Node& v, const std::string& p) {
                     if (reader.read<int>(v, p, "an integer") != 3)
                       reader.fail(p, "expected 3, got " + YamlReader::describe(v));
                   }},
                  {"cols",
                   [&](const YAML::Node& v, const std::string& p) {
                     if (reader.read<int>(v, p, "an integer") != 3)
                       reader.fail(p, "expected 3, got " + YamlReader::describe(v));
                   }},
                  {"data", [&](const YAML::Node& v, const std::string& p) {
                     data = reader.readNumbers(v, p, 9);
                   }}});
  const std::string data_path = YamlReader::child(path, "data");
  if (data.empty())
    reader.fail(data_path, "missing (the 9 numbers fx, 0, cx, 0, fy, cy, 0, 0, 1)");
  if (data[1] != 0.0 || data[3] != 0.0 || data[6] != 0.0 || data[7] != 0.0 ||
      data[8] != 1.0)
    reader.fail(data_path,
                "expected a pinhole matrix [fx, 0, cx, 0, fy, cy, 0, 0, 1], got " +
                    YamlReader::describe(node["data"]));
  K.fx = data[0];
  K.cx = data[2];
  K.fy = data[4];
  K.cy = data[5];
}

void readDistortion(const YamlReader& reader, const YAML::Node& node,
                    const std::string& path)
{
  const auto ignoreInt = [&](const YAML::Node& v, const std::string& p) {
    reader.read<int>(v, p, "an integer");
  };
  reader.forEach(node, path,
                 {{"rows", ignoreInt},
                  {"cols", ignoreInt},
                  {"data", [&](const YAML::Node& v, const std::string& p) {
                     const std::vector<double> k =
                         reader.readList<double>(v, p, "numbers");
                     for (double c : k)
                       if (c != 0.0)
                         reader.fail(p, "non-zero distortion " + YamlReader::describe(v) +
                                            ": rectify the depth images first (aligned "
                                            "depth streams are rectified) and give zero "
                                            "coefficients");
                   }}});
}

std::string formatStamp(double stamp_s)
{
  std::ostringstream s;
  s << std::fixed << std::setprecision(6) << stamp_s;
  return s.str();
}

/// For each line of depth.txt, the line of detections.txt whose stamp is within
/// kMaxDetectionDt_s of its own (null if none). Every line of detections.txt must
/// belong to a frame, and a frame has at most one.
std::vector<const StampedFile*>
matchDetections(const std::vector<StampedFile>& frames, const std::string& frames_path,
                const std::vector<StampedFile>& detections,
                const std::string& detections_path)
{
  std::vector<const StampedFile*> sorted;
  for (const StampedFile& d : detections)
    sorted.push_back(&d);
  std::stable_sort(
      sorted.begin(), sorted.end(),
      [](const StampedFile* a, const StampedFile* b) { return a->stamp_s < b->stamp_s; });
  std::vector<const StampedFile*> match(frames.size(), nullptr);
  std::vector<bool> used(detections.size(), false);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const StampedFile& f = frames[i];
    auto it = std::lower_bound(
        sorted.begin(), sorted.end(), f.stamp_s - kMaxDetectionDt_s,
        [](const StampedFile* d, double stamp) { return d->stamp_s < stamp; });
    for (; it != sorted.end() && (*it)->stamp_s <= f.stamp_s + kMaxDetectionDt_s; ++it) {
      const StampedFile* d = *it;
      used[std::size_t(d - detections.data())] = true;
      if (!match[i]) {
        match[i] = d;
        continue;
      }
      const StampedFile* second = match[i]->line > d->line ? match[i] : d;
      const StampedFile* first = second == d ? match[i] : d;
      failLine(detections_path, second->line,
               "'" + second->file + "' is a second detection file for frame '" + f.file +
                   "' (" + formatStamp(f.stamp_s) + " s, line " + std::to_string(f.line) +
                   " of " + inQuotes(frames_path) + "; line " +
                   std::to_string(first->line) + " lists '" + first->file + "')");
    }
  }
  for (std::size_t k = 0; k < detections.size(); ++k)
    if (!used[k])
      failLine(detections_path, detections[k].line,
               "'" + detections[k].file + "' (" + formatStamp(detections[k].stamp_s) +
                   " s) matches no frame of " + inQuotes(frames_path) +
                   " (a detection file takes the frame of its stamp, within 1e-6 s)");
  return match;
}

} // namespace

CameraInfo readCameraInfo(const std::string& path)
{
  const YamlReader reader(path);
  const YAML::Node root = reader.parse(YamlReader::readText(path));
  CameraInfo info;
  CameraIntrinsics& K = info.intrinsics;
  bool width = false, height = false, matrix = false;
  const auto ignore = [](const YAML::Node&, const std::string&) {};
  const auto readSide = [&](bool& seen, std::uint32_t& side) {
    return [&](const YAML::Node& v, const std::string& p) {
      const long long n = reader.read<long long>(v, p, "an integer");
      if (n < 1 || n > 16384)
        reader.fail(p, "expected 1 to 16384 pixels, got " + YamlReader::describe(v));
      side = static_cast<std::uint32_t>(n);
      seen = true;
    };
  };
  reader.forEach(
      root, "",
      {{"image_width", readSide(width, K.width)},
       {"image_height", readSide(height, K.height)},
       {"camera_matrix",
        [&](const YAML::Node& v, const std::string& p) {
          readPinholeMatrix(reader, v, p, K);
          matrix = true;
        }},
       {"distortion_model",
        [&](const YAML::Node& v, const std::string& p) {
          info.distortion_model = reader.read<std::string>(v, p, "a name");
        }},
       {"distortion_coefficients",
        [&](const YAML::Node& v, const std::string& p) { readDistortion(reader, v, p); }},
       {"depth_scale",
        [&](const YAML::Node& v, const std::string& p) {
          info.depth_scale = reader.read<double>(v, p, "a number");
          if (!(info.depth_scale > 0.0) || !std::isfinite(info.depth_scale))
            reader.fail(p, "expected units per metre > 0 (1000: millimetres), got " +
                               YamlReader::describe(v));
        }},
       {"camera_name", ignore},
       {"rectification_matrix", ignore},
       {"projection_matrix", ignore},
       {"binning_x", ignore},
       {"binning_y", ignore},
       {"roi", ignore}});
  if (!width)
    reader.fail("image_width", "missing");
  if (!height)
    reader.fail("image_height", "missing");
  if (!matrix)
    reader.fail("camera_matrix",
                "missing (rows: 3, cols: 3, data: [fx, 0, cx, 0, fy, cy, "
                "0, 0, 1])");
  try {
    K.validate();
  } catch (const InvalidArgumentError& e) {
    reader.fail("camera_matrix", e.what());
  }
  return info;
}

void writeCameraInfo(const std::string& path, const CameraInfo& info)
{
  const CameraIntrinsics& K = info.intrinsics;
  AtomicFile file(path);
  std::ostream& out = file.stream();
  out << std::setprecision(17);
  out << "# ROS camera_info (as camera_calibration writes it) + depth_scale (plantnbv)\n"
      << "image_width: " << K.width << "\nimage_height: " << K.height
      << "\ncamera_name: depth\ncamera_matrix:\n  rows: 3\n  cols: 3\n  data: [" << K.fx
      << ", 0, " << K.cx << ", 0, " << K.fy << ", " << K.cy << ", 0, 0, 1]\n"
      << "distortion_model: " << info.distortion_model
      << "\ndistortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [0, 0, 0, 0, 0]\n"
      << "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, "
         "1]\n"
      << "projection_matrix:\n  rows: 3\n  cols: 4\n  data: [" << K.fx << ", 0, " << K.cx
      << ", 0, 0, " << K.fy << ", " << K.cy << ", 0, 0, 0, 1, 0]\n"
      << "depth_scale: " << info.depth_scale << "\n";
  file.commit();
}

std::vector<StampedFile> readTumFileList(const std::string& path)
{
  std::vector<StampedFile> files;
  for (const Record& r : readRecords(path)) {
    const std::vector<std::string>& fields = r.fields;
    const std::size_t line = r.line;
    if (fields.size() != 2)
      failLine(path, line,
               "expected 'timestamp filename', got " + std::to_string(fields.size()) +
                   " fields");
    StampedFile f;
    f.stamp_s = finiteNumber(path, line, fields[0], "timestamp");
    f.file = fields[1];
    f.line = line;
    if (!detail::staysInside(f.file))
      failLine(path, line,
               "'" + f.file + "' must be a path inside the folder (relative, no '..')");
    files.push_back(f);
  }
  return files;
}

std::vector<StampedPose> readTumTrajectory(const std::string& path)
{
  std::vector<StampedPose> poses;
  static const char* kNames[] = {"timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};
  for (const Record& r : readRecords(path)) {
    const std::vector<std::string>& fields = r.fields;
    const std::size_t line = r.line;
    if (fields.size() != 8)
      failLine(path, line,
               "expected 8 numbers 'timestamp tx ty tz qx qy qz qw', got " +
                   std::to_string(fields.size()));
    double v[8];
    for (int k = 0; k < 8; ++k)
      v[k] = finiteNumber(path, line, fields[std::size_t(k)], kNames[k]);
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    const double norm = q.norm();
    if (!(std::abs(norm - 1.0) <= kQuaternionNormTolerance))
      failLine(path, line,
               "quaternion (" + fields[4] + ", " + fields[5] + ", " + fields[6] + ", " +
                   fields[7] + ") has norm " + shortestText(norm) +
                   ", expected a unit quaternion (within 1e-3)");
    StampedPose p;
    p.stamp_s = v[0];
    p.pose = Pose(Eigen::Vector3d(v[1], v[2], v[3]), q); // normalizes
    // A quaternion that is a unit one to double precision (FramesFolderWriter's, 17
    // digits) is kept as written: normalizing it again moves its last bits in a third of
    // cases, and a replayed folder would not give the poses it was written with.
    if (std::abs(norm - 1.0) <= kUnitNormRounding)
      p.pose.orientation = q;
    p.line = line;
    poses.push_back(p);
  }
  return poses;
}

FramesFolder::FramesFolder(const std::string& folder, const FramesFolderOptions& options)
    : folder_(folder)
{
  std::error_code ec;
  if (fs::exists(folder, ec) && !fs::is_directory(folder, ec))
    throw IoError(inQuotes(folder) + ": is not a folder (a frames folder: camera.yaml, "
                                     "depth.txt, groundtruth.txt, depth/)");
  if (!fs::is_directory(folder, ec))
    throw FileNotFoundError(inQuotes(folder) +
                            ": no such folder (a frames folder: camera.yaml, "
                            "depth.txt, groundtruth.txt, depth/)");
  const fs::path dir(folder);
  const std::string camera_path = (dir / "camera.yaml").string();
  if (!fs::exists(camera_path, ec))
    throw FileNotFoundError(inQuotes(camera_path) +
                            ": no such file (the camera's calibration, ROS "
                            "camera_info YAML)");
  camera_ = readCameraInfo(camera_path);
  if (options.depth_scale != 0.0) {
    if (!(options.depth_scale > 0.0) || !std::isfinite(options.depth_scale))
      throw InvalidArgumentError("depth scale must be > 0 units per metre, got " +
                                 shortestText(options.depth_scale));
    camera_.depth_scale = options.depth_scale;
  }
  const std::string list_path = (dir / "depth.txt").string();
  if (!fs::exists(list_path, ec))
    throw FileNotFoundError(inQuotes(list_path) +
                            ": no such file (\"timestamp filename\" per frame)");
  std::string poses_path = (dir / "groundtruth.txt").string();
  if (!fs::exists(poses_path, ec))
    poses_path = (dir / "poses.txt").string();
  if (!fs::exists(poses_path, ec))
    throw FileNotFoundError(
        inQuotes((dir / "groundtruth.txt").string()) +
        ": no such file, nor poses.txt (\"timestamp tx ty tz qx qy qz qw\" per "
        "pose)");
  const std::vector<StampedFile> files = readTumFileList(list_path);
  std::vector<StampedPose> poses = readTumTrajectory(poses_path);
  if (files.empty())
    throw FormatError(inQuotes(list_path) + ": lists no frame");
  const std::string detections_path = (dir / "detections.txt").string();
  std::vector<StampedFile> detections;
  if (fs::exists(detections_path, ec))
    detections = readTumFileList(detections_path);
  const std::vector<const StampedFile*> frame_detections =
      matchDetections(files, list_path, detections, detections_path);
  std::stable_sort(
      poses.begin(), poses.end(),
      [](const StampedPose& a, const StampedPose& b) { return a.stamp_s < b.stamp_s; });
  for (std::size_t i = 0; i < files.size(); ++i) {
    const StampedFile& f = files[i];
    // The nearest pose: the first at or after the stamp, or the one before it.
    const auto after = std::lower_bound(
        poses.begin(), poses.end(), f.stamp_s,
        [](const StampedPose& p, double stamp) { return p.stamp_s < stamp; });
    const StampedPose* best = nullptr;
    if (after != poses.end())
      best = &*after;
    if (after != poses.begin() &&
        (!best || f.stamp_s - std::prev(after)->stamp_s <= best->stamp_s - f.stamp_s))
      best = &*std::prev(after);
    const double dt = best ? std::abs(best->stamp_s - f.stamp_s) : INFINITY;
    if (!(dt <= options.max_pose_dt_s)) {
      if (options.skip_unmatched) {
        ++skipped_;
        continue;
      }
      std::ostringstream s;
      s << "frame '" << f.file << "' (" << formatStamp(f.stamp_s) << " s) has no pose in "
        << inQuotes(poses_path) << " within " << options.max_pose_dt_s << " s";
      if (best)
        s << " (nearest " << formatStamp(best->stamp_s) << " s)";
      s << "; --skip-unmatched skips such frames";
      failLine(list_path, f.line, s.str());
    }
    FrameRecord r;
    r.stamp_s = f.stamp_s;
    r.depth_path = (dir / f.file).string();
    r.T_W_O = best->pose;
    r.pose_dt_s = dt;
    if (frame_detections[i])
      r.detections_path = (dir / frame_detections[i]->file).string();
    frames_.push_back(r);
  }
  if (frames_.empty())
    throw FormatError(inQuotes(list_path) + ": none of its " +
                      std::to_string(files.size()) + " frames has a pose within " +
                      shortestText(options.max_pose_dt_s) + " s in " +
                      inQuotes(poses_path));
}

void FramesFolder::loadDepth(std::size_t i, DepthImage& depth) const
{
  const FrameRecord& frame = frames_.at(i);
  const CameraIntrinsics& K = camera_.intrinsics;
  // The size is checked from the header, before the pixels are allocated.
  loadDepthPng(frame.depth_path, depth, camera_.depth_scale, K.width, K.height);
}

void FramesFolder::loadDetections(std::size_t i, std::vector<Detection>& detections) const
{
  const FrameRecord& frame = frames_.at(i);
  if (frame.detections_path.empty()) {
    detections.clear();
    return;
  }
  const CameraIntrinsics& K = camera_.intrinsics;
  detections = readDetections(frame.detections_path, K.width, K.height);
}

FramesFolderWriter::FramesFolderWriter(const std::string& folder,
                                       const CameraInfo& camera)
    : folder_(folder), camera_(camera)
{
  camera_.intrinsics.validate();
  if (!(camera_.depth_scale > 0.0) || !std::isfinite(camera_.depth_scale))
    throw InvalidArgumentError("depth scale must be > 0 units per metre, got " +
                               shortestText(camera_.depth_scale));
  const fs::path dir(folder);
  std::error_code ec;
  fs::create_directories(dir / "depth", ec);
  if (ec)
    throw IoError("cannot create the frames folder " + inQuotes(folder) + ": " +
                  ec.message());
  const std::string camera_path = (dir / "camera.yaml").string();
  if (fs::exists(camera_path, ec)) {
    const CameraInfo there = readCameraInfo(camera_path);
    const CameraIntrinsics &a = there.intrinsics, &b = camera_.intrinsics;
    if (a.width != b.width || a.height != b.height || a.fx != b.fx || a.fy != b.fy ||
        a.cx != b.cx || a.cy != b.cy || there.depth_scale != camera_.depth_scale)
      throw FormatError(inQuotes(camera_path) + " describes another camera (" +
                        a.toString() + ", depth_scale " +
                        shortestText(there.depth_scale) +
                        "): write these frames to a new folder");
  } else {
    writeCameraInfo(camera_path, camera_);
  }
  const std::string list_path = (dir / "depth.txt").string();
  if (fs::exists(list_path, ec))
    for (const StampedFile& f : readTumFileList(list_path)) {
      ++count_;
      last_stamp_s_ = std::max(last_stamp_s_, f.stamp_s);
    }
  // Appended to as it is: it must be readable.
  const std::string detections_path = (dir / "detections.txt").string();
  if (fs::exists(detections_path, ec))
    readTumFileList(detections_path);
}

void FramesFolderWriter::append(const DepthImage& depth, const Pose& T_W_O,
                                double stamp_s, const std::vector<Detection>* detections)
{
  const CameraIntrinsics& K = camera_.intrinsics;
  if (depth.width != K.width || depth.height != K.height)
    throw InvalidArgumentError(
        "frames folder " + inQuotes(folder_) + ": a " + std::to_string(depth.width) +
        "x" + std::to_string(depth.height) + " frame for a " + std::to_string(K.width) +
        "x" + std::to_string(K.height) + " camera");
  if (std::isnan(stamp_s))
    stamp_s = count_ == 0 ? 0.0 : last_stamp_s_ + 1.0;
  if (!std::isfinite(stamp_s) || (count_ > 0 && !(stamp_s > last_stamp_s_)))
    throw InvalidArgumentError(
        "frames folder " + inQuotes(folder_) + ": stamp " + formatStamp(stamp_s) +
        " s is not after the folder's last frame (" + formatStamp(last_stamp_s_) + " s)");
  const fs::path dir(folder_);
  char name[32];
  std::snprintf(name, sizeof(name), "depth/%06zu.png", count_);
  const std::string png_path = (dir / name).string();
  std::error_code ec;
  if (fs::exists(png_path, ec))
    throw IoError(inQuotes(png_path) +
                  " exists but depth.txt does not list it: refusing to "
                  "overwrite it");
  // The detection files of this frame: the JSON and the masks writeDetections names.
  char json_name[32];
  std::snprintf(json_name, sizeof(json_name), "detections/%06zu.json", count_);
  std::vector<std::string> detection_files;
  if (detections) {
    detection_files.push_back((dir / json_name).string());
    for (std::size_t k = 0; k < detections->size(); ++k)
      if (!(*detections)[k].mask.empty()) {
        char mask_name[48];
        std::snprintf(mask_name, sizeof(mask_name), "detections/%06zu_%zu.png", count_,
                      k);
        detection_files.push_back((dir / mask_name).string());
      }
    for (const std::string& file : detection_files)
      if (fs::exists(file, ec))
        throw IoError(inQuotes(file) +
                      " exists but detections.txt does not list it: refusing to "
                      "overwrite it");
  }
  const auto removeDetectionFiles = [&] {
    for (const std::string& file : detection_files)
      fs::remove(file, ec);
  };
  saveDepthPng(png_path, depth.width, depth.height, depth.depth_m, camera_.depth_scale);
  if (detections) {
    try {
      fs::create_directories(dir / "detections", ec);
      if (ec)
        throw IoError("cannot create " + inQuotes((dir / "detections").string()) + ": " +
                      ec.message());
      writeDetections(detection_files.front(), *detections, K.width, K.height);
    } catch (const Error&) {
      removeDetectionFiles();
      fs::remove(png_path, ec);
      throw;
    }
  }

  // Each list is written again whole with its new line (a few bytes a frame beside a
  // depth PNG), both prepared before either replaces its file: a full disk leaves the
  // lists as they were, never a torn line or a pose without its image.
  const auto withLine = [&](const std::string& file, const char* header,
                            const std::string& line) {
    const std::string path = (dir / file).string();
    auto out = std::make_unique<AtomicFile>(path);
    out->stream() << (fs::exists(path, ec)
                          ? detail::readFileToString(path, defaultInputLimits())
                          : std::string(header))
                  << line << '\n';
    return out;
  };
  const std::string stamp = formatStamp(stamp_s);
  const Eigen::Vector3d& t = T_W_O.position;
  const Eigen::Quaterniond& q = T_W_O.orientation;
  std::ostringstream pose;
  pose << stamp << std::setprecision(17) << ' ' << t.x() << ' ' << t.y() << ' ' << t.z()
       << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w();
  std::unique_ptr<AtomicFile> detection_list;
  try {
    const auto poses =
        withLine("groundtruth.txt",
                 "# T_W_O: the depth camera's optical frame (z forward, x right, y down) "
                 "in the world (z up)\n# timestamp tx ty tz qx qy qz qw\n",
                 pose.str());
    const auto frames =
        withLine("depth.txt",
                 "# depth images (16-bit PNG, depth_scale units per metre "
                 "in camera.yaml)\n# timestamp filename\n",
                 stamp + ' ' + name);
    if (detections)
      detection_list = withLine("detections.txt",
                                "# 2D detections of the depth frames (JSON, "
                                "docs/real-robot.md)\n# timestamp filename\n",
                                stamp + ' ' + json_name);
    poses->prepare();
    frames->prepare();
    if (detection_list)
      detection_list->prepare();
    poses->commit();
    frames->commit();
  } catch (const Error&) {
    fs::remove(png_path, ec); // unlisted, it would stop the next frame
    removeDetectionFiles();
    throw;
  }
  ++count_;
  last_stamp_s_ = stamp_s;
  // Last: a frame listed without its detections is a valid folder, detections listed
  // without their frame are not.
  if (detection_list) {
    try {
      detection_list->commit();
    } catch (const Error&) {
      removeDetectionFiles();
      throw;
    }
  }
}

} // namespace io
} // namespace plantnbv
