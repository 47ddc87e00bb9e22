#pragma once
/// @file estimator_detail.h
/// @brief What the Estimator's source files (estimator*.cpp) share and nobody else needs: the
/// wall clock of the per-frame timings and the scheduling constants.
#include <chrono>

#include "types/measurements.h"

namespace vid::estimator_detail {

using Clock = std::chrono::steady_clock;
inline double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
constexpr TimeNs kMaxSubstepNs = 10'000'000;  // 10 ms sub-steps over IMU gaps
constexpr TimeNs kGtInitToleranceNs = 20'000'000;
// Longest half window of the gyro fit in the time-offset clone Jacobian (rate_fit.h). 0.1 and 0.15 s
// left t_d inconsistent on the gentle flights (NEES of single runs up to 81 and 51), with 0.25 s
// the estimate still lagged more at 10 s than with 0.4 s (docs/notes/time-offset.md).
// Frames wait this long for the later gyro samples while t_d is estimated.
constexpr TimeNs kTdRateHalfWindowNs = 400'000'000;
// The shortest window rate_for_clone falls back to near an impact: 21 samples at 400 Hz.
constexpr TimeNs kTdRateMinHalfWindowNs = 25'000'000;

}  // namespace vid::estimator_detail
