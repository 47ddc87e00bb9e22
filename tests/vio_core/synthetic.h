#pragma once
// Analytic synthetic multirotor sequences for the estimator tests: smooth trajectory,
// body z along the required thrust direction, a smooth external force, exact or noisy IMU,
// rotor speeds (4 equal rotors), and feature frames of random landmarks (mono or stereo).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "types/calibration.h"
#include "types/measurements.h"
#include "vio_core/estimator.h"
#include "vio_core/estimator_params.h"

namespace vid::test {

struct TimeWindow {
  double start = -1.0, end = -1.0;  // seconds; inactive if start < 0
  bool contains(double t) const { return start >= 0.0 && t >= start && t < end; }
};

struct SynthConfig {
  double duration = 10.0;
  double imu_rate = 400.0, rotor_rate = 100.0, cam_rate = 20.0;
  bool noisy = false;
  unsigned seed = 1;
  // noise actually applied when noisy (continuous-time densities)
  double gyro_density = 1e-3, accel_density = 0.05, thrust_density = 0.02;  // thrust: m/s^2/sqrt(Hz)
  double pixel_sigma = 1.0, focal = 400.0;
  Eigen::Vector3d b_g{0.004, -0.003, 0.002}, b_a{0.05, -0.04, 0.03};
  double force_amplitude = 1.0;  // m/s^2 (mass-normalized)
  bool stereo = true;
  int landmarks = 2000;
  TimeWindow rotor_gap, camera_gap, imu_gap;
  double mass = 1.5, gravity = 9.81;
};

struct TruthState {
  TimeNs t_ns = 0;
  Eigen::Vector3d p, v, F_W, F_I;
  Eigen::Quaterniond q;
};

struct SynthData {
  std::vector<Measurement> stream;
  std::vector<TruthState> truth;  // at IMU times
  VehicleParams vehicle;
  std::vector<CameraCalib> cameras;
};

/// Analytic truth at time t [s].
TruthState synth_truth(const SynthConfig& c, double t);
SynthData generate(const SynthConfig& c);
/// Estimator config matching the data (noise params = generator noise, GT-style init sigmas).
EstimatorConfig matching_config(const SynthConfig& c, const SynthData& d, PropagationMode mode);
/// Filter initial state from truth at the first IMU time (biases zero, force from truth).
ImuState initial_state(const SynthConfig& c);

}  // namespace vid::test
