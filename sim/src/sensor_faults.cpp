/// @file sensor_faults.cpp
/// @brief Real-sensor effects (sim/include/sim/sensor_faults.h, config/sim/README.md).

#include "sim/sensor_faults.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vid::sim {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr int kBurstTones = 12;  // sinusoids per burst and channel: a dense enough band

/// @brief Raised-cosine window on [0, d] with ramps of a fifth of d (flat in between).
double burst_envelope(double u, double d) {
  if (u < 0.0 || u > d) return 0.0;
  const double ramp = 0.2 * d;
  const double e = std::min(u, d - u);
  return e >= ramp ? 1.0 : 0.5 - 0.5 * std::cos(std::numbers::pi * e / ramp);
}

}  // namespace

Eigen::Vector3d SensorFaultsConfig::thrust_axis_I() const {
  if (thrust_tilt_deg == 0.0) return Eigen::Vector3d::UnitZ();
  const double a = thrust_tilt_deg * std::numbers::pi / 180.0, z = thrust_azimuth_deg * std::numbers::pi / 180.0;
  return Eigen::Vector3d(std::sin(a) * std::cos(z), std::sin(a) * std::sin(z), std::cos(a));
}

double rotor_frequency_hz(double n, const std::string& unit) { return unit == "rpm" ? n / 60.0 : n / kTwoPi; }

VibrationModel::VibrationModel(const VibrationConfig& config, const std::string& rotor_unit, double hover_speed,
                               double imu_rate_hz, int rotor_count, std::uint64_t seed)
    : config_(config),
      unit_(rotor_unit),
      reference_speed_(config.reference_speed > 0.0 ? config.reference_speed : hover_speed),
      rate_hz_(imu_rate_hz),
      rng_(seed),
      angle_(Eigen::VectorXd::Zero(rotor_count)),
      last_freq_(Eigen::VectorXd::Zero(rotor_count)),
      phase_(rotor_count) {
  // Draw order fixed: phases (rotor, harmonic, channel), then burst tones; the broadband
  // noise continues the same stream sample by sample.
  for (auto& r : phase_)
    for (auto& h : r)
      for (double& p : h) p = rng_.uniform(0.0, kTwoPi);
  for (const VibrationBurst& b : config_.bursts) {
    std::array<std::vector<Tone>, 6> tones;
    for (int c = 0; c < 6; ++c) {
      const double rms = c < 3 ? b.accel_rms : b.gyro_rms;
      for (int k = 0; k < kBurstTones; ++k) {
        const double f = rng_.uniform(b.band_lo_hz, b.band_hi_hz);
        const double ph = rng_.uniform(0.0, kTwoPi);
        tones[c].push_back({f, ph, rms * std::sqrt(2.0 / kBurstTones)});
      }
    }
    burst_tones_.push_back(std::move(tones));
  }
}

Eigen::Vector3d VibrationModel::burst_value(double t_s, bool gyro) const {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < config_.bursts.size(); ++i) {
    const VibrationBurst& b = config_.bursts[i];
    const double env = burst_envelope(t_s - b.t_s, b.duration_s);
    if (env == 0.0) continue;
    for (int a = 0; a < 3; ++a) {
      for (const Tone& tone : burst_tones_[i][(gyro ? 3 : 0) + a])
        v[a] += env * tone.amp * std::sin(kTwoPi * tone.f_hz * (t_s - b.t_s) + tone.phase);
    }
  }
  return v;
}

