#include "vid_system/frame_faults.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>

#include "frontend/image_decode.h"
#include "io/errors.h"

namespace vid::system {

void FrameFaults::skip(FrameFault kind, const std::string& what) {
  if (strict_) throw io::DatasetError(what + " (--strict: a bad camera frame is an error)");
  long& n = kind == FrameFault::kMissing ? missing_ : kind == FrameFault::kUnreadable ? unreadable_ : wrong_size_;
  ++n;
  if (total() <= kLines) spdlog::warn("{}; frame skipped", what);
}

void FrameFaults::report_rest() {
  if (reported_ || total() <= kLines) return;
  reported_ = true;
  spdlog::warn("{} camera frames skipped in all, {} more than warned above ({} missing, {} unreadable, {} of the "
               "wrong size; see summary.json)",
               total(), total() - kLines, missing_, unreadable_, wrong_size_);
}

bool check_frame_image(const cv::Mat& image, const std::string& path, int width, int height, FrameFaults& faults) {
  if (image.empty()) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
      faults.skip(FrameFault::kMissing, path + ": missing image file");
    } else {
      std::string why;
      decode_gray8(path, &why);  // again, for the reason (on this failure path only)
      faults.skip(FrameFault::kUnreadable, path + ": unreadable image (" + why + ")");
    }
    return false;
  }
  if (image.cols == width && image.rows == height) return true;
  faults.skip(FrameFault::kWrongSize,
              fmt::format("{}: image is {}x{}, calibration says {}x{}", path, image.cols, image.rows, width, height));
  return false;
}

}  // namespace vid::system
