#pragma once
/// \file frames_folder.h
/// \brief Frames folders: depth frames and camera poses in the layout of the TUM RGB-D
/// benchmark, with the camera's calibration as ROS camera_info YAML, so that frames from
/// a robot, a ROS bag, a RealSense recording or another simulator come in, and our
/// simulated camera's go out (docs/real-robot.md).
///
/// \code
/// FRAMES/
///   camera.yaml      ROS camera_info (image_width, image_height, camera_matrix,
///                    distortion_model, distortion_coefficients) + optional depth_scale
///   depth.txt        "timestamp filename" per line, '#' comments
///   groundtruth.txt  "timestamp tx ty tz qx qy qz qw" per line: T_W_O, the camera's
///                    optical frame (z forward, x right, y down) in the world (z up);
///                    poses.txt is read when groundtruth.txt is absent
///   depth/*.png      16-bit grey, depth_scale units per metre, 0 = no return
///   detections.txt   optional: "timestamp filename" per line, '#' comments, listing
///                    the frames' detection files
///   detections/*.json  2D detections of a frame, with their masks (detections_io.h)
/// \endcode
///
/// A frame takes the detection file whose stamp equals its depth stamp within
/// kMaxDetectionDt_s (1e-6 s: the same microsecond, as written with 6 decimals). A line
/// of detections.txt that matches no line of depth.txt, or a second one for the same
/// frame, is an error naming it; the detections of a frame skipped for want of a pose are
/// ignored with it. A frame with no line in detections.txt has no detections (the
/// detector did not run on it); an empty list means it found nothing.
///
/// Every error is a FormatError or IoError naming the file and, for text files, the line.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <plantnbv/camera/camera_intrinsics.h>
#include <plantnbv/camera/depth_image.h>
#include <plantnbv/common/pose.h>
#include <plantnbv/io/detections_io.h>

namespace plantnbv {
namespace io {

/// \brief A detection file belongs to the frame whose depth stamp is within this of its
/// own, seconds.
constexpr double kMaxDetectionDt_s = 1e-6;

/// \brief What camera.yaml says: pinhole intrinsics (range limits as CameraIntrinsics'
/// defaults) and the depth PNGs' units.
struct CameraInfo {
  CameraIntrinsics intrinsics; ///< image size, fx fy cx cy (pixels)
  /// Units of the depth PNGs per metre, > 0 (1000: millimetres, RealSense; TUM's own
  /// sequences: 5000). Default 1000.
  double depth_scale = 1000.0;
  /// As the file names it; only zero distortion coefficients are accepted.
  std::string distortion_model = "plumb_bob";
};

/// \brief Reads a ROS camera_info YAML file (as camera_calibration writes it) with an
/// optional `depth_scale`. camera_matrix must be a pinhole matrix [fx 0 cx; 0 fy cy;
/// 0 0 1]; every distortion coefficient must be 0 (depth streams aligned by the driver
/// are rectified; rectify others first). rectification_matrix, projection_matrix,
/// camera_name, binning_x/y and roi are accepted and not used.
/// \throws IoError if unreadable; FormatError "'camera.yaml' key: ..." otherwise.
CameraInfo readCameraInfo(const std::string& path);
/// \brief Writes camera.yaml in the form readCameraInfo reads (and ROS tools read).
/// \throws IoError.
void writeCameraInfo(const std::string& path, const CameraInfo& info);

/// \brief A line of a TUM file list ("timestamp filename").
struct StampedFile {
  double stamp_s = 0.0; ///< timestamp, seconds
  std::string file;     ///< as written, relative to the folder
  std::size_t line = 0; ///< its line in the file (from 1), for messages
};
/// \brief A line of a TUM trajectory ("timestamp tx ty tz qx qy qz qw").
struct StampedPose {
  double stamp_s = 0.0; ///< timestamp, seconds
  Pose pose;            ///< the quaternion normalized
  std::size_t line = 0; ///< its line in the file (from 1), for messages
};

/// \brief Reads depth.txt (or detections.txt). Blank lines and lines starting with '#'
/// are skipped; a file name must be relative and must not leave the folder ("..").
/// \throws IoError, FormatError "'depth.txt' line N: ...".
std::vector<StampedFile> readTumFileList(const std::string& path);
/// \brief Reads groundtruth.txt / poses.txt: 8 finite numbers per line; a quaternion
/// whose norm is within 1e-3 of 1 is normalized, any other is refused.
/// \throws IoError, FormatError "'groundtruth.txt' line N: ...".
std::vector<StampedPose> readTumTrajectory(const std::string& path);

/// \brief One depth frame of a folder and its pose.
struct FrameRecord {
  double stamp_s = 0.0;   ///< the depth image's timestamp (depth.txt), seconds
  std::string depth_path; ///< the PNG's path (folder + file)
  Pose T_W_O;             ///< the optical frame's pose
  double pose_dt_s = 0.0; ///< |depth stamp - pose stamp|
  /// The detection file's path (folder + file, from detections.txt); empty when the
  /// frame has none.
  std::string detections_path;
};

/// \brief How a folder's frames are matched with poses.
struct FramesFolderOptions {
  /// A frame takes the pose with the nearest timestamp within this (TUM's associate
  /// convention, 0.02 s).
  double max_pose_dt_s = 0.02;
  /// Frames with no pose near them are skipped (counted) instead of refused.
  bool skip_unmatched = false;
  /// > 0: replaces camera.yaml's depth_scale.
  double depth_scale = 0.0;
};

/// \brief A frames folder, opened: its camera, and its frames in depth.txt's order, each
/// with its pose.
///
/// \code
/// io::FramesFolder folder("FRAMES");
/// DepthImage depth;
/// for (std::size_t i = 0; i < folder.frames().size(); ++i) {
///   folder.loadDepth(i, depth);
///   session.integrate(depth, folder.camera().intrinsics, folder.frames()[i].T_W_O);
/// }
/// \endcode
class FramesFolder {
public:
  /// \brief Reads camera.yaml, depth.txt and groundtruth.txt (or poses.txt) and matches
  /// frames to poses, and detections.txt when there is one and matches frames to
  /// detection files; the PNGs are read by loadDepth, the detections by loadDetections.
  /// \throws IoError naming a missing file; FormatError for a bad line, a frame with no
  /// pose near it (unless skip_unmatched), a folder with no frame, a line of
  /// detections.txt that matches no frame or a frame that has one already.
  explicit FramesFolder(const std::string& folder,
                        const FramesFolderOptions& options = {});

