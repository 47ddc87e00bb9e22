#pragma once
/// @file health_monitor.h
/// @brief Filter health from the visual updates: innovations out of band, feature starvation.
///
/// The divergence checks of the estimator catch a state that is already absurd (not finite,
/// velocity or position sigma out of range, covariance not positive definite). Two slower
/// failures show first in the visual updates:
/// * **Innovations out of band.** With a consistent filter the 95 % chi2 gate rejects about
///   5 % of the features it tests (plus outliers). When over `health_window_s` at least
///   `health_max_chi2_rejected_fraction` of at least `health_min_tested_features` tested features
///   fail the gate, the predicted measurements no longer match the images: the state or its
///   covariance is wrong (the NEES is far out of band, which needs ground truth to see
///   directly; the innovations show it without). The estimator reports it as diverged: vid_run
///   stops with exit 3, vid_live re-initializes.
/// * **Feature starvation.** No feature track reaches an update for `health_starvation_s`
///   while frames arrive (the frontend loses every track: covered lens, dark, blank or blurred
///   scene): the filter integrates the IMU alone. Tracks that reach an update but cannot be
///   triangulated (a camera standing still sees no parallax) are not starvation: the scene is
///   there, the motion is not. Not a reset (a new filter would starve too): reported and counted.

#include <deque>
#include <string>

#include "types/measurements.h"
#include "vio_core/estimator_params.h"

namespace vid {

/// @brief Verdict after one frame.
struct HealthVerdict {
  bool out_of_band = false;  ///< innovations out of band: the filter should be reset
  bool starving = false;     ///< no feature used for health_starvation_s
  std::string message;       ///< why (empty when healthy)
};

/// @brief Sliding-window monitor of the visual updates' gate statistics.
class HealthMonitor {
 public:
  explicit HealthMonitor(const EstimatorParams& p);
  /// @brief Feed one frame's visual update: features tested by the chi2 gate (used +
  /// rejected by it), of those rejected, and features that reached the update but could not be
  /// triangulated.
  HealthVerdict on_frame(TimeNs t_ns, int tested, int rejected_chi2, int untriangulated = 0);
  bool starving() const { return starving_; }
  /// @brief Starvation episodes started so far and their total length [s].
  long starvation_episodes() const { return episodes_; }
  double starved_s() const { return starved_s_; }
  /// @brief Largest rejected fraction over one window with enough tested features.
  double max_rejected_fraction() const { return max_fraction_; }

 private:
  struct FrameStats {
    TimeNs t_ns;
    int tested, rejected;
  };
  EstimatorParams p_;
  std::deque<FrameStats> window_;
  int tested_ = 0, rejected_ = 0;  ///< sums over window_
  TimeNs last_used_ns_ = 0;        ///< last frame a track reached the update (or the first frame)
  TimeNs last_frame_ns_ = 0;
  bool seen_frame_ = false;
  bool starving_ = false;
  long episodes_ = 0;
  double starved_s_ = 0.0;
  double max_fraction_ = 0.0;
};

}  // namespace vid
