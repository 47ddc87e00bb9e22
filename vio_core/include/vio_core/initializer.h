#pragma once
/// @file initializer.h
/// @brief Static / hover initialization from a window of IMU (and thrust) samples:
/// gravity-aligned orientation from the averaged accelerometer, gyro bias from the averaged
/// gyro, and in dynamics mode F_ext from a_mean - T_m. Thrust tells hover (T/m ≈ g) and
/// resting (T ≈ 0, |a| ≈ g) from free fall (|a| ≈ 0), where gravity is not observable.

#include <Eigen/Core>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "types/measurements.h"
#include "vio_core/estimator_params.h"
#include "vio_core/state.h"

namespace vid {

/// @brief Initial state and covariance.
struct InitResult {
  TimeNs t_ns = 0;
  ImuState x;
  Eigen::MatrixXd P;  ///< imu_dim x imu_dim
  /// In-flight initialization: the poses of the window's earlier frames in the new world frame
  /// (oldest first; from the frame positions and gyro rotations of the alignment), so that a
  /// re-initialized run's trajectory has no gap over the window. Empty otherwise.
  std::vector<TimedPose> window_poses;
};

/// @brief Diagonal initial covariance from the params' init sigmas (orientation split into
/// roll/pitch and yaw in the world frame, mapped to the body-frame right perturbation).
Eigen::MatrixXd initial_covariance(const EstimatorParams& params, const Eigen::Quaterniond& q_WI);

/// @brief IMU state from a ground-truth sample (pose, velocity, biases; F_ext and its rate
/// zero), for initialization from ground truth.
ImuState state_from_groundtruth(const GroundTruthSample& gt);

/// @brief Sliding-window static/hover detector and initializer.
class StaticInitializer {
 public:
  explicit StaticInitializer(const EstimatorParams& params) : params_(params) {}

  /// @brief Feed one IMU sample with its thrust (T_m ignored in imu mode). Returns the
  /// initial state once the window is full and still; otherwise std::nullopt.
  std::optional<InitResult> add(TimeNs t_ns, const Eigen::Vector3d& gyro,
                                const Eigen::Vector3d& accel, const Eigen::Vector3d& T_m);
  /// @brief Why the last full window was rejected ("" if none yet).
  const std::string& last_rejection() const { return reason_; }

 private:
  struct Sample {
    TimeNs t;
    Eigen::Vector3d w, a, T;
  };
  EstimatorParams params_;
  std::deque<Sample> window_;
  std::string reason_;
};

/// @brief Rotation with yaw 0 whose body z-axis is along the measured specific force f_I
/// (R_WI f_I ∥ +z_W).
Eigen::Quaterniond gravity_aligned_orientation(const Eigen::Vector3d& f_I);

}  // namespace vid
