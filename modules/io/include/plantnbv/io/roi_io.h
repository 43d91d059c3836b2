#pragma once
/// \file roi_io.h
/// \brief ROI files: YAML boxes in metres, each with an optional name and either a
/// centre and a size (full side lengths; the form saveRoi writes) or its lowest and
/// highest corners `min` and `max` (the form of the ROI viewpoint planner, Zaenker et
/// al.'s roi_viewpoint_planner). The boxes come under `boxes:` or, in the planner's
/// form, as the top-level list itself:
/// \code{.yaml}
/// boxes:
///   - name: main_stem
///     center: [1.0, 0.0, 1.15]
///     size: [0.05, 0.05, 0.7]
///   - min: [0.98, -0.02, 0.92]
///     max: [1.02, 0.02, 0.98]
/// \endcode
/// \code{.yaml}
/// - {min: [0.5, -0.25, 1.0], max: [1.5, 0.25, 2.0]}
/// - name: leaf
///   min: [0.9, -0.1, 1.2]
///   max: [1.1, 0.1, 1.4]
/// \endcode
/// A box given by corners has centre (min + max) / 2 and size max - min.
///
/// Frame: both forms are read in the world frame the plant stands in. Boxes drawn in a
/// model file's own coordinates (as the ROI viewpoint planner's are, in its Gazebo
/// world) match the plant when it is loaded with `--keep-frame` (docs/plants.md).

#include <string>

#include <plantnbv/common/box.h>

namespace plantnbv {
namespace io {

/// \brief Reads an ROI file in either form (see the file comment). Keys other than
/// `boxes` (top level) and `name` with `center` and `size` or with `min` and `max` (in a
/// box) are rejected. A file over defaultInputLimits().max_file_bytes is refused before
/// it is read.
/// \throws IoError if missing or unreadable; FormatError naming the file, the box index
/// (from 0) and the key (io::YamlReader's messages), e.g. "'rois.yaml' boxes[2].size:
/// expected 3 non-negative numbers, got [0.1, -0.2, 0.3]" ("'rois.yaml' [2]: ..." in a
/// top-level list), for malformed YAML, a missing key, a vector without exactly 3
/// numbers, a NaN or infinite centre, size or corner, a size that is not > 0 on every
/// axis or a min that is not < max on every axis (a box without volume: a score over it
/// would mean nothing), a box mixing center/size with min/max, corners that overflow to
/// infinity, an unknown key, or a file without boxes; FormatError naming the cap for a
/// file over the size limit.
Roi loadRoi(const std::string& path);

/// \brief Writes an ROI file that loadRoi reads back exactly: each number in the
/// shortest decimal form that reads back as the same double (at most 17 significant
/// digits), names quoted when YAML could misread them, unnamed boxes without `name`.
/// \throws IoError if the file cannot be written; InvalidArgumentError for an empty ROI
/// (an ROI file needs boxes) or a non-finite value.
void saveRoi(const std::string& path, const Roi& roi);

} // namespace io
} // namespace plantnbv
