#pragma once
/// @file thrust_buffer.h
/// @brief Recent mass-normalized thrust samples, linearly interpolated to IMU times, with a
/// hold-last-value fallback over rotor-stream gaps.

#include <Eigen/Core>
#include <deque>

#include "types/measurements.h"

namespace vid {

/// @brief Thrust at one query time.
struct ThrustQuery {
  Eigen::Vector3d T_m = Eigen::Vector3d::Zero();  ///< [0, 0, T/m] [m/s^2]
  bool valid = false;  ///< false: no thrust sample at all yet
  bool held = false;   ///< true: t lies beyond the newest sample by more than the gap limit
};

/// @brief Time-ordered buffer of T_m samples.
class ThrustBuffer {
 public:
  /// @param gap_ns  a query further than this from any bracketing sample is "held"
  explicit ThrustBuffer(TimeNs gap_ns = 50'000'000) : gap_ns_(gap_ns) {}

  /// @brief Append a sample; samples must come in non-decreasing time order (older ignored).
  void add(TimeNs t_ns, double thrust_per_mass);
  /// @brief Newest sample time (INT64_MIN when empty).
  TimeNs newest() const { return samples_.empty() ? INT64_MIN : samples_.back().first; }
  /// @brief True when a sample at or after t exists (interpolation possible).
  bool covers(TimeNs t_ns) const { return !samples_.empty() && samples_.back().first >= t_ns; }
  /// @brief Interpolated T_m at t (held value beyond the newest sample / across a long gap).
  ThrustQuery at(TimeNs t_ns) const;
  /// @brief Drop samples no longer needed for queries at or after t.
  void prune_before(TimeNs t_ns);

 private:
  TimeNs gap_ns_;
  std::deque<std::pair<TimeNs, double>> samples_;
};

}  // namespace vid