void VibrationModel::apply(double t_s, const Eigen::VectorXd& rotor_speeds, ImuSample* sample) {
  const Eigen::Index n_rot = angle_.size();
  Eigen::VectorXd freq(n_rot);
  for (Eigen::Index r = 0; r < n_rot; ++r) freq[r] = rotor_frequency_hz(rotor_speeds[r], unit_);
  if (!first_) angle_ += kTwoPi * 0.5 * (freq + last_freq_) * (t_s - last_t_s_);
  first_ = false;
  last_freq_ = freq;
  last_t_s_ = t_s;

  Eigen::Vector3d acc = Eigen::Vector3d::Zero(), gyr = Eigen::Vector3d::Zero();
  double mean_scale = 0.0;
  for (Eigen::Index r = 0; r < n_rot; ++r) {
    const double s = std::pow(std::max(rotor_speeds[r], 0.0) / reference_speed_, config_.speed_exponent);
    mean_scale += s / static_cast<double>(n_rot);
    const double harmonic[2] = {1.0, static_cast<double>(config_.blades)};
    for (int h = 0; h < 2; ++h) {
      const Eigen::Vector3d& A = h == 0 ? config_.accel_rotor_amplitude : config_.accel_blade_amplitude;
      const Eigen::Vector3d& G = h == 0 ? config_.gyro_rotor_amplitude : config_.gyro_blade_amplitude;
      for (int a = 0; a < 3; ++a) {
        acc[a] += s * A[a] * std::sin(harmonic[h] * angle_[r] + phase_[r][h][a]);
        gyr[a] += s * G[a] * std::sin(harmonic[h] * angle_[r] + phase_[r][h][3 + a]);
      }
    }
  }
  // Broadband: drawn every sample (also with the rotors stopped) to keep the stream aligned.
  const double sq = std::sqrt(rate_hz_) * mean_scale;
  for (int a = 0; a < 3; ++a) acc[a] += config_.accel_noise_density * sq * rng_.normal();
  for (int a = 0; a < 3; ++a) gyr[a] += config_.gyro_noise_density * sq * rng_.normal();
  sample->accel_I += acc + burst_value(t_s, false);
  sample->gyro_I += gyr + burst_value(t_s, true);
}

ImuStampJitter::ImuStampJitter(double sigma_s, double max_s, double rate_hz, std::uint64_t seed)
    : sigma_s_(sigma_s),
      max_s_(max_s),
      min_gap_ns_(std::max<TimeNs>(1, static_cast<TimeNs>(std::llround(0.05e9 / rate_hz)))),
      rng_(seed) {}

TimeNs ImuStampJitter::stamp(TimeNs t_true) {
  const double e = std::clamp(sigma_s_ * rng_.normal(), -max_s_, max_s_);
  TimeNs s = t_true + static_cast<TimeNs>(std::llround(e * 1e9));
  if (last_ && s < *last_ + min_gap_ns_) s = *last_ + min_gap_ns_;
  last_ = s;
  return s;
}

RotorTelemetry::RotorTelemetry(const SensorFaultsConfig& config, bool noise, std::uint64_t seed)
    : latency_s_(config.rotor_latency_s),
      quantization_(config.rotor_quantization),
      drop_p_(noise ? config.rotor_drop_probability : 0.0),
      max_drops_(config.rotor_max_consecutive_drops),
      rng_(seed) {}

std::optional<RotorSample> RotorTelemetry::receive(RotorSample s) {
  if (drop_p_ > 0.0) {
    const bool lost = rng_.uniform() < drop_p_;  // drawn for every message
    if (lost && consecutive_ < max_drops_) {
      ++consecutive_;
      return std::nullopt;
    }
    consecutive_ = 0;
  }
  if (quantization_ > 0.0) {
    for (double& n : s.speeds) n = std::round(n / quantization_) * quantization_;
  }
  s.t_ns += static_cast<TimeNs>(std::llround(latency_s_ * 1e9));
  return s;
}

RotorDips::RotorDips(const SensorFaultsConfig& config, int rotor_count, double duration_s, std::uint64_t seed)
    : dips_(config.dips) {
  const RandomRotorDips& r = config.random_dips;
  if (r.rate_per_s > 0.0) {
    Rng rng(seed);
    const double end = r.end_s < 0.0 ? duration_s : std::min(r.end_s, duration_s);
    for (double t = r.start_s;;) {
      t += -std::log(1.0 - rng.uniform()) / r.rate_per_s;  // exponential inter-arrival
      const int rotor = std::min(rotor_count - 1, static_cast<int>(rng.uniform() * rotor_count));
      if (t + r.duration_s > end) break;
      dips_.push_back({t, rotor, r.duration_s, r.depth});
    }
  }
}

Eigen::VectorXd RotorDips::apply(double t_s, const Eigen::VectorXd& n_cmd) const {
  Eigen::VectorXd n = n_cmd;
  for (const RotorDip& d : dips_) {
    if (t_s >= d.t_s && t_s < d.t_s + d.duration_s && d.rotor < n.size()) n[d.rotor] *= 1.0 - d.depth;
  }
  return n;
}

}  // namespace vid::sim
