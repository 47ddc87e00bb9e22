#pragma once
/// @file accel_noise.h
/// @brief Vibration-aware accelerometer noise of the dynamics-mode update: covariance matching
/// on the innovations (Mehra 1972; Mohamed & Schwarz 1999), README "Real sensors".
///
/// A real multirotor's accelerometer carries rotor vibration that comes and goes with the rotor
/// speeds and in bursts (docs/real_sensors.md): a fixed noise density is either far too low in
/// a burst (every sample looks like a force step) or far too high in calm flight. Per IMU axis,
/// the spread of the innovations over the last window (0.25 s by default) (exponentially weighted; their
/// variance about their own mean, so a force step - a shift of the mean - is not read as noise)
/// is compared with the innovation variance the nominal noise predicts; beyond twice that, the
/// excess is added to the measurement noise: R_i = R_nom + (var_i - e_i). A consistent filter's
/// window variance stays near e_i , so the nominal
/// noise is kept there, sample for sample (100 samples at 400 Hz: the estimate spreads ~14 %).

#include <Eigen/Core>

namespace vid {

/// @brief Per-axis accelerometer noise variance from the recent innovations.
class AccelNoiseAdapter {
 public:
  /// @param nominal_var R_nom [(m/s^2)^2] per sample; @param window_samples the averaging
  /// window in samples (0 = off: the nominal noise always).
  AccelNoiseAdapter(double nominal_var, double window_samples);
  /// @brief The noise variance per IMU axis for the next sample.
  const Eigen::Vector3d& noise_var() const { return R_; }
  /// @brief Add one sample's innovation r_I and its covariance diagonal S_I (both in I, with
  /// the noise noise_var() that was used).
  void add(const Eigen::Vector3d& r_I, const Eigen::Vector3d& S_I_diag);
  /// @brief The innovation variance the nominal noise predicts for the last sample, per axis.
  const Eigen::Vector3d& nominal_innovation_var() const { return e_; }
  /// @brief Samples with an inflated noise on some axis.
  long inflated_samples() const { return inflated_; }
  void reset();

 private:
  double R_nom_;
  double alpha_;  ///< 1 / window
  long n_ = 0;
  Eigen::Vector3d mean_ = Eigen::Vector3d::Zero(), sq_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d R_, e_;
  long inflated_ = 0;
};

}  // namespace vid
