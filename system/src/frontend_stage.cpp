#include "vid_system/frontend_stage.h"

#include <stdexcept>

#include "frontend/klt_tracker.h"

namespace vid::system {

FrontendStage::FrontendStage(const FrontendParams& params, const std::vector<CameraCalib>& cameras,
                             bool right_images) {
  if (cameras.empty()) throw std::invalid_argument("FrontendStage: no camera calibration");
  stereo_ = params.stereo && right_images && cameras.size() >= 2;
  std::vector<CameraCalib> tracked{cameras[0]};
  if (stereo_) tracked.push_back(cameras[1]);
  tracker_ = std::make_unique<KltTracker>(params, tracked);
}

FrontendStage::~FrontendStage() = default;

void FrontendStage::add_imu(const ImuSample& s) { tracker_->add_imu(s); }

FeatureFrame FrontendStage::track(TimeNs t_ns, const cv::Mat& left, const cv::Mat& right) {
  return tracker_->process(t_ns, left, stereo_ ? right : cv::Mat());
}

}  // namespace vid::system
