#pragma once
/// \file roi_io.h
/// \brief ROI files: YAML with a list of boxes, each with a centre and a size in metres
/// and an optional name:
/// \code{.yaml}
/// boxes:
///   - name: main_stem
///     center: [1.0, 0.0, 1.15]
///     size: [0.05, 0.05, 0.7]
/// \endcode

#include <string>

#include <plantnbv/common/box.h>

namespace plantnbv {
namespace io {

/// \brief Reads an ROI file. Keys other than `boxes` (top level) and `name`, `center`,
/// `size` (in a box) are rejected. A file over defaultInputLimits().max_file_bytes is
/// refused before it is read.
/// \throws IoError if missing or unreadable; FormatError naming the file, the box index
/// (from 0) and the key (io::YamlReader's messages), e.g. "'rois.yaml' boxes[2].size:
/// expected 3 non-negative numbers, got [0.1, -0.2, 0.3]", for malformed YAML, a missing
/// key, a vector without exactly 3 numbers, a NaN or infinite centre or size, a size that
/// is not > 0 on every axis (a box without volume: a score over it would mean nothing),
/// corners that overflow to infinity, an unknown key, or a file without boxes;
/// FormatError naming the cap for a file over the size limit.
Roi loadRoi(const std::string& path);

/// \brief Writes an ROI file that loadRoi reads back exactly: each number in the
/// shortest decimal form that reads back as the same double (at most 17 significant
/// digits), names quoted when YAML could misread them, unnamed boxes without `name`.
/// \throws IoError if the file cannot be written; InvalidArgumentError for an empty ROI
/// (an ROI file needs boxes) or a non-finite value.
void saveRoi(const std::string& path, const Roi& roi);

} // namespace io
} // namespace plantnbv
