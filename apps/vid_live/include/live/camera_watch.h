#pragma once
/// @file camera_watch.h
/// @brief Notices a camera that never delivers: IMU data goes on for a bounded span of data
/// time and not one camera frame came (vid_live health `no_camera`, exit 5). A camera that
/// starts late but does deliver ends the fault.

#include <optional>

#include "types/measurements.h"

namespace vid::live {

/// @brief Watches the first camera frame against the IMU's data time (worker thread only).
class CameraWatch {
 public:
  /// @param limit_s  IMU data time after the first IMU sample without any frame before the fault
  explicit CameraWatch(double limit_s) : limit_s_(limit_s) {}

  /// @brief An IMU sample at @p t. @return true once: when the limit passes without a frame.
  bool on_imu(TimeNs t);
  /// @brief A camera frame at @p t. @return true when it ends a no-camera fault (a late camera).
  bool on_frame(TimeNs t);
  /// @brief End of input. @return true when no frame came at all and the fault was not reported
  /// yet (an input shorter than the limit): the caller reports it now.
  bool on_end();

  /// @brief True while no frame has come and the limit has passed (or the input ended).
  bool fault() const { return fault_; }
  /// @brief True when the input had IMU data and not one camera frame.
  bool never_delivered() const { return first_imu_.has_value() && !first_frame_; }
  /// @brief IMU data time seen so far after the first IMU sample [s].
  double imu_span_s() const;
  /// @brief Data time from the first IMU sample to the first frame [s] (none: no frame, or no IMU before it).
  std::optional<double> first_frame_after_s() const;
  double limit_s() const { return limit_s_; }

 private:
  double limit_s_;
  std::optional<TimeNs> first_imu_, last_imu_, first_frame_;
  bool fault_ = false, reported_ = false;
};

}  // namespace vid::live
