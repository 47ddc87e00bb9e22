#pragma once
/// @file accel_innovation.h
/// @brief One accelerometer update as the force-jump detector keeps it (force_jump.h), filled
/// by accel_update (ekf_update.h): its own header so that neither includes the other.

#include <Eigen/Core>

#include "types/measurements.h"

namespace vid {

/// @brief Largest IMU error block (theta, p, v, b_g, b_a, F, dF/dt).
constexpr int kMaxImuDim = 22;

/// @brief One accelerometer sample as the detector keeps it.
struct AccelInnovation {
  TimeNs t_ns = 0;
  Eigen::Vector3d w = Eigen::Vector3d::Zero();  ///< innovation in the force frame [m/s^2]
  Eigen::Vector3d w_test = Eigen::Vector3d::Zero();  ///< w clipped at 3 sigma (set by the detector)
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();  ///< its covariance in the force frame
  /// The part of S's noise that is vibration (the adapted noise above nominal, accel_noise.h),
  /// in the force frame: coloured, so the detector does not count it as white (test()).
  Eigen::Matrix3d S_vib = Eigen::Matrix3d::Zero();
  /// The measurement a_m - s T_m in the force frame: R_WI (a_m - s T_m) (world model; R_WI of
  /// the sample's time) or a_m - s T_m (body model); s = 1 unless the thrust scale is estimated.
  Eigen::Vector3d y = Eigen::Vector3d::Zero();
  /// T_m in the force frame (R_WI T_m or T_m): y's sensitivity to s is -T.
  Eigen::Vector3d T = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R_WI = Eigen::Matrix3d::Identity();  ///< orientation estimate at the sample
  Eigen::Matrix<double, kMaxImuDim, 1> dx_imu = Eigen::Matrix<double, kMaxImuDim, 1>::Zero();  ///< IMU-block correction applied (0 if gated)
  bool gated = false;  ///< past the chi2 gate when it arrived (rejected, or applied down-weighted)
};

}  // namespace vid
