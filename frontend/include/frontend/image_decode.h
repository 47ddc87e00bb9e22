#pragma once
/// @file image_decode.h
/// @brief Image files as the frontend takes them: 8-bit single-channel gray.
///
/// Files are read here and their structure checked (PNG: signature, chunk lengths, CRCs, IEND;
/// JPEG: start and end markers) before OpenCV decodes them from memory, so that a truncated or
/// corrupt file is reported by us in one line instead of by libpng / libjpeg on stderr.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace vid {

/// @brief Decode one image file as 8-bit gray (colour converted); empty Mat when the file is
/// missing, unreadable or of another depth, and then @p fault (when given) says why, e.g.
/// "missing file" or "truncated PNG (cut at byte 812 of 1024)".
///
/// 16-bit pixels hold a camera's N = @p significant_bits bits right-aligned (a 12-bit camera
/// writes 0..4095): they are divided by 2^(N-8), so the camera's range maps onto 0..255
/// (larger values saturate). N = 16 is the plain `/ 256`. 8-bit images ignore N. A stream must
/// use one N for all its frames (see detect_bit_depth), or its brightness would jump.
cv::Mat decode_gray8(const std::string& path, std::string* fault = nullptr, int significant_bits = 16);

/// @brief The bits a camera stream's pixels use, found from some of its image files.
struct BitDepth {
  int bits = 8;     ///< 8 for 8-bit images, else the significant bits of the 16-bit ones (9..16)
  std::string how;  ///< how it was found, for logs and summary.json
};

/// @brief Find a stream's bit depth from sample files (e.g. spread over the sequence).
///
/// 8-bit images: 8. 16-bit PNGs with an sBIT chunk (significant bits, PNG spec 11.3.3.4):
/// its value. Other 16-bit images: the bit length of the largest pixel value over all samples,
/// rounded up to 10, 12, 14 or 16 (what cameras deliver), so that a dark sample of a 12-bit
/// camera (largest value 1800) is still taken as 12-bit. Unreadable files are skipped; with no
/// readable sample the result is 16 ("no readable image": the plain `/ 256`).
BitDepth detect_bit_depth(const std::vector<std::string>& paths);

}  // namespace vid
