#pragma once
/// \file detections_io.h
/// \brief 2D detections of one depth frame (what YOLO-style and Mask R-CNN-style
/// detectors give): a JSON file per frame, with optional instance masks as 8-bit grey
/// PNGs beside it (docs/real-robot.md, "Detections").
///
/// \code
/// {"detections": [
///   {"class": "leaf_node", "score": 0.9, "box": [12.5, 40, 30, 61.25]},
///   {"class": "fruit", "score": 0.75, "box": [100, 80, 140, 122], "mask":
///   "000001_1.png"}
/// ]}
/// \endcode
///
/// - `class`: a non-empty string (required). Any class is accepted; consumers filter.
/// - `score`: a number in [0, 1] (required).
/// - `box`: [u0, v0, u1, v1] in pixels (required): the box's edges, in the continuous
///   image coordinates where pixel u spans [u, u + 1) (COCO, Detectron2, YOLO in
///   pixels); 0 <= u0 <= u1 <= width, 0 <= v0 <= v1 <= height. Pixel (u, v) is in the
///   box when its centre is: u0 <= u + 0.5 <= u1 and v0 <= v + 0.5 <= v1. (The camera
///   model puts pixel centres at integer coordinates for rays; only boxes use edges.)
/// - `mask` (optional): an 8-bit grey PNG of exactly the depth image's size, a path
///   relative to the JSON file's folder that stays inside it (no "..", not absolute);
///   non-zero pixels are the instance's.
/// - No other key, in an entry or at the top level; a key may not be repeated.
///
/// Every error on a file is a FormatError (or IoError / FileNotFoundError for a file that
/// cannot be read) whose one-line message names the file and the entry:
/// "'det/000001.json' detections[2].score: 1.5 is not in [0, 1]".

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <plantnbv/camera/detection.h>

namespace plantnbv {
namespace io {

/// \brief The most detections one file may hold; a file with more is refused (a
/// detector gives tens to a few hundred).
constexpr std::size_t kMaxDetectionsPerFrame = 10000;
/// \brief The most bytes the masks of one file may take once read (width * height per
/// mask, 1 GiB): one PNG named by every entry is refused before it exhausts memory.
constexpr std::uint64_t kMaxMaskBytesPerFrame = std::uint64_t{1} << 30;

/// \brief Reads a detection file (the format above), loading each entry's mask, if it has
/// one, into Detection::mask.
/// \param[in] path the JSON file
/// \param[in] width the depth image's width, pixels (boxes and masks are checked against
/// it)
/// \param[in] height the depth image's height, pixels
/// \return the detections in the file's order.
/// \throws InvalidArgumentError if width or height is not in 1 to 16384; IoError /
/// FileNotFoundError if the file or a mask cannot be read; FormatError for malformed
/// JSON, a missing, repeated or unknown key, a value of the wrong type or out of range,
/// a mask that is not an 8-bit grey PNG of width x height, more than
/// kMaxDetectionsPerFrame entries or masks over kMaxMaskBytesPerFrame, a file over
/// 64 MiB (or defaultInputLimits().max_file_bytes if smaller). Thread-safe.
std::vector<Detection> readDetections(const std::string& path, std::uint32_t width,
                                      std::uint32_t height);

/// \brief Writes a detection file that readDetections reads back exactly (scores and
/// boxes to the last bit). Masks are written first, as PNGs named `<stem>_<k>.png`
/// beside the file (`000001.json`: `000001_0.png` for detections[0]), then the JSON;
/// each file whole or not at all. Masks of an earlier file of the same name that the new
/// one does not name are left as they are.
/// \param[in] path the JSON file
/// \param[in] detections what to write (an empty list: a frame where nothing was found)
/// \param[in] width the depth image's width, pixels
/// \param[in] height the depth image's height, pixels
/// \throws InvalidArgumentError "'PATH' detections[k].FIELD: ..." for what
/// readDetections would refuse (an empty class, a class that is not UTF-8, a score
/// outside [0, 1], a box outside the image, a mask of the wrong size, too many); IoError
/// if a file cannot be written.
void writeDetections(const std::string& path, const std::vector<Detection>& detections,
                     std::uint32_t width, std::uint32_t height);

} // namespace io
} // namespace plantnbv
