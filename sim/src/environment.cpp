#include "sim/environment.h"

#include <cmath>
#include <stdexcept>

#include "sim/render/random.h"
#include "smooth_profile.h"

namespace vid::sim {

SimEnvironment::SimEnvironment(const EnvironmentConfig& config, double initial_mass_kg,
                               double duration_s, std::uint64_t seed)
    : config_(config), initial_mass_kg_(initial_mass_kg) {
  const auto& w = config_.wind;
  if (w.enabled && w.gust_std_mps > 0.0) {
    if (!(w.gust_time_constant_s > 0.0)) throw std::invalid_argument("wind: gust_time_constant_s must be > 0");
    // Exact discretisation of the OU process at gust_dt_s_.
    Rng rng(derive_seed(seed, 0x77696e64ULL));
    const double phi = std::exp(-gust_dt_s_ / w.gust_time_constant_s);
    const double q = w.gust_std_mps * std::sqrt(1.0 - phi * phi);
    const std::size_t n = static_cast<std::size_t>(std::ceil(duration_s / gust_dt_s_)) + 3;
    Eigen::Vector3d g(rng.normal(), rng.normal(), rng.normal());
    g *= w.gust_std_mps;
    gusts_.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
      gusts_.push_back(g);
      g = phi * g + q * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    }
  }
  // The mass must stay physical over the whole run.
  double lowest = initial_mass_kg;
  for (double t = 0.0; t <= duration_s + 1.0; t += 0.01) lowest = std::min(lowest, mass_kg(t));
  if (!(lowest > 0.1 * initial_mass_kg))
    throw std::invalid_argument("mass: payload drops / mass loss take the mass below 10 % of the initial mass");
}

Eigen::Vector3d SimEnvironment::wind_velocity_W(double t) const {
  Eigen::Vector3d v = config_.wind.mean_mps;
  if (!gusts_.empty()) {
    const double x = std::max(0.0, t) / gust_dt_s_;
    const std::size_t i = std::min(static_cast<std::size_t>(x), gusts_.size() - 2);
    const double f = std::min(1.0, x - static_cast<double>(i));
    v += (1.0 - f) * gusts_[i] + f * gusts_[i + 1];
  }
  return v;
}

Eigen::Vector3d SimEnvironment::rope_force_W(const dynamics::QuadrotorState& x) const {
  const RopeConfig& r = config_.rope;
  const Eigen::Vector3d d = x.p_WI - r.anchor_W;
  const double len = d.norm();
  const double stretch = len - r.rest_length_m;
  if (!r.enabled || stretch <= 0.0 || len < 1e-9) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d u = d / len;
  const double rate = u.dot(x.v_WI);
  const double fade = r.damping_ramp_m > 0.0 ? std::min(1.0, stretch / r.damping_ramp_m) : 1.0;
  const double tension = std::max(0.0, r.stiffness_N_per_m * stretch + fade * r.damping_Ns_per_m * rate);
  return -tension * u;
}

Eigen::Vector3d SimEnvironment::force_W(double t, const dynamics::QuadrotorState& x) const {
  Eigen::Vector3d f = rope_force_W(x);
  if (config_.wind.enabled) f += config_.wind.drag_N_per_mps * (wind_velocity_W(t) - x.v_WI);
  for (const PushConfig& p : config_.pushes) {
    const double u = (t - p.t_s) / p.duration_s;
    if (u > 0.0 && u < 1.0) {
      const double s = std::sin(M_PI * u);
      f += p.force_N * s * s;
    }
  }
  return f;
}

double SimEnvironment::mass_kg(double t) const {
  double m = initial_mass_kg_;
  for (const PayloadEvent& e : config_.payloads) {
    if (e.ramp_s <= 0.0) {
      if (t >= e.t_s) m += e.delta_kg;
    } else {
      m += e.delta_kg * detail::smoothstep7((t - e.t_s) / e.ramp_s)[0];
    }
  }
  const MassLossConfig& l = config_.mass_loss;
  if (l.rate_kg_per_s > 0.0 && l.end_s > l.start_s)
    m -= l.rate_kg_per_s * std::clamp(t - l.start_s, 0.0, l.end_s - l.start_s);
  return m;
}

}  // namespace vid::sim
