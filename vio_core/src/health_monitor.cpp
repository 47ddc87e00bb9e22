/// @file health_monitor.cpp
#include "vio_core/health_monitor.h"

#include <algorithm>
#include <cstdio>

namespace vid {

HealthMonitor::HealthMonitor(const EstimatorParams& p) : p_(p) {}

HealthVerdict HealthMonitor::on_frame(TimeNs t_ns, int tested, int rejected_chi2, int untriangulated) {
  HealthVerdict v;
  if (!seen_frame_) {
    seen_frame_ = true;
    last_used_ns_ = last_frame_ns_ = t_ns;
  }
  // Starvation: time since the last frame in which a track reached the update.
  if (starving_) starved_s_ += static_cast<double>(t_ns - last_frame_ns_) * 1e-9;
  last_frame_ns_ = t_ns;
  if (tested + untriangulated > 0) {
    last_used_ns_ = t_ns;
    starving_ = false;
  } else if (p_.health_starvation_s > 0.0 && !starving_ &&
             static_cast<double>(t_ns - last_used_ns_) * 1e-9 >= p_.health_starvation_s) {
    starving_ = true;
    ++episodes_;
  }
  v.starving = starving_;

  // Innovations: the chi2 gate's rejection fraction over the window.
  window_.push_back({t_ns, tested, rejected_chi2});
  tested_ += tested;
  rejected_ += rejected_chi2;
  const TimeNs span = seconds_to_ns(p_.health_window_s);
  while (!window_.empty() && window_.front().t_ns <= t_ns - span) {
    tested_ -= window_.front().tested;
    rejected_ -= window_.front().rejected;
    window_.pop_front();
  }
  if (tested_ >= p_.health_min_tested_features && tested_ > 0)
    max_fraction_ = std::max(max_fraction_, static_cast<double>(rejected_) / tested_);
  if (p_.health_max_chi2_rejected_fraction > 0.0 && tested_ >= p_.health_min_tested_features &&
      rejected_ >= p_.health_max_chi2_rejected_fraction * tested_) {
    v.out_of_band = true;
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "visual innovations out of band: %d of %d features failed the chi2 gate over the last %.2g s",
                  rejected_, tested_, p_.health_window_s);
    v.message = buf;
  } else if (starving_) {
    char buf[120];
    std::snprintf(buf, sizeof buf, "feature starvation: no feature track reached an update for %.2f s",
                  static_cast<double>(t_ns - last_used_ns_) * 1e-9);
    v.message = buf;
  }
  return v;
}

}  // namespace vid
