#include "sim/sensors.h"

#include <cmath>

namespace vid::sim {

ImuModel::ImuModel(const ImuConfig& config, bool noise, std::uint64_t seed)
    : config_(config), noise_(noise), rng_(seed), b_g_(config.initial_gyro_bias), b_a_(config.initial_accel_bias) {}

Eigen::Vector3d ImuModel::normal3() {
  // Fixed evaluation order (x, y, z) keeps the stream reproducible.
  const double x = rng_.normal();
  const double y = rng_.normal();
  const double z = rng_.normal();
  return Eigen::Vector3d(x, y, z);
}

ImuSample ImuModel::measure(TimeNs t_ns, const Eigen::Vector3d& w_I, const Eigen::Vector3d& f_I) {
  ImuSample s;
  s.t_ns = t_ns;
  s.gyro_I = w_I + b_g_;
  s.accel_I = f_I + b_a_;
  if (noise_) {
    const double sq = std::sqrt(config_.noise.rate_hz);
    s.gyro_I += config_.noise.gyro_noise_density * sq * normal3();
    s.accel_I += config_.noise.accel_noise_density * sq * normal3();
  }
  return s;
}

void ImuModel::step_bias() {
  if (!noise_) return;
  const double sdt = std::sqrt(1.0 / config_.noise.rate_hz);
  b_g_ += config_.noise.gyro_random_walk * sdt * normal3();
  b_a_ += config_.noise.accel_random_walk * sdt * normal3();
}

RotorSensorModel::RotorSensorModel(const RotorSensor& config, bool noise, std::uint64_t seed)
    : config_(config), noise_(noise), rng_(seed) {}

RotorSample RotorSensorModel::measure(TimeNs t_ns, const Eigen::VectorXd& speeds) {
  RotorSample s;
  s.t_ns = t_ns;
  const double sigma = config_.noise_density * std::sqrt(config_.rate_hz);
  for (Eigen::Index i = 0; i < speeds.size(); ++i) {
    double n = speeds[i];
    if (noise_) n += sigma * rng_.normal();
    // A stopped rotor gives no tachometer pulses: exactly 0. A turning one never reads
    // below 0 (the noise is clipped; it is drawn in both cases to keep the stream aligned).
    if (speeds[i] == 0.0) n = 0.0;
    if (n < 0.0) n = 0.0;
    s.speeds.push_back(n);
  }
  return s;
}

}  // namespace vid::sim
