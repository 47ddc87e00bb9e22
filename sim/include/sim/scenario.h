#pragma once
/// @file scenario.h
/// @brief A simulation scenario (config/sim/*.yaml): vehicle, controller, trajectory,
/// environment, sensors, cameras, plus the raw scene/render/features sections that the
/// render module parses. Keys are documented in config/sim/README.md.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dynamics/quadrotor.h"
#include "sim/controller.h"
#include "sim/environment.h"
#include "sim/sensor_faults.h"
#include "sim/takeoff_landing.h"
#include "sim/trajectory.h"
#include "types/calibration.h"
#include "types/measurements.h"

namespace vid::sim {

/// @brief IMU sensor: EuRoC/Kalibr noise plus the initial biases.
struct ImuConfig {
  ImuNoise noise;  ///< rate_hz, densities, random walks
  Eigen::Vector3d initial_gyro_bias = Eigen::Vector3d::Zero();   ///< [rad/s]
  Eigen::Vector3d initial_accel_bias = Eigen::Vector3d::Zero();  ///< [m/s^2]
};

/// @brief Rotor speed sensor; unit must match the vehicle's rotor speed unit.
struct RotorConfig {
  bool enabled = true;
  RotorSensor sensor;
};

/// @brief Cameras (same rate, synchronised).
struct CamerasConfig {
  double rate_hz = 30.0;
  std::vector<CameraCalib> cameras;
  bool images = true;    ///< render images (off: feature-only)
  bool features = true;  ///< write feat0 (feature-level measurements) + landmarks.csv
  /// True camera-IMU clock offset [s], Kalibr's sign: t_imu = t_cam + offset. Every camera
  /// stamp is the IMU-clock time of its image minus the offset (plus jitter). What the written
  /// calibration says is each camera's `timeshift_cam_imu` (default 0: unknown).
  double time_offset_s = 0.0;
  double time_offset_jitter_s = 0.0;  ///< per-frame Gaussian jitter of the offset [s] (clamped to 3 sigma)
};

/// @brief Everything vid_sim needs to produce one sequence.
struct Scenario {
  std::string file;          ///< source file (for messages)
  std::string name;
  std::uint64_t seed = 1;
  double duration_s = 60.0;
  TimeNs start_time_ns = 1'700'000'000'000'000'000LL;
  bool noise = true;         ///< false: every sensor noise and random walk off
  double physics_max_step_s = 0.001;
  double control_rate_hz = 500.0;

  dynamics::QuadrotorParams vehicle;
  std::string rotor_unit = "rpm";
  ControllerGains gains;
  TrajectoryConfig trajectory;
  EnvironmentConfig environment;   ///< incl. `ground:` (environment.ground)
  TakeoffLandingConfig takeoff_landing;  ///< start and end at rest on the ground

  ImuConfig imu;
  RotorConfig rotor;
  double groundtruth_rate_hz = 200.0;
  /// Heading (yaw about gravity) of the vehicle at t = 0 in the written ground-truth world
  /// [deg]; unset = the trajectory's own. Real recordings start at any heading in their
  /// motion-capture world while an estimator starts at its own; this makes the two differ.
  std::optional<double> initial_heading_deg;
  bool initial_heading_random = false;  ///< draw initial_heading_deg from the seed
  CamerasConfig cameras;
  /// Real-sensor effects (`sensor_faults:`); all off by default. The thrust-axis tilt acts in
  /// the physics only: `vehicle` stays the nominal vehicle the controller knows.
  SensorFaultsConfig faults;

  YAML::Node scene_node;     ///< raw `scene:` section (may be null)
  YAML::Node render_node;    ///< raw `render:` section (may be null)
  YAML::Node features_node;  ///< raw `features:` section (may be null)
};

/// @brief Load and validate a scenario file. Unknown keys, wrong types and bad values throw
/// vid::io::ConfigError "FILE: key 'a.b': message".
Scenario load_scenario(const std::filesystem::path& file);

/// @brief Same from a YAML string; @p name stands for the file in messages.
Scenario load_scenario_string(const std::string& text, const std::string& name);

/// @brief Apply vid_sim's run options to a loaded scenario: @p seed and @p duration_s replace
/// the scenario's (and its trajectory's); @p heading is degrees, "random" (drawn from the
/// seed) or empty (the scenario's). A malformed heading throws std::invalid_argument.
void apply_run_options(Scenario& s, std::optional<std::uint64_t> seed, std::optional<double> duration_s,
                       const std::string& heading);

/// @brief Vehicle parameters for vehicle.yaml (mass, gravity, k_i): the simulated k_i times
/// `sensor_faults.thrust_coefficient_factor` (1 unless set).
VehicleParams vehicle_params_of(const Scenario& s);

}  // namespace vid::sim
