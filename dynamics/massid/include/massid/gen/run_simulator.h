#pragma once
/// @file run_simulator.h
/// @brief One run of the study: reference trajectory + MPC with the wrong nominal mass +
/// true dynamics of docs/model.md eq. (55) with the true (time-varying) mass + noisy measurements.
///
/// Timing: sample k is at t_k = k / rate_hz. Its row holds the measured q, p, v at t_k and the
/// commands computed from them; the commands are held (zero-order hold) on [t_k, t_{k+1}).
/// True dynamics (docs/model.md eq. (55)): q' = 1/2 q ⊗ [0, w], p' = v, v' = R(q) (T/m) e3 + g_W, integrated
/// with the exact rotation for constant w and RK4 (dynamics/rk4.h) for p, v (integration_substeps per sample).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "geometry/pose.h"
#include "massid/gen/study_config.h"
#include "massid/run_data.h"

namespace vid::massid::gen {

/// @brief Noise-free state of a study run at a sample time, with the controller's reference
/// and command (for tests and diagnostics; sim::TruthSample is the simulator's, unrelated).
struct RunTruthSample {
  Pose T_WI;  ///< true attitude and position
  Eigen::Vector3d v_WI = Eigen::Vector3d::Zero();
  Eigen::Vector3d p_ref_W = Eigen::Vector3d::Zero();  ///< reference position at t_k
  Eigen::Vector3d a_cmd_W = Eigen::Vector3d::Zero();  ///< acceleration the MPC asked for
  bool saturated = false;  ///< a controller bound was active at t_k
};

/// @brief Summary numbers of one run.
struct RunStats {
  double position_rmse_m = 0.0;    ///< true p vs reference over the whole run
  double saturated_fraction = 0.0; ///< fraction of samples with an active bound
  double thrust_min_N = 0.0, thrust_max_N = 0.0;  ///< observed command range
  double thrust_bound_min_N = 0.0, thrust_bound_max_N = 0.0;  ///< physical bounds
  double mass_base_kg = 0.0;
};

/// @brief Result of simulate_run.
struct SimulatedRun {
  MassIdRun run;                   ///< what goes to the CSV and the manifest
  std::vector<RunTruthSample> truth;  ///< one per sample
  RunStats stats;
};

/// @brief Seed of run `index` of trajectory x profile; depends on names, not list positions,
/// so a subset generates the same runs as the full study.
std::uint64_t run_seed(std::uint64_t base_seed, const std::string& trajectory,
                       const std::string& profile, int index);

/// @brief Simulate one run (deterministic in `seed`).
/// @throws std::invalid_argument on unknown trajectory or profile
SimulatedRun simulate_run(const GeneratorSettings& settings, const std::string& trajectory,
                          const std::string& profile, int index, std::uint64_t seed);

/// @brief Write the noise-free companion of a run (diagnostics, plots of the inputs):
/// `t,px,py,pz,qw,qx,qy,qz,vx,vy,vz,px_ref,py_ref,pz_ref,ax_cmd,ay_cmd,az_cmd,saturated`.
/// @throws std::runtime_error naming the file when it cannot be written
void write_truth_csv(const std::filesystem::path& file, const SimulatedRun& run);

}  // namespace vid::massid::gen
