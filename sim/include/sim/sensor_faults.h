#pragma once
/// @file sensor_faults.h
/// @brief What real multirotor sensors do that the ideal ones do not (`sensor_faults:`,
/// config/sim/README.md "Real-sensor effects"): rotor-harmonic and broadband IMU vibration
/// with bursts, IMU stamp jitter, a tilted thrust axis, rotor telemetry latency /
/// quantization / lost messages, a thrust-coefficient error of the written vehicle.yaml and
/// one-rotor speed dips. Everything is off by default; with every key absent the simulator
/// draws no extra random numbers and its output is byte-identical to that of before.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sim/render/random.h"
#include "types/measurements.h"

namespace vid::sim {

/// @brief Band-limited vibration burst on the IMU in [t_s, t_s + duration_s].
struct VibrationBurst {
  double t_s = 0.0;
  double duration_s = 1.0;
  double accel_rms = 0.0;  ///< per axis [m/s^2] on the flat part of the window
  double gyro_rms = 0.0;   ///< per axis [rad/s]
  double band_lo_hz = 10.0, band_hi_hz = 40.0;
};

/// @brief Rotor-driven IMU vibration. Amplitudes hold at `reference_speed` and scale with
/// (n / reference_speed)^speed_exponent per rotor.
struct VibrationConfig {
  bool enabled = false;
  double reference_speed = 0.0;  ///< [rotor unit]; 0 = hover speed of the nominal vehicle
  double speed_exponent = 2.0;
  int blades = 2;
  Eigen::Vector3d accel_rotor_amplitude = Eigen::Vector3d::Zero();  ///< per rotor, line at f_rot [m/s^2]
  Eigen::Vector3d accel_blade_amplitude = Eigen::Vector3d::Zero();  ///< per rotor, line at blades f_rot
  Eigen::Vector3d gyro_rotor_amplitude = Eigen::Vector3d::Zero();   ///< [rad/s]
  Eigen::Vector3d gyro_blade_amplitude = Eigen::Vector3d::Zero();
  double accel_noise_density = 0.0;  ///< broadband [m/s^2/sqrt(Hz)] (Kalibr: sigma_d = density sqrt(rate))
  double gyro_noise_density = 0.0;   ///< [rad/s/sqrt(Hz)]
  std::vector<VibrationBurst> bursts;
};

/// @brief One rotor's speed command scaled by (1 - depth) over [t_s, t_s + duration_s].
struct RotorDip {
  double t_s = 0.0;
  int rotor = 0;
  double duration_s = 0.1;
  double depth = 0.15;
};

/// @brief Random dips: Poisson arrivals on a uniformly drawn rotor (own random stream).
struct RandomRotorDips {
  double rate_per_s = 0.0;
  double duration_s = 0.1;
  double depth = 0.15;
  double start_s = 2.0;
  double end_s = -1.0;  ///< < 0: the scenario's end
};

/// @brief The whole `sensor_faults:` section.
struct SensorFaultsConfig {
  VibrationConfig vibration;
  double imu_jitter_s = 0.0;      ///< sigma of IMU stamp - true sample time [s]
  double imu_max_jitter_s = 0.0;  ///< bound of that difference [s]
  double thrust_tilt_deg = 0.0;   ///< thrust axis angle from z_I
  double thrust_azimuth_deg = 0.0;  ///< direction of the tilt, from x_I about z_I
  double thrust_coefficient_factor = 1.0;  ///< written vehicle.yaml k_i / simulated k_i
  double rotor_latency_s = 0.0;     ///< rotor stamps = true sample time + latency
  double rotor_quantization = 0.0;  ///< speed step [rotor unit]; 0 = none
  double rotor_drop_probability = 0.0;  ///< each rotor message is lost with this probability
  int rotor_max_consecutive_drops = 2;  ///< longest gap = (this + 1) periods
  std::vector<RotorDip> dips;
  RandomRotorDips random_dips;

  /// @brief Unit thrust axis in I (z_I when there is no tilt).
  Eigen::Vector3d thrust_axis_I() const;
  bool imu_jitter() const { return imu_jitter_s > 0.0; }
  bool rotor_telemetry() const {
    return rotor_latency_s > 0.0 || rotor_quantization > 0.0 || rotor_drop_probability > 0.0;
  }
};

/// @brief Rotor frequency [Hz] of speed @p n in @p unit ("rpm": n / 60, "rad/s": n / 2 pi).
double rotor_frequency_hz(double n, const std::string& unit);

/// @brief Adds vibration to IMU samples. Call once per IMU sample, in order, with the true
/// sample time and rotor speeds; the rotor angles are integrated between calls (trapezoid).
class VibrationModel {
 public:
  VibrationModel(const VibrationConfig& config, const std::string& rotor_unit, double hover_speed,
                 double imu_rate_hz, int rotor_count, std::uint64_t seed);
  /// @brief Add the vibration at true time @p t_s to @p sample (gyro and accel).
  void apply(double t_s, const Eigen::VectorXd& rotor_speeds, ImuSample* sample);

 private:
  Eigen::Vector3d burst_value(double t_s, bool gyro) const;
  VibrationConfig config_;
  std::string unit_;
  double reference_speed_;
  double rate_hz_;
  Rng rng_;
  Eigen::VectorXd angle_;     ///< rotor angles [rad]
  Eigen::VectorXd last_freq_; ///< rotor frequencies at the previous sample [Hz]
  double last_t_s_ = 0.0;
  bool first_ = true;
  /// Random phases [rotor][harmonic 0/1][accel 0..2, gyro 3..5].
  std::vector<std::array<std::array<double, 6>, 2>> phase_;
  struct Tone { double f_hz, phase, amp; };
  std::vector<std::array<std::vector<Tone>, 6>> burst_tones_;  ///< per burst, per channel
};

/// @brief IMU stamps: true time + clamp(N(0, sigma), +-max), then strictly increasing with at
/// least 5 % of the sample period between stamps.
class ImuStampJitter {
 public:
  ImuStampJitter(double sigma_s, double max_s, double rate_hz, std::uint64_t seed);
  TimeNs stamp(TimeNs t_true);

 private:
  double sigma_s_, max_s_;
  TimeNs min_gap_ns_;
  Rng rng_;
  std::optional<TimeNs> last_;
};

/// @brief Rotor telemetry as received: lost messages, quantized speeds, late stamps.
class RotorTelemetry {
 public:
  RotorTelemetry(const SensorFaultsConfig& config, bool noise, std::uint64_t seed);
  /// @brief The message as received, or nullopt when it is lost.
  std::optional<RotorSample> receive(RotorSample s);

 private:
  double latency_s_, quantization_, drop_p_;
  int max_drops_;
  Rng rng_;
  int consecutive_ = 0;
};

/// @brief One-rotor speed dips acting on the motors (the listed ones plus the random ones).
class RotorDips {
 public:
  RotorDips(const SensorFaultsConfig& config, int rotor_count, double duration_s, std::uint64_t seed);
  bool empty() const { return dips_.empty(); }
  const std::vector<RotorDip>& dips() const { return dips_; }
  /// @brief The motor command at @p t_s: each dipping rotor's command times (1 - depth).
  Eigen::VectorXd apply(double t_s, const Eigen::VectorXd& n_cmd) const;

 private:
  std::vector<RotorDip> dips_;
};

}  // namespace vid::sim
