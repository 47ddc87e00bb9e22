/// @file mass_profile.cpp
/// @brief The five true-mass profiles as piecewise-linear segments.
#include "massid/gen/mass_profile.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "massid/gen/rng.h"

namespace vid::massid::gen {

MassProfile MassProfile::constant(double m_kg) {
  MassProfile p;
  p.segments_.push_back({0.0, std::numeric_limits<double>::infinity(), m_kg, m_kg});
  return p;
}

MassProfile MassProfile::make(const std::string& name, double m_base, const MassProfileSettings& s,
                              double rate_hz, std::uint64_t seed) {
  Rng rng(seed ^ 0x6D61'7373ull);
  const double shift = s.time_jitter_s > 0.0 ? rng.uniform(-s.time_jitter_s, s.time_jitter_s) : 0.0;
  auto at = [&](double t) { return std::max(0.0, std::round((t + shift) * rate_hz) / rate_hz); };
  const double inf = std::numeric_limits<double>::infinity();
  MassProfile p;
  if (name == "constant") {
    return constant(m_base);
  } else if (name == "linear_decrease") {
    const double t0 = at(s.decrease_start_s), t1 = at(s.decrease_end_s);
    const double m_end = m_base * (1.0 - s.decrease_fraction);
    p.segments_ = {{0.0, t0, m_base, m_base}, {t0, t1, m_base, m_end}, {t1, inf, m_end, m_end}};
    p.events_s_ = {t0, t1};
  } else if (name == "step_drop" || name == "step_pickup") {
    const double ts = at(s.step_time_s);
    const double m1 = m_base * (name == "step_drop" ? 1.0 - s.step_fraction : 1.0 + s.step_fraction);
    p.segments_ = {{0.0, ts, m_base, m_base}, {ts, inf, m1, m1}};
    p.events_s_ = {ts};
  } else if (name == "up_down") {
    double t_prev = 0.0;
    bool loaded = false;
    for (double t_event : s.up_down_times_s) {
      const double te = at(t_event);
      const double m = loaded ? m_base * (1.0 + s.up_down_fraction) : m_base;
      p.segments_.push_back({t_prev, te, m, m});
      p.events_s_.push_back(te);
      t_prev = te;
      loaded = !loaded;
    }
    const double m = loaded ? m_base * (1.0 + s.up_down_fraction) : m_base;
    p.segments_.push_back({t_prev, inf, m, m});
  } else {
    throw std::invalid_argument("unknown mass profile '" + name +
                                "' (constant, linear_decrease, step_drop, step_pickup, up_down)");
  }
  return p;
}

double MassProfile::mass_kg(double t) const {
  for (const Segment& seg : segments_) {
    if (t < seg.t1) {
      if (t <= seg.t0 || !std::isfinite(seg.t1) || seg.t1 <= seg.t0) return seg.m0;
      return seg.m0 + (seg.m1 - seg.m0) * (t - seg.t0) / (seg.t1 - seg.t0);
    }
  }
  return segments_.back().m1;
}

}  // namespace vid::massid::gen
