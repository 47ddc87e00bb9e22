#pragma once
/// @file mass_profile.h
/// @brief The five true-mass profiles m(t) of the study (numbers in study_config.h and README):
/// constant; linear_decrease (spraying: constant, then a linear drain, then constant);
/// step_drop (a payload is released); step_pickup (a payload is picked up); up_down (payload
/// picked up and dropped repeatedly). Steps are right-continuous: m(t_step) is the new mass.

#include <cstdint>
#include <string>
#include <vector>

#include "massid/gen/study_config.h"

namespace vid::massid::gen {

/// @brief A piecewise-linear mass profile: value at breakpoints, steps as coinciding times.
class MassProfile {
 public:
  /// @brief Profile `name` for base mass m_base; every event time is moved by one uniform
  /// draw in +-time_jitter_s from `seed` and snapped to the sample grid of `rate_hz`, so
  /// steps happen exactly at a sample time.
  /// @throws std::invalid_argument on an unknown name
  static MassProfile make(const std::string& name, double m_base_kg,
                          const MassProfileSettings& settings, double rate_hz, std::uint64_t seed);
  /// @brief A constant mass.
  static MassProfile constant(double m_kg);
  /// @brief m(t) [kg].
  double mass_kg(double t_s) const;
  /// @brief Event times after jitter (for tests and plots).
  const std::vector<double>& event_times() const { return events_s_; }

 private:
  /// Segments: on [t_i, t_{i+1}) mass goes linearly from m_start_i to m_end_i; the last
  /// segment extends to infinity at m_end.
  struct Segment {
    double t0, t1, m0, m1;
  };
  std::vector<Segment> segments_;
  std::vector<double> events_s_;
};

}  // namespace vid::massid::gen
