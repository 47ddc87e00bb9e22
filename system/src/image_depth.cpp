/// @file image_depth.cpp
/// @brief Camera bit depths from a few images of each stream (see vid_system/image_depth.h).
#include "vid_system/image_depth.h"

#include <string>
#include <vector>

#include "io/csv_reader.h"

namespace vid::system {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kSamples = 5;

/// Up to kSamples image paths of camN spread over its data.csv rows.
std::vector<std::string> sample_images(const fs::path& cam_dir) {
  std::vector<std::string> names;
  io::CsvReader csv(cam_dir / "data.csv");
  while (csv.next_row()) {
    csv.expect_columns(2);
    names.emplace_back(csv.field(1));
  }
  std::vector<std::string> paths;
  const std::size_t n = names.size();
  for (std::size_t k = 0; k < std::min(n, kSamples); ++k) {
    const std::size_t i = n <= kSamples ? k : k * (n - 1) / (kSamples - 1);
    paths.push_back((cam_dir / "data" / names[i]).string());
  }
  return paths;
}

}  // namespace

CameraDepths camera_bit_depths(const fs::path& mav0, int configured) {
  CameraDepths d;
  for (int cam = 0; cam < 2; ++cam) {
    auto& out = d.cams[static_cast<std::size_t>(cam)];
    if (configured != 0) {
      out = {configured, "image_bit_depth in the frontend settings"};
      continue;
    }
    const fs::path dir = mav0 / ("cam" + std::to_string(cam));
    if (fs::is_regular_file(dir / "data.csv")) out = detect_bit_depth(sample_images(dir));
  }
  return d;
}

}  // namespace vid::system
