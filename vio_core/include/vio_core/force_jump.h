#pragma once
/// @file force_jump.h
/// @brief Abrupt external forces (rope snaps, impacts, hooks, payload drops): detection in the
/// accelerometer innovations and the re-estimate of the force from the samples that saw it.
///
/// Why: the force's process model (random walk on F and dF/dt) is built for smooth forces. A
/// step of 5-30 N makes every accelerometer innovation large at once; a chi2 gate then throws
/// away exactly the samples that carry the news, and those it keeps are explained partly by
/// tilt and accelerometer bias. Instead, a generalized likelihood ratio (GLR) test for a step in
/// the innovation mean (Willsky & Jones 1976) runs over the last n = 2 .. N samples:
///
///   l_n = C_n^T (sum_k S_k)^-1 C_n,   C_n = sum of the last n innovations (force frame),
///
/// (each innovation clipped at 3 sigma, so that one outlier weighs no more than a 3-sigma sample)
/// which is chi2(3) while the filter is consistent and grows as n |dF|^2 / sigma^2 after a
/// step. Each half of the window must carry the step too (a one-sample spike is not a step).
/// Vibration is not white: the noise the adapter adds for it (S_vib, power above 10 Hz) sums
/// over n samples to at most min(n^2, 1/sin^2(pi f_lo dt)) times its variance (a tone at the
/// band's lowest frequency f_lo, its worst case), not n times, so half a cycle of a 10-40 Hz
/// burst is not read as a step (docs/model.md eq. (22)).
/// On a detection the window's accelerometer corrections of velocity, biases and force are
/// undone (not of the pose, which the clones share), the force gets the
/// step's prior variance and its rate restarts, and the window's samples are applied once as
/// their mean, so the force jumps to the new level in a few samples while the biases keep what
/// they had; velocity and position get what propagation with the old force missed.
/// Samples the chi2 gate held back inside the window are used, not lost.

#include <Eigen/Core>
#include <deque>
#include <optional>
#include <vector>

#include "types/measurements.h"
#include "vio_core/accel_innovation.h"
#include "vio_core/estimator_params.h"
#include "vio_core/state.h"

namespace vid {

/// @brief A detected step: over the newest n samples, GLR statistic and jump estimate.
struct ForceJump {
  int n = 0;
  double statistic = 0.0;
  Eigen::Vector3d delta = Eigen::Vector3d::Zero();  ///< mean innovation of the window (force frame)
  TimeNs t_ns = 0;  ///< time of the newest sample
};

/// @brief Windowed GLR step detector over accelerometer innovations (no state mutation).
class ForceJumpDetector {
 public:
  explicit ForceJumpDetector(const EstimatorParams& p);
  /// @brief Add the newest sample; returns a sample pushed out of the window (the caller
  /// finalizes its gate decision), if any.
  std::optional<AccelInnovation> push(const AccelInnovation& s);
  /// @brief Test every window of the newest 2 .. N samples; the detection with the largest
  /// statistic (the most likely onset), or nullopt.
  std::optional<ForceJump> test() const;
  /// @brief Samples newest first (index 0 = newest).
  const AccelInnovation& recent(int i) const { return buf_[buf_.size() - 1 - static_cast<std::size_t>(i)]; }
  int size() const { return static_cast<int>(buf_.size()); }
  /// @brief Forget every sample (after a jump the innovations restart from a new level).
  void clear() { buf_.clear(); }

 private:
  /// @brief The coloured (vibration) part of the covariance of a sum of n samples whose
  /// S_vib sum to X_n, beyond the white n-fold sum already in sum S.
  Eigen::Matrix3d coloured_excess(int n, const Eigen::Matrix3d& X_n) const;

  double threshold_;
  double vib_sum_gain_max_;  ///< 1 / sin^2(pi f_lo dt): a tone at f_lo summed over its half cycle
  double split_sigma_;
  double min_step_;
  int max_window_;
  std::deque<AccelInnovation> buf_;
  mutable std::vector<Eigen::Vector3d> cum_w_;  ///< scratch of test(): sums of the newest i innovations
  mutable std::vector<Eigen::Matrix3d> cum_S_;
  mutable std::vector<Eigen::Matrix3d> cum_X_;
};

/// @brief Apply a detected jump to the state: undo the window's accelerometer corrections of
/// the IMU block from the velocity on (not the pose the clones share); add the step's prior to
/// the force covariance (variance (2|delta|)^2 per axis) and restart its rate (zero mean,
/// sigma_rate0, uncorrelated); update with the window's mean measurement
/// y_bar = F - dF/dt dt_bar + R_bar b_a (+ noise_var / n) in one 3-row EKF update;
/// move velocity and position by the integral of the window's innovations (what propagation
/// with the old force missed), with its noise added to their covariance.
/// @param window the jump's samples, newest first (detector.recent(0 .. n-1))
void apply_force_jump(FilterState& state, const std::vector<AccelInnovation>& window, const ForceJump& jump,
                      double noise_var, double sigma_rate0);

}  // namespace vid
