#pragma once
/// @file estimator_outputs.h
/// @brief What the estimator emits: the IMU-rate estimate, the filter status and the stage times
/// of a camera frame.

#include <Eigen/Core>
#include <string>

#include "types/measurements.h"
#include "vio_core/flight_phase.h"
#include "vio_core/state.h"

namespace vid {

/// @brief Filter health.
enum class FilterStatus { kWaitingForInit, kOk, kDiverged };
/// @brief "waiting_for_init" / "ok" / "diverged".
std::string to_string(FilterStatus s);

/// @brief One IMU-rate estimate.
struct EstimateOutput {
  TimeNs t_ns = 0;
  ImuState x;
  Eigen::VectorXd sigma;  ///< 1-sigma of the IMU error block (15 or 18)
  Eigen::Matrix3d cov_theta, cov_p;  ///< for consistency checks
  /// External force in I and in W [m/s^2] and their covariances (zero in imu mode); the one
  /// in the state's force frame is the state's block, the other is mapped through R_WI with
  /// the orientation uncertainty included.
  Eigen::Vector3d F_ext_I, F_ext_W;
  Eigen::Matrix3d cov_F_I, cov_F_W;
  double sigma_thrust_scale = 0.0;  ///< 1-sigma of x.thrust_scale (0 when it is not estimated)
  double time_offset_s = 0.0;        ///< camera-IMU time offset t_d in use (t_imu = t_cam + t_d)
  double sigma_time_offset_s = 0.0;  ///< its 1-sigma (0 when it is not estimated)
  FilterStatus status = FilterStatus::kOk;
  FlightPhase phase = FlightPhase::kUnknown;  ///< landed / airborne (dynamics mode; flight_phase.h)
};

/// @brief Stage times of one camera frame [ms] (propagation and accelerometer updates are
/// accumulated since the previous frame).
struct FrameTimings {
  TimeNs t_ns = 0;  ///< the frame's camera stamp
  double propagation_ms = 0.0;
  double accel_update_ms = 0.0;
  double msckf_update_ms = 0.0;
  double marginalization_ms = 0.0;
  int features_used = 0;
  int features_rejected = 0;
  int features_rejected_chi2 = 0;  ///< of features_rejected, by the chi2 gate (health_monitor.h)
  int clones = 0;
};

}  // namespace vid
