#pragma once
/// @file environment.h
/// @brief External forces (elastic rope, tether, wind with gusts, pushes, impacts, force
/// steps, a replayed force table, the floor's contact with the landing gear) and the mass profile (payload pick-up/drop, continuous mass
/// loss) as deterministic functions of time and vehicle state, with the force's time
/// derivative for ground truth.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "dynamics/quadrotor.h"
#include "sim/force_sources.h"
#include "sim/ground_contact.h"

namespace vid::sim {

/// @brief Wind: air velocity = mean + Ornstein-Uhlenbeck gusts; force = c (v_air - v).
struct WindConfig {
  bool enabled = false;
  Eigen::Vector3d mean_mps = Eigen::Vector3d::Zero();
  double gust_std_mps = 0.0;         ///< stationary std of each gust component
  double gust_time_constant_s = 2.0;
  double drag_N_per_mps = 0.3;       ///< linear air drag coefficient
};

/// @brief Payload pick-up (delta > 0) or drop (delta < 0), blended over ramp_s (0 = step).
struct PayloadEvent {
  double t_s = 0.0;
  double delta_kg = 0.0;
  double ramp_s = 0.2;
};

/// @brief Continuous mass loss (spraying) at a constant rate on [start, end].
struct MassLossConfig {
  double rate_kg_per_s = 0.0;
  double start_s = 0.0;
  double end_s = 0.0;
};

/// @brief Everything acting on the vehicle from outside.
struct EnvironmentConfig {
  RopeConfig rope;
  RopeConfig tether;                      ///< stiff rope, damping_ramp_m = 0 (snaps taut)
  WindConfig wind;
  std::vector<PushConfig> pushes;
  std::vector<PushConfig> impacts;        ///< listed impacts (short sin^2 pulses)
  RandomImpactsConfig random_impacts;
  std::vector<ForceStepConfig> steps;
  ForceTable from_file;                   ///< empty = none
  std::vector<PayloadEvent> payloads;
  MassLossConfig mass_loss;
  GroundContactConfig ground;             ///< floor contact of the landing gear (off by default)
};

/// @brief Deterministic environment built from a config, initial mass, duration and seed.
class SimEnvironment : public dynamics::Environment {
 public:
  /// @throws std::invalid_argument when the mass would drop to <= 10 % of the initial mass
  SimEnvironment(const EnvironmentConfig& config, double initial_mass_kg, double duration_s,
                 std::uint64_t seed);
  Eigen::Vector3d force_W(double t_s, const dynamics::QuadrotorState& x) const override;
  double mass_kg(double t_s) const override;
  /// @brief Torque of the ground contact about the CoM [N m, I] (zero without `ground:`).
  Eigen::Vector3d torque_I(double t_s, const dynamics::QuadrotorState& x) const override;
  bool has_torque() const override { return ground_.has_value(); }
  /// @brief d/dt force_W along the motion [N/s, W]; @p a_W is the vehicle's acceleration at
  /// (t, x) (rope damping and wind drag depend on it), @p dw_I its angular acceleration (the
  /// ground contact at the gear feet depends on it). Analytic for every source; a true
  /// force step contributes 0 (its rate is an impulse, not representable).
  Eigen::Vector3d force_rate_W(double t_s, const dynamics::QuadrotorState& x, const Eigen::Vector3d& a_W,
                               const Eigen::Vector3d& dw_I = Eigen::Vector3d::Zero()) const;
  /// @brief The ground contact, or nullptr without `ground:`.
  const GroundContact* ground() const { return ground_ ? &*ground_ : nullptr; }
  /// @brief Ground reaction (normal + friction) alone, its rate and torque at (x, a_W, dw_I);
  /// all zero without `ground:`.
  ContactWrench ground_contact(const dynamics::QuadrotorState& x, const Eigen::Vector3d& a_W,
                               const Eigen::Vector3d& dw_I) const;
  /// @brief Call after every accepted integration step: updates the friction stick anchors.
  void commit_step(const dynamics::QuadrotorState& x) {
    if (ground_) ground_->commit(x);
  }
  /// @brief Replace the contact state (stick anchors), e.g. by a settled copy's.
  void set_ground(const GroundContact& ground) { ground_ = ground; }
  /// @brief Rope tension force alone [N, W] (zero when slack).
  Eigen::Vector3d rope_force_W(const dynamics::QuadrotorState& x) const;
  /// @brief Tether tension force alone [N, W] (zero when slack).
  Eigen::Vector3d tether_force_W(const dynamics::QuadrotorState& x) const;
  /// @brief Air velocity at t (mean + gust) [m/s].
  Eigen::Vector3d wind_velocity_W(double t_s) const;
  /// @brief Every impact pulse (listed, then the random ones drawn from the seed).
  const std::vector<PushConfig>& impacts() const { return impacts_; }

 private:
  /// @brief Sum of all sources; the rate part uses @p a_W and @p dw_I.
  ForceAndRate evaluate(double t_s, const dynamics::QuadrotorState& x, const Eigen::Vector3d& a_W,
                        const Eigen::Vector3d& dw_I) const;
  /// @brief Air velocity and its rate (slope of the gust interpolation).
  std::pair<Eigen::Vector3d, Eigen::Vector3d> wind_and_rate_W(double t_s) const;

  EnvironmentConfig config_;
  double initial_mass_kg_;
  double gust_dt_s_ = 0.01;
  std::vector<Eigen::Vector3d> gusts_;  ///< gust samples every gust_dt_s_
  std::vector<PushConfig> impacts_;
  std::optional<GroundContact> ground_;
};

/// @brief Rate of the whole force0 ground truth (environment incl. ground contact + linear
/// rotor drag F_drag = -R diag(d) R^T v) [N/s, W], analytic, at (t, x) with acceleration
/// @p a_W and angular acceleration @p dw_I.
Eigen::Vector3d external_force_rate_W(const SimEnvironment& env, const dynamics::QuadrotorParams& vehicle,
                                      double t_s, const dynamics::QuadrotorState& x, const Eigen::Vector3d& a_W,
                                      const Eigen::Vector3d& dw_I = Eigen::Vector3d::Zero());

}  // namespace vid::sim
