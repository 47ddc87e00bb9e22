#pragma once
/// @file force_sources.h
/// @brief The individual external-force sources of the simulator (elastic rope / tether,
/// sin^2 pulses for pushes and impacts, force steps, a replayed force table, random impacts)
/// as pure functions returning the force AND its analytic time derivative. SimEnvironment
/// (environment.h) sums them.

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace vid::sim {

/// @brief A force [N, W] and its time derivative [N/s, W] at one instant.
struct ForceAndRate {
  Eigen::Vector3d f_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d df_W = Eigen::Vector3d::Zero();
};

/// @brief Elastic rope from a fixed anchor to the CoM; pulls only when stretched. Also the
/// `tether` (damping_ramp_m = 0: the damping acts in full as soon as the rope is taut).
struct RopeConfig {
  bool enabled = false;
  Eigen::Vector3d anchor_W = Eigen::Vector3d::Zero();  ///< [m]
  double rest_length_m = 1.0;
  double stiffness_N_per_m = 20.0;
  double damping_Ns_per_m = 2.0;
  /// Damping fades in over the first `damping_ramp_m` of stretch so the tension is continuous
  /// when the rope becomes taut (a real rope does not jump either). 0 = no fade (tether).
  double damping_ramp_m = 0.02;
};

/// @brief sin^2 pulse F(t) = force sin^2(pi (t - t0) / duration) on [t0, t0 + duration]:
/// pushes and impacts.
struct PushConfig {
  double t_s = 0.0;
  Eigen::Vector3d force_N = Eigen::Vector3d::Zero();  ///< peak force, W
  double duration_s = 0.2;
};

/// @brief Random impacts: Poisson arrivals, peak and duration uniform in their ranges.
struct RandomImpactsConfig {
  double rate_per_s = 0.0;                ///< mean impacts per second (0 = none)
  double peak_min_N = 20.0, peak_max_N = 50.0;
  double duration_min_s = 0.02, duration_max_s = 0.05;
  double start_s = 2.0;                   ///< no impact before (take-off)
  double end_s = -1.0;                    ///< none after; < 0 = scenario end
  std::string directions = "horizontal";  ///< horizontal (wall) | up (ground) | any
};

/// @brief Force step (hook engaged, payload released): delta force_N added at t_s, in the
/// world frame or the body frame (rotates with the vehicle); a linear ramp over rise_s
/// (0 = true step).
struct ForceStepConfig {
  double t_s = 0.0;
  Eigen::Vector3d force_N = Eigen::Vector3d::Zero();  ///< delta [N], W or I
  bool body_frame = false;
  double rise_s = 0.0;
};

/// @brief World-frame force table replayed with linear interpolation, held outside its span.
struct ForceTable {
  std::string file;                   ///< source (messages, summary)
  std::vector<double> t_s;            ///< strictly increasing, relative to the scenario start
  std::vector<Eigen::Vector3d> f_W_N;
  bool empty() const { return t_s.empty(); }
  /// @brief Interpolated force and the slope of its segment (0 outside the span).
  ForceAndRate eval(double t_s) const;
};

/// @brief Load a `t_ns, Fx, Fy, Fz` CSV ('#' lines skipped; t_ns relative to the scenario
/// start). @throws io::DatasetError "FILE:LINE: column N 'name': ..." on malformed rows,
/// non-increasing times or an empty file.
ForceTable load_force_table(const std::filesystem::path& csv);

/// @brief Rope / tether force on a vehicle at p with velocity v and acceleration a (all W);
/// tension = k s + fade(s) c ds/dt clipped at 0 (a rope never pushes), zero while slack.
/// The rate is analytic (d/dt of tension and direction), zero where the tension is clipped.
ForceAndRate rope_force(const RopeConfig& rope, const Eigen::Vector3d& p_W, const Eigen::Vector3d& v_W,
                        const Eigen::Vector3d& a_W);

/// @brief sin^2 pulse and its analytic rate (peak rate pi |F| / duration at a quarter).
ForceAndRate pulse_force(const PushConfig& pulse, double t_s);

/// @brief Fraction of a step applied at t (0..1) and its rate [1/s] (0 for a true step).
Eigen::Vector2d step_fraction(const ForceStepConfig& step, double t_s);

/// @brief Draw the random impacts on [start, end or duration] from @p seed (deterministic).
std::vector<PushConfig> draw_random_impacts(const RandomImpactsConfig& config, double duration_s,
                                            std::uint64_t seed);

}  // namespace vid::sim
