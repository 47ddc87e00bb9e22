/// @file test_imu_noise.cpp
/// @brief IMU noise densities and bias random walks estimated from a long static run (Allan
/// variance, non-overlapping clusters, pooled over the three axes) match the configured
/// values within 10 %; rotor speed noise matches its density; noise off means exact values.

#include <gtest/gtest.h>

#include <cmath>

#include "sim/sensors.h"

namespace vid::sim {
namespace {

/// @brief Overlapping Allan variance at cluster size m (in blocks) from 0.1 s block means y,
/// pooled over the three axes.
double allan_variance(const std::vector<Eigen::Vector3d>& y, std::size_t m) {
  std::vector<Eigen::Vector3d> cum(y.size() + 1, Eigen::Vector3d::Zero());
  for (std::size_t j = 0; j < y.size(); ++j) cum[j + 1] = cum[j] + y[j];
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t k = 0; k + 2 * m <= y.size(); ++k) {
    const Eigen::Vector3d c0 = (cum[k + m] - cum[k]) / static_cast<double>(m);
    const Eigen::Vector3d c1 = (cum[k + 2 * m] - cum[k + m]) / static_cast<double>(m);
    sum += (c1 - c0).squaredNorm();
    ++count;
  }
  return 0.5 * sum / (3.0 * static_cast<double>(count));
}

/// @brief Solve AVAR(tau) = N^2 / tau + K^2 tau / 3 at a short and a long cluster time.
void estimate(const std::vector<Eigen::Vector3d>& blocks, double block_s, double* N, double* K) {
  const double t1 = 1.0, t2 = 100.0;
  const double a1 = allan_variance(blocks, static_cast<std::size_t>(std::lround(t1 / block_s)));
  const double a2 = allan_variance(blocks, static_cast<std::size_t>(std::lround(t2 / block_s)));
  Eigen::Matrix2d A;
  A << 1 / t1, t1 / 3, 1 / t2, t2 / 3;
  const Eigen::Vector2d s = A.inverse() * Eigen::Vector2d(a1, a2);
  *N = std::sqrt(s[0]);
  *K = std::sqrt(s[1]);
}

TEST(ImuNoise, AllanEstimatesMatchConfiguration) {
  ImuConfig cfg;
  cfg.noise.rate_hz = 400.0;
  cfg.noise.gyro_noise_density = 0.001;
  cfg.noise.gyro_random_walk = 3.5e-5;
  cfg.noise.accel_noise_density = 0.1;
  cfg.noise.accel_random_walk = 4.0e-3;
  ImuModel imu(cfg, true, 12345);
  // Four hours static, kept as 0.1 s block means (the Allan clusters are multiples of it).
  const std::size_t per_block = 40;
  const std::size_t blocks = static_cast<std::size_t>(4 * 3600 * 10);
  std::vector<Eigen::Vector3d> gyro(blocks, Eigen::Vector3d::Zero()), accel(blocks, Eigen::Vector3d::Zero());
  const Eigen::Vector3d f_I(0.0, 0.0, 9.81);
  TimeNs t = 0;
  for (std::size_t b = 0; b < blocks; ++b) {
    for (std::size_t k = 0; k < per_block; ++k, t += 2'500'000) {
      const ImuSample s = imu.measure(t, Eigen::Vector3d::Zero(), f_I);
      gyro[b] += s.gyro_I / static_cast<double>(per_block);
      accel[b] += (s.accel_I - f_I) / static_cast<double>(per_block);
      imu.step_bias();
    }
  }
  double Ng, Kg, Na, Ka;
  estimate(gyro, 0.1, &Ng, &Kg);
  estimate(accel, 0.1, &Na, &Ka);
  std::printf("gyro N %.4e (0.001) K %.4e (3.5e-5); accel N %.4e (0.1) K %.4e (4e-3)\n", Ng, Kg, Na, Ka);
  EXPECT_NEAR(Ng / 0.001, 1.0, 0.10);
  EXPECT_NEAR(Kg / 3.5e-5, 1.0, 0.10);
  EXPECT_NEAR(Na / 0.1, 1.0, 0.10);
  EXPECT_NEAR(Ka / 4.0e-3, 1.0, 0.10);
}

TEST(ImuNoise, NoiseOffIsExact) {
  ImuConfig cfg;
  cfg.initial_gyro_bias = Eigen::Vector3d(0.01, 0.02, 0.03);
  ImuModel imu(cfg, false, 1);
  for (int k = 0; k < 100; ++k) {
    const ImuSample s = imu.measure(k, Eigen::Vector3d(1, 2, 3), Eigen::Vector3d(4, 5, 6));
    EXPECT_EQ((s.gyro_I - Eigen::Vector3d(1.01, 2.02, 3.03)).norm(), 0.0);
    EXPECT_EQ((s.accel_I - Eigen::Vector3d(4, 5, 6)).norm(), 0.0);
    imu.step_bias();
  }
}

TEST(RotorNoise, StandardDeviationMatchesDensity) {
  RotorSensor cfg;
  cfg.rate_hz = 100.0;
  cfg.noise_density = 1.459;
  RotorSensorModel rotor(cfg, true, 99);
  const Eigen::VectorXd truth = Eigen::Vector4d(5000, 5100, 5200, 5300);
  double sum2 = 0.0;
  const int n = 50000;
  for (int k = 0; k < n; ++k) {
    const RotorSample s = rotor.measure(k, truth);
    for (int i = 0; i < 4; ++i) sum2 += (s.speeds[i] - truth[i]) * (s.speeds[i] - truth[i]);
  }
  const double sigma = std::sqrt(sum2 / (4.0 * n));
  EXPECT_NEAR(sigma / (1.459 * 10.0), 1.0, 0.02);
}

}  // namespace
}  // namespace vid::sim
