#pragma once
/// @file study_config.h
/// @brief Settings of the study's data generator (config/massid/study.yaml), with the defaults
/// documented in dynamics/massid/README.md "Data generation".

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "types/calibration.h"

namespace vid::massid::gen {

/// @brief Sizes and timing of the reference trajectories (see reference_trajectory.h).
struct TrajectorySettings {
  double altitude_m = 1.5;         ///< mean height of every trajectory
  double ramp_s = 3.0;             ///< smooth start from hover (time warp)
  double loop_radius_m = 2.0;      ///< loop: circle radius
  double loop_period_s = 8.0;      ///< loop: time per revolution
  double loop_z_amplitude_m = 0.3; ///< loop: height oscillation, twice per revolution
  double lemniscate_size_m = 3.0;  ///< lemniscate (Gerono): half width in x (y half height = size/2)
  double lemniscate_period_s = 6.0;
  double zigzag_dx_m = 1.5;        ///< zigzag: forward step per leg
  double zigzag_dy_m = 2.0;        ///< zigzag: lateral peak-to-peak per leg
  double zigzag_dz_m = 0.5;        ///< zigzag: height peak-to-peak per leg
  double zigzag_leg_s = 2.5;       ///< zigzag: duration of one leg (rest to rest)
  double square_side_m = 3.0;
  double square_leg_s = 3.0;       ///< square: duration of one side (rest to rest)
  double random_accel_xy = 3.0;    ///< random: bound on |a| per horizontal axis [m/s^2]
  double random_accel_z = 1.5;     ///< random: bound on |a_z| [m/s^2]
  double random_amplitude_xy = 3.0;  ///< random: bound on sum of amplitudes per horizontal axis [m]
  double random_amplitude_z = 0.8;   ///< random: bound on sum of vertical amplitudes [m]
  double random_freq_min_hz = 0.05;
  double random_freq_max_hz = 0.3;
};

/// @brief Mass profile parameters (see mass_profile.h); times in s, fractions of the base mass.
struct MassProfileSettings {
  double time_jitter_s = 1.0;        ///< per-run uniform jitter of every event time (+-)
  double decrease_start_s = 5.0;     ///< linear_decrease: spraying starts
  double decrease_end_s = 20.0;      ///< linear_decrease: tank empty
  double decrease_fraction = 0.3;    ///< linear_decrease: mass sprayed / base mass
  double step_time_s = 10.0;         ///< step_drop / step_pickup
  double step_fraction = 0.25;       ///< step size / base mass
  std::vector<double> up_down_times_s = {5.0, 10.0, 15.0, 20.0};  ///< pick up, drop, ...
  double up_down_fraction = 0.25;
};

/// @brief Linearized MPC and attitude loop (see mpc_controller.h).
struct ControllerSettings {
  double mpc_dt_s = 0.1;        ///< prediction step
  int horizon = 10;             ///< prediction steps
  double weight_p = 10.0;       ///< position error weight [1/m^2]
  double weight_v = 1.0;        ///< velocity error weight [s^2/m^2]
  double weight_a = 0.2;        ///< acceleration deviation from the reference [s^4/m^2]
  double accel_xy_max = 6.0;    ///< per-axis bound on horizontal acceleration [m/s^2]
  double integral_gain = 2.0;   ///< position-error integral [1/s^3] (0 = off)
  double integral_accel_max = 6.0;  ///< anti-windup bound on the integral term [m/s^2]
  double attitude_gain = 8.0;   ///< P gain on the attitude error [1/s]
  double rate_max = 6.0;        ///< per-axis body-rate bound [rad/s]
  double tilt_max_deg = 40.0;   ///< thrust-direction tilt bound
  double thrust_min_ratio = 0.3;  ///< thrust bounds as multiples of base weight m_base g
  double thrust_max_ratio = 2.2;
};

/// @brief Everything the generator needs.
struct GeneratorSettings {
  std::vector<std::string> trajectories = {"random", "loop", "lemniscate", "zigzag", "square"};
  std::vector<std::string> profiles = {"constant", "linear_decrease", "step_drop", "step_pickup",
                                       "up_down"};
  int runs = 50;                    ///< per trajectory x profile
  std::uint64_t seed = 20240601;    ///< base seed; each run's seed is derived from it
  double rate_hz = 100.0;           ///< sample (and control) rate
  double duration_s = 25.0;
  int integration_substeps = 2;     ///< RK4 steps per sample interval
  double gravity = kDefaultGravity;
  double mass_min_kg = 0.8;         ///< per-run base mass, uniform in [min, max]
  double mass_max_kg = 1.6;
  double initial_mass_factor = 1.2; ///< controller/methods believe m0 = factor * m_true(0)
  double sigma_q = 0.005;           ///< [rad] attitude measurement noise per axis
  double sigma_p = 0.01;            ///< [m]
  double sigma_v = 0.02;            ///< [m/s]
  TrajectorySettings trajectory;
  MassProfileSettings mass;
  ControllerSettings controller;
};

/// @brief Parse YAML text (every key optional; unknown keys are errors).
/// @throws std::runtime_error "SOURCE: key 'k': message"
GeneratorSettings parse_generator_settings(const std::string& yaml_text, const std::string& source);
/// @brief Load a settings file. @throws std::runtime_error naming the file and key
GeneratorSettings load_generator_settings(const std::filesystem::path& file);
/// @brief The settings as YAML text (parse_generator_settings gives them back).
std::string generator_settings_yaml(const GeneratorSettings& settings);
/// @brief Field-wise equality over the same table that parses and prints.
bool operator==(const GeneratorSettings& a, const GeneratorSettings& b);
/// @brief Check ranges and names. @throws std::invalid_argument naming the key
void validate(const GeneratorSettings& settings);

}  // namespace vid::massid::gen
