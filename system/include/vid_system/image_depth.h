#pragma once
/// @file image_depth.h
/// @brief The bit depth of each camera stream of a dataset folder, fixed for the whole run so
/// that 16-bit images keep one brightness scale from the first frame to the last.

#include <array>
#include <filesystem>
#include <string>

#include "frontend/image_decode.h"

namespace vid::system {

/// @brief Bit depth per camera id 0 / 1 (what vid::decode_gray8 takes as significant_bits).
struct CameraDepths {
  std::array<BitDepth, 2> cams{BitDepth{16, "no images"}, BitDepth{16, "no images"}};
  /// @brief Significant bits of camera @p cam_id (16 for other ids).
  int bits(int cam_id) const { return cam_id >= 0 && cam_id < 2 ? cams[static_cast<std::size_t>(cam_id)].bits : 16; }
};

/// @brief @p configured (FrontendParams::image_bit_depth) for every camera when it is not 0;
/// else, per camera, vid::detect_bit_depth over up to 5 images spread evenly over the rows of
/// camN/data.csv (first and last included), so a dark start does not decide alone.
/// @param mav0 the dataset's mav0 folder (io::DatasetReader::mav0())
CameraDepths camera_bit_depths(const std::filesystem::path& mav0, int configured);

}  // namespace vid::system
