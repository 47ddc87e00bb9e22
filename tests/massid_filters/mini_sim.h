#pragma once
/// @file mini_sim.h
/// @brief A tiny deterministic simulator of docs/model.md eq. (55) for the filter tests: a loop reference
/// flown with differentially-flat commands (thrust from the true mass, body rates from the
/// reference attitude), truth integrated with RK4 on the continuous ODE (inputs held between
/// samples), and Gaussian noise on the measured q, p, v.

#include <functional>

#include "massid/run_data.h"

namespace vid::massid::test {

/// @brief Settings of one simulated run.
struct MiniSimConfig {
  double duration_s = 8.0;
  double rate_hz = 100.0;
  double initial_mass_guess = 1.2;                       ///< 20% above the true 1.0 kg
  std::function<double(double)> mass = [](double) { return 1.0; };  ///< true mass at t
  double sigma_q = 0.005, sigma_p = 0.01, sigma_v = 0.02;
  double loop_radius_m = 2.0, loop_period_s = 6.0, loop_height_amp_m = 0.5;
  std::uint64_t seed = 7;
};

/// @brief Simulate one run (trajectory "loop").
MassIdRun simulate_loop(const MiniSimConfig& cfg);

}  // namespace vid::massid::test
