/// @file thrust_buffer.cpp
/// @brief Interpolation of thrust to IMU times.
#include "vio_core/thrust_buffer.h"

namespace vid {

void ThrustBuffer::add(TimeNs t_ns, double thrust_per_mass) {
  if (!samples_.empty() && t_ns < samples_.back().first) return;
  if (!samples_.empty() && t_ns == samples_.back().first) {
    samples_.back().second = thrust_per_mass;
    return;
  }
  samples_.emplace_back(t_ns, thrust_per_mass);
}

ThrustQuery ThrustBuffer::at(TimeNs t_ns) const {
  ThrustQuery q;
  if (samples_.empty()) return q;
  q.valid = true;
  if (t_ns <= samples_.front().first) {
    q.T_m.z() = samples_.front().second;
    q.held = samples_.front().first - t_ns > gap_ns_;
    return q;
  }
  if (t_ns >= samples_.back().first) {
    q.T_m.z() = samples_.back().second;
    q.held = t_ns - samples_.back().first > gap_ns_;
    return q;
  }
  // first sample strictly after t
  auto it = samples_.begin();
  while (it->first <= t_ns) ++it;
  const auto& b = *it;
  const auto& a = *(it - 1);
  const double w = static_cast<double>(t_ns - a.first) / static_cast<double>(b.first - a.first);
  q.T_m.z() = (1.0 - w) * a.second + w * b.second;
  // inside a long gap between two samples: the interpolation spans missing data
  q.held = (b.first - a.first) > 2 * gap_ns_;
  return q;
}

void ThrustBuffer::prune_before(TimeNs t_ns) {
  while (samples_.size() > 2 && samples_[1].first <= t_ns) samples_.pop_front();
}

}  // namespace vid
