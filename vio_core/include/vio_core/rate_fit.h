/// @file rate_fit.h
/// @brief The body rate at one instant from the gyro samples around it (local quadratic fit),
/// for the time-offset clone Jacobian.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "vio_core/measurements.h"

namespace vid {

/// @brief One gyro sample (bias not removed).
struct GyroSample {
  TimeNs t_ns = 0;
  Eigen::Vector3d gyro_I = Eigen::Vector3d::Zero();
};

/// @brief Least-squares quadratic fit of each gyro axis over the @p samples within
/// [t - half_window, t + half_window] (any order), evaluated at @p t_ns.
///
/// Why not the sample nearest the frame: the time offset is learned from how the rate changes
/// between clones (README "Camera-IMU time offset"), a few mrad/s at 0.1 rad/s^2. One sample of
/// the seed's gyro carries 20 mrad/s of white noise; in the clone Jacobian that noise reads as
/// information the images never gave (t_d locked ms away with a sigma of 0.3 ms). A fit over
/// +-0.4 s leaves ~1.5 mrad/s, correlated from clone to clone, which the estimate tolerates.
/// @return nullopt with fewer than 8 samples in the window (the caller falls back).
std::optional<Eigen::Vector3d> fit_rate(const std::vector<GyroSample>& samples, TimeNs t_ns, TimeNs half_window_ns);

}  // namespace vid
