#pragma once
/// @file smooth_profile.h
/// @brief Septic smoothstep S(x) = 35x^4 - 84x^5 + 70x^6 - 20x^7 (rest-to-rest with zero
/// velocity, acceleration and jerk at both ends) and its integral; private to sim.

#include <algorithm>
#include <array>
#include <cmath>

namespace vid::sim::detail {

inline constexpr double kSmoothstepPeakVel = 2.1875;           ///< max S'(x)
inline constexpr double kSmoothstepPeakAcc = 7.5131884024732;  ///< max |S''(x)|

/// @brief Duration of a rest-to-rest smoothstep move over @p length_m within the speed and
/// acceleration limits (at least 1 ms).
inline double smoothstep_duration(double length_m, double max_speed, double max_accel) {
  return std::max({kSmoothstepPeakVel * length_m / max_speed, std::sqrt(kSmoothstepPeakAcc * length_m / max_accel), 1e-3});
}

/// @brief S(x) and its first four derivatives for x clamped to [0, 1].
inline std::array<double, 5> smoothstep7(double x) {
  if (x <= 0.0) return {0.0, 0.0, 0.0, 0.0, 0.0};
  if (x >= 1.0) return {1.0, 0.0, 0.0, 0.0, 0.0};
  const double x2 = x * x, x3 = x2 * x, x4 = x3 * x, x5 = x4 * x, x6 = x5 * x, x7 = x6 * x;
  return {35 * x4 - 84 * x5 + 70 * x6 - 20 * x7,
          140 * x3 - 420 * x4 + 420 * x5 - 140 * x6,
          420 * x2 - 1680 * x3 + 2100 * x4 - 840 * x5,
          840 * x - 5040 * x2 + 8400 * x3 - 4200 * x4,
          840 - 10080 * x + 25200 * x2 - 16800 * x3};
}

/// @brief Phase phi(t) with phi' ramping smoothly 0 -> 1 over [0, T]; phi = 0 for t <= 0.
/// Returns phi and its first four time derivatives.
inline std::array<double, 5> ramp_phase(double t, double T) {
  if (t <= 0.0) return {0.0, 0.0, 0.0, 0.0, 0.0};
  if (T <= 0.0) return {t, 1.0, 0.0, 0.0, 0.0};
  if (t >= T) return {0.5 * T + (t - T), 1.0, 0.0, 0.0, 0.0};
  const double x = t / T;
  const auto S = smoothstep7(x);
  const double x5 = x * x * x * x * x;
  const double integral = 7 * x5 - 14 * x5 * x + 10 * x5 * x * x - 2.5 * x5 * x * x * x;
  return {T * integral, S[0], S[1] / T, S[2] / (T * T), S[3] / (T * T * T)};
}

}  // namespace vid::sim::detail