  /// \brief The folder's path, as given.
  const std::string& folder() const { return folder_; }
  /// \brief camera.yaml (depth_scale replaced by the options' when they give one).
  const CameraInfo& camera() const { return camera_; }
  /// \brief The frames, in depth.txt's order, each with its matched pose.
  const std::vector<FrameRecord>& frames() const { return frames_; }
  /// \brief Frames of depth.txt skipped for want of a pose (skip_unmatched).
  std::size_t skippedFrames() const { return skipped_; }

  /// \brief Reads frame i's PNG in the camera's depth units.
  /// \throws IoError if missing; FormatError if it is not a 16-bit grey PNG, is
  /// truncated, or its size differs from camera.yaml's.
  void loadDepth(std::size_t i, DepthImage& depth) const;

  /// \brief Reads frame i's detections (readDetections, checked against the camera's
  /// image size); empty when the frame has no detection file.
  /// \throws what readDetections throws.
  void loadDetections(std::size_t i, std::vector<Detection>& detections) const;

private:
  std::string folder_;
  CameraInfo camera_;
  std::vector<FrameRecord> frames_;
  std::size_t skipped_ = 0;
};

/// \brief Appends frames to a frames folder (created if missing): camera.yaml on first
/// use, depth/NNNNNN.png, a line in depth.txt and in groundtruth.txt per frame, and for
/// a frame given detections, detections/NNNNNN.json (the same NNNNNN; masks
/// detections/NNNNNN_k.png) and a line in detections.txt.
///
/// Appending to a folder keeps what is there: the camera must be the one of its
/// camera.yaml, a stamp must be later than the last one, and a PNG or detection file is
/// never overwritten. The files are written before the lines, and detections.txt's line
/// last, so an interrupted append leaves at most unlisted files or a frame without its
/// detections.
class FramesFolderWriter {
public:
  /// \throws IoError if the folder cannot be made; FormatError if it holds a
  /// camera.yaml of another camera or an unreadable depth.txt.
  FramesFolderWriter(const std::string& folder, const CameraInfo& camera);

  /// \brief Frames listed in depth.txt (those there before, and those appended).
  std::size_t frameCount() const { return count_; }
  /// \brief The stamp of the last frame; -1 if none.
  double lastStamp() const { return last_stamp_s_; }

  /// \brief Appends one frame: `depth` written in the camera's depth_scale (so NaN and
  /// depths that round to 0 read back as no return), T_W_O its optical frame.
  /// \param[in] depth the frame, of the camera's size
  /// \param[in] T_W_O its optical frame in the world
  /// \param[in] stamp_s its timestamp; NaN: the last one + 1 s (0 for the first).
  /// \param[in] detections when not null, the frame's detections (an empty list: the
  /// detector found nothing), written by writeDetections; null: none (default).
  /// \throws InvalidArgumentError for a size other than the camera's, a stamp not after
  /// the last, or detections writeDetections refuses; IoError if a file cannot be
  /// written or a detection file of this frame's number exists (unlisted).
  void append(const DepthImage& depth, const Pose& T_W_O, double stamp_s,
              const std::vector<Detection>* detections = nullptr);

private:
  std::string folder_;
  CameraInfo camera_;
  std::size_t count_ = 0;
  double last_stamp_s_ = -1.0;
};

} // namespace io
} // namespace plantnbv
