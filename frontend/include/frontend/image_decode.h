#pragma once
/// @file image_decode.h
/// @brief Image files as the frontend takes them: 8-bit single-channel gray.

#include <opencv2/core.hpp>
#include <string>

namespace vid {

/// @brief Decode one image file as 8-bit gray (16-bit scaled down by 256, colour converted);
/// empty Mat when the file is missing, unreadable or of another depth.
cv::Mat decode_gray8(const std::string& path);

}  // namespace vid
