#pragma once
/// @file track_drawing.h
/// @brief Pictures of the tracker state for people: left image with short track trails, and
/// (stereo) the right image beside it with a line per stereo match.

#include <cstdint>
#include <deque>
#include <opencv2/core.hpp>
#include <unordered_map>

#include "frontend/klt_tracker.h"

namespace vid {

/// @brief Keeps the last few positions of each live track and draws them.
class TrackDrawer {
 public:
  /// @param trail_length  positions kept per track
  explicit TrackDrawer(std::size_t trail_length = 10) : trail_length_(trail_length) {}
  /// @brief Record the tracker's live tracks (forgets tracks that ended; bounded memory).
  void update(const std::vector<Track>& tracks);
  /// @brief BGR picture: left with trails (green = old, yellow = young, red = new), and when
  /// `right` is given, the right image to the side with stereo match lines.
  cv::Mat draw(const cv::Mat& left, const cv::Mat& right, const std::vector<Track>& tracks,
               const std::string& caption) const;

 private:
  std::size_t trail_length_;
  std::unordered_map<std::uint64_t, std::deque<cv::Point2f>> trails_;
};

}  // namespace vid
