#pragma once
/// @file frame_faults.h
/// @brief The one policy for recoverable data faults (docs/errors.md): a camera frame whose
/// image is missing, unreadable or of the wrong size is skipped with one warning line naming
/// the file and the fault (the first kLines faults; the rest in one line with the counts when
/// the run ends) and counted; under strict every such fault is an error instead.

#include <string>

#include <opencv2/core.hpp>

namespace vid::system {

enum class FrameFault { kMissing, kUnreadable, kWrongSize };

class FrameFaults {
 public:
  static constexpr long kLines = 5;  ///< faults warned one by one; the rest are summed up

  void set_strict(bool strict) { strict_ = strict; }
  bool strict() const { return strict_; }
  /// @brief A frame skipped for @p what ("PATH: unreadable image (...)"): counted and warned,
  /// or under strict thrown as io::DatasetError.
  void skip(FrameFault kind, const std::string& what);
  /// @brief One line with the counts of the faults not warned one by one (once; none when
  /// there were at most kLines).
  void report_rest();

  long missing() const { return missing_; }
  long unreadable() const { return unreadable_; }
  long wrong_size() const { return wrong_size_; }
  long total() const { return missing_ + unreadable_ + wrong_size_; }

 private:
  bool strict_ = false, reported_ = false;
  long missing_ = 0, unreadable_ = 0, wrong_size_ = 0;
};

/// @brief Check a decoded image (vid::decode_gray8 of @p path; empty when it failed) against
/// the camera's calibrated size: true when usable, else the fault is passed to @p faults
/// (missing file, unreadable with the decoder's reason, or wrong size with both sizes).
bool check_frame_image(const cv::Mat& image, const std::string& path, int width, int height, FrameFaults& faults);

}  // namespace vid::system
