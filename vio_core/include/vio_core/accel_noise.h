#pragma once
/// @file accel_noise.h
/// @brief Vibration-aware accelerometer noise of the dynamics-mode update: covariance matching
/// on the innovations (Mehra 1972; Mohamed & Schwarz 1999), docs/model.md eqs. (19)-(21),
/// docs/notes/real-sensors.md.
///
/// A real multirotor's accelerometer carries rotor vibration that comes and goes with the rotor
/// speeds and in bursts (docs/real_sensors.md): a fixed noise density is either far too low in
/// a burst (every sample looks like a force step) or far too high in calm flight. Per IMU axis,
/// the innovations' power above kHighpassHz (a first-order high-pass), over the last window
/// (0.25 s by default, exponentially weighted) and scaled to the variance of white noise of
/// that power, is compared with the innovation variance the nominal noise predicts; beyond twice
/// that, the excess is added to the measurement noise: R_i = R_nom + (var_i - e_i).
///
/// Why above 10 Hz: a force the filter is still catching up with (a touchdown, a rope snap) leaves
/// a slow innovation that decays over 50-500 ms. Read as noise (the plain window variance), it
/// made the filter stop listening to the accelerometer just as the ground took the weight: the
/// vehicle sank 0.4 m through the floor on takeoff_landing_short. Rotor vibration (its lines
/// alias anywhere below Nyquist) and 10-40 Hz frame bursts are above it. A consistent filter's
/// innovations are white, the scaled high-pass power equals e_i, and the nominal noise is kept,
/// sample for sample (100 samples at 400 Hz: the estimate spreads ~15 %).

#include <Eigen/Core>
#include <vector>

namespace vid {

/// @brief Per-axis accelerometer noise variance from the recent innovations.
class AccelNoiseAdapter {
 public:
  /// Innovation power below this counts as force, not noise [Hz].
  static constexpr double kHighpassHz = 10.0;
  /// Vibration counts where the white-equivalent power exceeds this multiple of what the
  /// nominal noise predicts (about 3 standard deviations of a window's estimate, and past the
  /// innovations of a filter still catching up with a force).
  static constexpr double kExcessRatio = 2.0;
  /// A sample's high-passed innovation counts at most this many sigma of the noise in use.
  static constexpr double kClipSigma = 3.0;
  /// @param nominal_var R_nom [(m/s^2)^2] per sample; @param window_s the averaging window
  /// [s] (0 = off: the nominal noise always); @param rate_hz the IMU rate.
  AccelNoiseAdapter(double nominal_var, double window_s, double rate_hz);
  /// @brief The noise variance per IMU axis for the next sample.
  const Eigen::Vector3d& noise_var() const { return R_; }
  /// @brief Add one sample's innovation r_I and its covariance diagonal S_I (both in I, with
  /// the noise noise_var() that was used).
  void add(const Eigen::Vector3d& r_I, const Eigen::Vector3d& S_I_diag);
  /// @brief The innovation variance the nominal noise predicts for the last sample, per axis.
  const Eigen::Vector3d& nominal_innovation_var() const { return e_; }
  /// @brief Per axis, the vibration the force-jump detector must not read as white
  /// (force_jump.h): the high-passed innovation power above what the nominal noise predicts,
  /// from the median of the window's squares (white-equivalent, median of chi2(1) = 0.455) where
  /// it is clearly there (> kExcessRatio e_i), else 0. The median, not the mean: vibration fills
  /// the window, while an impact's few samples leave it unchanged and must stay detectable.
  const Eigen::Vector3d& excess_var() const { return excess_; }
  /// @brief Samples with an inflated noise on some axis.
  long inflated_samples() const { return inflated_; }
  void reset();

 private:
  double R_nom_;
  double alpha_;      ///< 1 / window [samples]
  double beta_;       ///< high-pass pole: y_k = beta (y_{k-1} + r_k - r_{k-1})
  double white_gain_;  ///< the high-pass's power gain on white noise, 2 beta^2 / (1 + beta)
  long n_ = 0;
  Eigen::Vector3d last_r_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d hp_ = Eigen::Vector3d::Zero();     ///< high-passed innovation
  Eigen::Vector3d hp_sq_ = Eigen::Vector3d::Zero();  ///< its windowed mean square
  Eigen::Vector3d R_, e_, excess_ = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> hp_sq_window_;  ///< the last window's squared high-passed innovations (ring)
  std::vector<double> scratch_;  ///< one axis of hp_sq_window_ for the median
  long inflated_ = 0;
};

}  // namespace vid
