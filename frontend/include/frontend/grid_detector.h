#pragma once
/// @file grid_detector.h
/// @brief Grid-based FAST detection with per-cell quotas and a minimum pixel distance to
/// existing and to newly accepted features.

#include <opencv2/core.hpp>
#include <vector>

#include "frontend/frontend_params.h"

namespace vid {

/// @brief Detects new corners spread evenly over the image.
class GridDetector {
 public:
  explicit GridDetector(const FrontendParams& params) : p_(params) {}

  /// @brief New corners (at most `wanted`) at least min_distance_px from `existing` and from
  /// each other, at most a per-cell quota in each grid cell (existing features count toward
  /// the quota); strongest FAST responses first. Only the cells an even fill of `wanted` needs
  /// are searched (the emptiest; see the .cpp). Cells left empty at fast_threshold are
  /// retried at fast_threshold_min; both thresholds are at least fast_noise_factor times the
  /// image's noise sigma. A cell searched without result is skipped by the next
  /// detect_cell_retry_frames calls (texture-less regions are not searched every frame).
  std::vector<cv::Point2f> detect(const cv::Mat& image, const std::vector<cv::Point2f>& existing,
                                  int wanted);

  /// @brief The features of the last detect() that were lost in their first tracked frame
  /// (their last positions); call once per frame after tracking, before detect(). A cell whose
  /// new features were all lost at once (noise corners of a dark or plain region, flicker)
  /// rests as a cell searched in vain does, instead of taking the budget again every frame.
  void first_frame_losses(const std::vector<cv::Point2f>& lost);

 private:
  std::vector<cv::Point2f> detect_in_cells(const cv::Mat& image, const std::vector<cv::Point2f>& existing,
                                           int wanted);
  int cell_of(const cv::Point2f& p) const;  ///< grid cell of a pixel of the last image

  FrontendParams p_;
  std::vector<int> idle_;      ///< per cell: calls left before it is searched again
  std::size_t next_cell_ = 0;  ///< where the next call starts taking cells at the fill level
  std::vector<int> born_;      ///< per cell: features the last detect() returned
  cv::Size size_;              ///< image size of the last detect()
};

}  // namespace vid
