#pragma once
/// @file sim_test_util.h
/// @brief Helpers of the simulator tests: load presets, collect a run in memory.

#include <string>
#include <vector>

#include "sim/scenario.h"
#include "sim/simulator.h"

namespace vid::sim::test {

/// @brief config/sim/<name>.yaml of the source tree.
std::string preset_path(const std::string& name);

/// @brief Everything a run produced, in memory.
struct Recording : SimSink {
  std::vector<ImuSample> imu;
  std::vector<RotorSample> rotor;
  std::vector<GroundTruthSample> gt;
  std::vector<ForceSample> force;
  std::vector<MassSample> mass;
  std::vector<TruthSample> truth;
  std::vector<PhaseSample> phase;
  void on_imu(const ImuSample& s) override { imu.push_back(s); }
  void on_rotor(const RotorSample& s) override { rotor.push_back(s); }
  void on_groundtruth(const GroundTruthSample& s) override { gt.push_back(s); }
  void on_force(const ForceSample& s) override { force.push_back(s); }
  void on_mass(const MassSample& s) override { mass.push_back(s); }
  void on_truth(const TruthSample& s) override { truth.push_back(s); }
  void on_phase(const PhaseSample& s) override { phase.push_back(s); }
};

/// @brief The vid17_like vehicle hovering at 1.2 m (no rope, no camera), IMU at @p imu_rate_hz
/// with zero white noise and biases, plus @p extra YAML appended at the top level.
Scenario hover_scenario(const std::string& extra, double duration_s, double imu_rate_hz = 400.0);

/// @brief Run a scenario without cameras and return what it produced.
Recording record(Scenario sc);

/// @brief Position RMSE of ground truth against the reference trajectory over [t_from, end].
double tracking_rmse(const Simulator& sim, const Recording& rec, double t_from_s);

}  // namespace vid::sim::test
