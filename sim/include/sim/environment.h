#pragma once
/// @file environment.h
/// @brief External forces (elastic rope, wind with gusts, impulsive pushes) and the mass
/// profile (payload pick-up/drop, continuous mass loss) as deterministic functions of time
/// and vehicle state.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "dynamics/quadrotor.h"

namespace vid::sim {

/// @brief Elastic rope from a fixed anchor to the CoM; pulls only when stretched.
struct RopeConfig {
  bool enabled = false;
  Eigen::Vector3d anchor_W = Eigen::Vector3d::Zero();  ///< [m]
  double rest_length_m = 1.0;
  double stiffness_N_per_m = 20.0;
  double damping_Ns_per_m = 2.0;
  /// Damping fades in over the first `damping_ramp_m` of stretch so the tension is continuous
  /// when the rope becomes taut (a real rope does not jump either).
  double damping_ramp_m = 0.02;
};

/// @brief Wind: air velocity = mean + Ornstein-Uhlenbeck gusts; force = c (v_air - v).
struct WindConfig {
  bool enabled = false;
  Eigen::Vector3d mean_mps = Eigen::Vector3d::Zero();
  double gust_std_mps = 0.0;         ///< stationary std of each gust component
  double gust_time_constant_s = 2.0;
  double drag_N_per_mps = 0.3;       ///< linear air drag coefficient
};

/// @brief Impulsive push: F(t) = force sin^2(pi (t - t0) / duration) on [t0, t0 + duration].
struct PushConfig {
  double t_s = 0.0;
  Eigen::Vector3d force_N = Eigen::Vector3d::Zero();  ///< peak force, W
  double duration_s = 0.2;
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
  WindConfig wind;
  std::vector<PushConfig> pushes;
  std::vector<PayloadEvent> payloads;
  MassLossConfig mass_loss;
};

/// @brief Deterministic environment built from a config, initial mass, duration and seed.
class SimEnvironment : public dynamics::Environment {
 public:
  /// @throws std::invalid_argument when the mass would drop to <= 10 % of the initial mass
  SimEnvironment(const EnvironmentConfig& config, double initial_mass_kg, double duration_s,
                 std::uint64_t seed);
  Eigen::Vector3d force_W(double t_s, const dynamics::QuadrotorState& x) const override;
  double mass_kg(double t_s) const override;
  /// @brief Rope tension force alone [N, W] (zero when slack).
  Eigen::Vector3d rope_force_W(const dynamics::QuadrotorState& x) const;
  /// @brief Air velocity at t (mean + gust) [m/s].
  Eigen::Vector3d wind_velocity_W(double t_s) const;

 private:
  EnvironmentConfig config_;
  double initial_mass_kg_;
  double gust_dt_s_ = 0.01;
  std::vector<Eigen::Vector3d> gusts_;  ///< gust samples every gust_dt_s_
};

}  // namespace vid::sim
