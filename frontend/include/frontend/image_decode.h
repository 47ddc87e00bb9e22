#pragma once
/// @file image_decode.h
/// @brief Image files as the frontend takes them: 8-bit single-channel gray.
///
/// Files are read here and their structure checked (PNG: signature, chunk lengths, CRCs, IEND;
/// JPEG: start and end markers) before OpenCV decodes them from memory, so that a truncated or
/// corrupt file is reported by us in one line instead of by libpng / libjpeg on stderr.

#include <opencv2/core.hpp>
#include <string>

namespace vid {

/// @brief Decode one image file as 8-bit gray (16-bit scaled down by 256, colour converted);
/// empty Mat when the file is missing, unreadable or of another depth, and then @p fault (when
/// given) says why, e.g. "missing file" or "truncated PNG (cut at byte 812 of 1024)".
cv::Mat decode_gray8(const std::string& path, std::string* fault = nullptr);

}  // namespace vid
