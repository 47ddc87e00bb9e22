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
  if (config_.ground.enabled) ground_.emplace(config_.ground);
  impacts_ = config_.impacts;
  const auto drawn = draw_random_impacts(config_.random_impacts, duration_s, derive_seed(seed, 0x696d7061ULL));
  impacts_.insert(impacts_.end(), drawn.begin(), drawn.end());
  // The mass must stay physical over the whole run.
  double lowest = initial_mass_kg;
  for (double t = 0.0; t <= duration_s + 1.0; t += 0.01) lowest = std::min(lowest, mass_kg(t));
  if (!(lowest > 0.1 * initial_mass_kg))
    throw std::invalid_argument("mass: payload drops / mass loss take the mass below 10 % of the initial mass");
}

std::pair<Eigen::Vector3d, Eigen::Vector3d> SimEnvironment::wind_and_rate_W(double t) const {
  Eigen::Vector3d v = config_.wind.mean_mps, dv = Eigen::Vector3d::Zero();
  if (!gusts_.empty()) {
    const double x = std::max(0.0, t) / gust_dt_s_;
    const std::size_t i = std::min(static_cast<std::size_t>(x), gusts_.size() - 2);
    const double f = std::min(1.0, x - static_cast<double>(i));
    v += (1.0 - f) * gusts_[i] + f * gusts_[i + 1];
    if (t > 0.0 && f < 1.0) dv = (gusts_[i + 1] - gusts_[i]) / gust_dt_s_;  // slope of the segment
  }
  return {v, dv};
}

Eigen::Vector3d SimEnvironment::wind_velocity_W(double t) const { return wind_and_rate_W(t).first; }

Eigen::Vector3d SimEnvironment::rope_force_W(const dynamics::QuadrotorState& x) const {
  return rope_force(config_.rope, x.p_WI, x.v_WI, Eigen::Vector3d::Zero()).f_W;
}

Eigen::Vector3d SimEnvironment::tether_force_W(const dynamics::QuadrotorState& x) const {
  return rope_force(config_.tether, x.p_WI, x.v_WI, Eigen::Vector3d::Zero()).f_W;
}

ForceAndRate SimEnvironment::evaluate(double t, const dynamics::QuadrotorState& x, const Eigen::Vector3d& a_W,
                                      const Eigen::Vector3d& dw_I) const {
  ForceAndRate sum;
  auto add = [&sum](const ForceAndRate& s) {
    sum.f_W += s.f_W;
    sum.df_W += s.df_W;
  };
  add(rope_force(config_.rope, x.p_WI, x.v_WI, a_W));
  add(rope_force(config_.tether, x.p_WI, x.v_WI, a_W));
  if (config_.wind.enabled) {
    const auto [v_air, dv_air] = wind_and_rate_W(t);
    add({config_.wind.drag_N_per_mps * (v_air - x.v_WI), config_.wind.drag_N_per_mps * (dv_air - a_W)});
  }
  for (const PushConfig& p : config_.pushes) add(pulse_force(p, t));
  for (const PushConfig& p : impacts_) add(pulse_force(p, t));
  // Body-frame steps: F_W = R_WI F_I, dF_W/dt = R_WI (w_I x F_I + dF_I/dt).
  Eigen::Vector3d f_I = Eigen::Vector3d::Zero(), df_I = Eigen::Vector3d::Zero();
  for (const ForceStepConfig& s : config_.steps) {
    const Eigen::Vector2d k = step_fraction(s, t);
    if (s.body_frame) {
      f_I += k[0] * s.force_N;
      df_I += k[1] * s.force_N;
    } else {
      add({k[0] * s.force_N, k[1] * s.force_N});
    }
  }
  if (!f_I.isZero() || !df_I.isZero()) {
    const Eigen::Matrix3d R_WI = x.q_WI.toRotationMatrix();
    add({R_WI * f_I, R_WI * (x.w_I.cross(f_I) + df_I)});
  }
  add(config_.from_file.eval(t));
  if (ground_) {
    const ContactWrench c = ground_->evaluate(x, a_W, dw_I);
    add({c.f_W, c.df_W});
  }
  return sum;
}

Eigen::Vector3d SimEnvironment::force_W(double t, const dynamics::QuadrotorState& x) const {
  return evaluate(t, x, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()).f_W;
}

Eigen::Vector3d SimEnvironment::torque_I(double /*t_s*/, const dynamics::QuadrotorState& x) const {
  if (!ground_) return Eigen::Vector3d::Zero();
  return ground_->evaluate(x, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()).tau_I;
}

ContactWrench SimEnvironment::ground_contact(const dynamics::QuadrotorState& x, const Eigen::Vector3d& a_W,
                                             const Eigen::Vector3d& dw_I) const {
  return ground_ ? ground_->evaluate(x, a_W, dw_I) : ContactWrench{};
}

Eigen::Vector3d SimEnvironment::force_rate_W(double t, const dynamics::QuadrotorState& x,
                                             const Eigen::Vector3d& a_W, const Eigen::Vector3d& dw_I) const {
  return evaluate(t, x, a_W, dw_I).df_W;
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

Eigen::Vector3d external_force_rate_W(const SimEnvironment& env, const dynamics::QuadrotorParams& vehicle,
                                      double t, const dynamics::QuadrotorState& x, const Eigen::Vector3d& a_W,
                                      const Eigen::Vector3d& dw_I) {
  // d/dt (-R D R^T v) with dR/dt = R [w]x: -R (w x (D v_I) - D (w x v_I) + D R^T a).
  const Eigen::Matrix3d R_WI = x.q_WI.toRotationMatrix();
  const Eigen::Vector3d& d = vehicle.linear_drag;
  const Eigen::Vector3d v_I = R_WI.transpose() * x.v_WI;
  const Eigen::Vector3d drag_rate_I =
      x.w_I.cross(d.cwiseProduct(v_I)) - d.cwiseProduct(x.w_I.cross(v_I)) + d.cwiseProduct(R_WI.transpose() * a_W);
  return env.force_rate_W(t, x, a_W, dw_I) - R_WI * drag_rate_I;
}

}  // namespace vid::sim
