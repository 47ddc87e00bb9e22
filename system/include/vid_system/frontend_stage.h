#pragma once
/// @file frontend_stage.h
/// @brief The image frontend as every program runs it: which cameras are tracked (cam 0, plus
/// cam 1 for a stereo frontend when it has images) and the KLT tracker over them. The System
/// (vid_run, vid_live) and vid_track share it.

#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "frontend/frontend_params.h"
#include "types/calibration.h"
#include "types/measurements.h"

namespace vid {
class KltTracker;
}  // namespace vid

namespace vid::system {

/// @brief KLT tracking of cam 0 (and cam 1 when stereo) with gyro prediction.
class FrontendStage {
 public:
  /// @param cameras       all calibrated cameras, cam 0 first
  /// @param right_images  false when the input has no cam 1 images (then mono whatever
  ///                      params.stereo says)
  FrontendStage(const FrontendParams& params, const std::vector<CameraCalib>& cameras, bool right_images = true);
  ~FrontendStage();
  FrontendStage(const FrontendStage&) = delete;
  FrontendStage& operator=(const FrontendStage&) = delete;

  /// @brief Gyro sample for the rotation prediction of the next frame.
  void add_imu(const ImuSample& s);
  /// @brief Track one frame; @p right is ignored by a mono frontend.
  FeatureFrame track(TimeNs t_ns, const cv::Mat& left, const cv::Mat& right);
  /// @brief Cameras tracked: 1 (mono) or 2 (stereo).
  int cameras() const { return stereo_ ? 2 : 1; }
  /// @brief The tracker (tracks and statistics of the last frame, for drawings).
  const KltTracker& tracker() const { return *tracker_; }

 private:
  bool stereo_ = false;
  std::unique_ptr<KltTracker> tracker_;
};

}  // namespace vid::system
