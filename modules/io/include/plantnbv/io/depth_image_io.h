#pragma once
/// \file depth_image_io.h
/// \brief Depth images as 16-bit PNG files, the format depth cameras' tools use, and
/// instance masks (detections_io.h) as 8-bit grey PNG files.

#include <cstdint>
#include <string>
#include <vector>

namespace plantnbv {

struct DepthImage;

namespace io {

/// \brief Writes a depth image (metres, row-major, NaN = no return) as a 16-bit grey PNG
/// in units of 1 / `units_per_metre` metres (default 1000: millimetres, as RealSense and
/// Kinect tools read them), rounded to the nearest unit; 0 means no return, as in those
/// tools. A depth that rounds to 0 or above 65535 units (65.5 m in millimetres) cannot be
/// stored and is written as 0 too.
/// \throws InvalidArgumentError if the size does not match `depth_m` or is 0, or
/// units_per_metre is not > 0; IoError if the file cannot be written.
void saveDepthPng(const std::string& path, std::uint32_t width, std::uint32_t height,
                  const std::vector<float>& depth_m, double units_per_metre = 1000.0);

/// \brief Reads a 16-bit grey PNG written by saveDepthPng back to metres (0 -> NaN).
/// Units and rounding: depthToUnits / depthFromUnits (camera/depth_image.h).
/// \throws IoError if the file is missing or unreadable, FormatError if it is not a
/// 16-bit single-channel PNG, is truncated or has a side over 16384 pixels.
void loadDepthPng(const std::string& path, std::uint32_t& width, std::uint32_t& height,
                  std::vector<float>& depth_m, double units_per_metre = 1000.0);
/// \brief As above, into a DepthImage; with an expected size (not 0), a PNG of another
/// size is a FormatError before its pixels are allocated.
void loadDepthPng(const std::string& path, DepthImage& depth,
                  double units_per_metre = 1000.0, std::uint32_t expected_width = 0,
                  std::uint32_t expected_height = 0);

/// \brief Writes an instance mask (row-major bytes, non-zero = the instance's pixels) as
/// an 8-bit grey PNG, its bytes as they are.
/// \throws InvalidArgumentError if the size does not match `mask` or is 0; IoError if
/// the file cannot be written (it is written whole or not at all).
void saveMaskPng(const std::string& path, std::uint32_t width, std::uint32_t height,
                 const std::vector<std::uint8_t>& mask);

/// \brief Reads an 8-bit grey PNG (as saveMaskPng, OpenCV's `imwrite` of a CV_8UC1
/// image or PIL's mode "L" write it; 1, 2 and 4-bit grey are expanded to 8 bits, zero
/// staying zero) into row-major bytes.
/// \param[in] path the PNG
/// \param[out] width its width, pixels
/// \param[out] height its height, pixels
/// \param[out] mask width * height bytes
/// \param[in] expected_width with expected_height, when not 0: a PNG of another size is
/// a FormatError "'PATH' is WxH, the depth image is WxH" before its pixels are allocated
/// \param[in] expected_height see expected_width
/// \throws IoError if the file is missing or unreadable; FormatError if it is not a PNG,
/// has colour, alpha, a palette or 16-bit samples ("'PATH' is not an 8-bit grey PNG (an
/// instance mask)"), is truncated or has a side over 16384 pixels.
void loadMaskPng(const std::string& path, std::uint32_t& width, std::uint32_t& height,
                 std::vector<std::uint8_t>& mask, std::uint32_t expected_width = 0,
                 std::uint32_t expected_height = 0);

} // namespace io
} // namespace plantnbv
