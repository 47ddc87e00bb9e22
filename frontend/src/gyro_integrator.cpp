#include "frontend/gyro_integrator.h"

#include <Eigen/Geometry>
#include <algorithm>

#include "geometry/so3.h"

namespace vid {

void GyroIntegrator::add(const ImuSample& s) {
  if (!buf_.empty() && s.t_ns <= buf_.back().t_ns) return;
  buf_.push_back(s);
  while (buf_.size() > max_samples_) buf_.pop_front();
}

Eigen::Vector3d GyroIntegrator::rate_at(TimeNs t) const {
  if (t <= buf_.front().t_ns) return buf_.front().gyro_I;
  if (t >= buf_.back().t_ns) return buf_.back().gyro_I;
  const auto it = std::lower_bound(buf_.begin(), buf_.end(), t,
                                   [](const ImuSample& s, TimeNs v) { return s.t_ns < v; });
  const auto& b = *it;
  const auto& a = *(it - 1);
  const double f = static_cast<double>(t - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  return (1.0 - f) * a.gyro_I + f * b.gyro_I;
}

std::optional<Eigen::Matrix3d> GyroIntegrator::rotation(TimeNs t0, TimeNs t1,
                                                        TimeNs max_gap_ns) const {
  if (buf_.empty() || t1 < t0) return std::nullopt;
  if (buf_.front().t_ns > t0 + max_gap_ns || buf_.back().t_ns < t1 - max_gap_ns) {
    return std::nullopt;
  }
  // Knots: t0, every sample strictly inside (t0, t1), t1; trapezoid rate on each piece.
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  TimeNs ta = t0;
  Eigen::Vector3d wa = rate_at(t0);
  auto it = std::upper_bound(buf_.begin(), buf_.end(), t0,
                             [](TimeNs v, const ImuSample& s) { return v < s.t_ns; });
  for (; it != buf_.end() && it->t_ns < t1; ++it) {
    const double dt = ns_to_s(it->t_ns - ta);
    R = R * so3::exp(0.5 * (wa + it->gyro_I) * dt);
    ta = it->t_ns;
    wa = it->gyro_I;
  }
  const Eigen::Vector3d wb = rate_at(t1);
  R = R * so3::exp(0.5 * (wa + wb) * ns_to_s(t1 - ta));
  return R;
}

void GyroIntegrator::prune_before(TimeNs t) {
  // Keep one sample at or before t for interpolation.
  while (buf_.size() >= 2 && buf_[1].t_ns <= t) buf_.pop_front();
}

}  // namespace vid
