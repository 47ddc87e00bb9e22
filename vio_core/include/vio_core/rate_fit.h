/// @file rate_fit.h
/// @brief The body rate at one instant from the gyro samples around it (local quadratic fit),
/// for the time-offset clone Jacobian.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "types/measurements.h"

namespace vid {

/// @brief One gyro sample (bias not removed).
struct GyroSample {
  TimeNs t_ns = 0;
  Eigen::Vector3d gyro_I = Eigen::Vector3d::Zero();
};

/// @brief A rate from fit_rate_adaptive and the window it came from.
struct AdaptiveRate {
  Eigen::Vector3d rate_I = Eigen::Vector3d::Zero();
  TimeNs half_window_ns = 0;  ///< the window that passed (or the shortest tried)
  bool passed = false;        ///< false: even the shortest window left model error in the residual
};

/// @brief Least-squares quadratic fit of each gyro axis over the @p samples (time order) within
/// [t - h, t + h], evaluated at @p t_ns, for the longest h from @p max_half_window_ns halving down
/// to @p min_half_window_ns whose residual is white noise (max = min: one fixed window).
///
/// Why a fit and not the sample nearest the frame: the time offset is learned from how the rate
/// changes between clones (docs/notes/time-offset.md), a few mrad/s at 0.1 rad/s^2. One
/// sample of the seed's gyro carries 20 mrad/s of white noise; in the clone Jacobian that noise
/// reads as information the images never gave (t_d locked ms away with a sigma of 0.3 ms). A fit
/// over +-0.4 s leaves ~1.5 mrad/s, correlated from clone to clone, which the estimate tolerates.
///
/// Why the window shrinks: a quadratic over +-0.4 s cannot follow an impact (the gyro swings 3.7 rad/s in 60 ms);
/// its rate at a clone near one was off by up to rad/s, which the clone Jacobian read as a rate
/// change and so as information on t_d (impacts: t_d 5 ms off a true 0 in one frame, sigma
/// 4.9 -> 1.6 ms). The noise level is measured, not taken from the calibration (real gyros carry
/// vibration far above the datasheet): the robust spread (MAD) of successive differences over the
/// longest window, per axis. A window passes when each axis's residual variance is at most
/// kRateFitResidualRatio times it.
/// @return nullopt when not even the longest window has 8 samples (the caller falls back).
std::optional<AdaptiveRate> fit_rate_adaptive(const std::vector<GyroSample>& samples, TimeNs t_ns,
                                              TimeNs max_half_window_ns, TimeNs min_half_window_ns);

/// @brief A window passes while its residual variance is below this multiple of the measured
/// noise variance (per axis). The residual of a pure-noise window has a variance ratio of
/// 1 +- sqrt(2 / (N - 3)): 1 +- 0.08 at the 0.4 s window (N = 320 at 400 Hz).
inline constexpr double kRateFitResidualRatio = 1.5;

}  // namespace vid
