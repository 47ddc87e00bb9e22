#pragma once
/// @file sensors.h
/// @brief IMU (white noise + bias random walk, discrete-time EuRoC/Kalibr model) and rotor
/// speed sensor (white noise) models, seeded deterministically.

#include <Eigen/Core>
#include <cstdint>

#include "sim/render/random.h"
#include "sim/scenario.h"
#include "types/measurements.h"

namespace vid::sim {

/// @brief Discrete IMU: y = x + b + sigma_d n, sigma_d = density * sqrt(rate);
/// b_{k+1} = b_k + walk * sqrt(dt) n.
class ImuModel {
 public:
  ImuModel(const ImuConfig& config, bool noise, std::uint64_t seed);
  /// @brief Measurement from true body rate and specific force (both in I), using the
  /// current biases.
  ImuSample measure(TimeNs t_ns, const Eigen::Vector3d& w_I, const Eigen::Vector3d& f_I);
  /// @brief Advance the bias random walk by one sample period (call after measure()).
  void step_bias();
  const Eigen::Vector3d& gyro_bias() const { return b_g_; }
  const Eigen::Vector3d& accel_bias() const { return b_a_; }

 private:
  Eigen::Vector3d normal3();
  ImuConfig config_;
  bool noise_;
  Rng rng_;
  Eigen::Vector3d b_g_, b_a_;
};

/// @brief Rotor speed sensor: y_i = max(0, n_i + sigma_d n), sigma_d = density * sqrt(rate);
/// exactly 0 for a stopped rotor (n_i = 0).
class RotorSensorModel {
 public:
  RotorSensorModel(const RotorSensor& config, bool noise, std::uint64_t seed);
  RotorSample measure(TimeNs t_ns, const Eigen::VectorXd& speeds);

 private:
  RotorSensor config_;
  bool noise_;
  Rng rng_;
};

}  // namespace vid::sim
