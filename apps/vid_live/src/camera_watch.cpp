#include "live/camera_watch.h"

namespace vid::live {

bool CameraWatch::on_imu(TimeNs t) {
  if (!first_imu_) first_imu_ = t;
  last_imu_ = t;
  if (first_frame_ || reported_ || ns_to_s(t - *first_imu_) <= limit_s_) return false;
  fault_ = reported_ = true;
  return true;
}

bool CameraWatch::on_frame(TimeNs t) {
  if (!first_frame_) first_frame_ = t;
  const bool ended = fault_;
  fault_ = false;
  return ended;
}

bool CameraWatch::on_end() {
  if (!never_delivered()) return false;
  fault_ = true;
  if (reported_) return false;
  reported_ = true;
  return true;
}

double CameraWatch::imu_span_s() const { return first_imu_ ? ns_to_s(*last_imu_ - *first_imu_) : 0.0; }

std::optional<double> CameraWatch::first_frame_after_s() const {
  if (!first_frame_ || !first_imu_) return std::nullopt;
  return ns_to_s(*first_frame_ - *first_imu_);
}

}  // namespace vid::live
