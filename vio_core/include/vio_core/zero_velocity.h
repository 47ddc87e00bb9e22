#pragma once
/// @file zero_velocity.h
/// @brief Zero-velocity update for a window without parallax (one camera).
///
/// An MSCKF learns translation only from parallax: with one camera and a vehicle that stands
/// or hovers, every feature's rays are parallel, triangulation fails and the IMU alone
/// integrates the tilt / accelerometer-bias error into velocity (0.1 m/s^2 is 0.35 m/s after
/// 3.5 s, and the mono filter never recovers once it moves). That the rays stay parallel is
/// itself the measurement: the window's camera centres did not move measurably. When the
/// median parallax of cam0's features between the oldest clone and now, with the rotation
/// between the two removed, stays below a pixel threshold, the filter applies v_WI = 0.
/// (OpenVINS's zero-velocity updater uses the raw disparity between consecutive frames; the
/// rotation-compensated window parallax also holds while the vehicle yaws in place.)

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <unordered_map>
#include <utility>
#include <vector>

#include "types/measurements.h"
#include "vio_core/state.h"

namespace vid {

/// @brief Parallax statistics of one camera between two times.
struct WindowParallax {
  double median_px = 0.0;  ///< median over features [px]
  int features = 0;        ///< features seen at both times (in front of the camera)
};

/// @brief Median of f |uv_new - pi(R_new_old [uv_old, 1])| over the pairs (normalized image
/// coordinates of one feature at the old and the new time): the parallax left after the
/// camera's rotation R_new_old (C_old -> C_new) is removed, in pixels for focal length f.
WindowParallax rotation_compensated_parallax(const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& uv_old_new,
                                             const Eigen::Matrix3d& R_new_old, double focal_px);

/// @brief One camera's observations of the recent frames by feature id. (The MSCKF's feature
/// database hands every track to an update once it reaches the oldest clone and starts it
/// anew, so it rarely holds one track over the whole window; this keeps the raw frames.)
class ParallaxWindow {
 public:
  explicit ParallaxWindow(int cam_id = 0) : cam_id_(cam_id) {}
  /// @brief Keep the frame's observations of this camera (normalized coordinates).
  void add(const FeatureFrame& frame);
  /// @brief Forget frames older than t.
  void drop_before(TimeNs t);
  /// @brief (uv_norm at t_old, uv_norm at the newest frame) of every feature seen in both.
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> matches(TimeNs t_old) const;

 private:
  int cam_id_;
  std::deque<std::pair<TimeNs, std::unordered_map<std::uint64_t, Eigen::Vector2d>>> frames_;
};

/// @brief EKF update with the pseudo-measurement v_WI = 0 (noise sigma_mps per axis).
/// Returns false when the update could not be applied (singular innovation covariance).
bool zero_velocity_update(FilterState& state, double sigma_mps);

}  // namespace vid
