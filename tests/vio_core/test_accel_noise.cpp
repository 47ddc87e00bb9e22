// Vibration-aware accelerometer noise (vio_core/accel_noise.h): covariance matching on the
// white part of the innovations, checked on synthetic innovation sequences.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "vio_core/accel_noise.h"

namespace vid {
namespace {

constexpr double kRate = 400.0;           // IMU rate [Hz]
constexpr double kRnom = 0.1 * 0.1 * kRate;  // 0.1 m/s^2/sqrt(Hz) per sample [(m/s^2)^2]
constexpr double kWindow_s = 0.25;        // the default accel_noise_window_s
constexpr double kWindow = kWindow_s * kRate;  // in samples

// Feeds r(k) on the x axis (y, z white at the nominal noise), as the estimator does: the
// innovation covariance is the noise that was used (no state uncertainty here). Returns the
// x-axis noise variance after every sample.
template <class Fn>
std::vector<double> feed(AccelNoiseAdapter& a, int n, Fn r_x, std::mt19937& rng) {
  std::normal_distribution<double> white(0.0, std::sqrt(kRnom));
  std::vector<double> R;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d S = a.noise_var();
    a.add(Eigen::Vector3d(r_x(k), white(rng), white(rng)), S);
    R.push_back(a.noise_var().x());
  }
  return R;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

TEST(AccelNoise, ConsistentInnovationsKeepTheNominalNoise) {
  AccelNoiseAdapter a(kRnom, kWindow_s, kRate);
  std::mt19937 rng(1);
  std::normal_distribution<double> white(0.0, std::sqrt(kRnom));
  feed(a, 8000, [&](int) { return white(rng); }, rng);
  // The 2x threshold over a 100-sample window is ~7 sigma of the window variance's spread.
  EXPECT_LT(a.inflated_samples(), 8000 / 100);
}

TEST(AccelNoise, WhiteNoiseThreeTimesNominalIsMatched) {
  AccelNoiseAdapter a(kRnom, kWindow_s, kRate);
  std::mt19937 rng(2);
  std::normal_distribution<double> loud(0.0, 3.0 * std::sqrt(kRnom));
  const std::vector<double> R = feed(a, 4000, [&](int) { return loud(rng); }, rng);
  // Covariance matching: var = R_true, so R = R_nom + (9 R_nom - R_nom) = 9 R_nom.
  EXPECT_NEAR(median({R.begin() + 1000, R.end()}) / kRnom, 9.0, 0.9);
}

class AccelNoiseVibration : public ::testing::TestWithParam<double> {};

TEST_P(AccelNoiseVibration, VibrationAboveTenHertzIsNoise) {
  // A frame burst (25 Hz) or a rotor line aliased to 125 Hz (at 400 Hz), amplitude 4 m/s^2
  // (variance 8), on the nominal noise: R follows the total, R_nom + 8, within the first-order
  // high-pass's ripple (it passes 95 % of 25 Hz and 107 % of 125 Hz as of white noise).
  AccelNoiseAdapter a(kRnom, kWindow_s, kRate);
  std::mt19937 rng(3);
  std::normal_distribution<double> white(0.0, std::sqrt(kRnom));
  const double w = 2.0 * M_PI * GetParam() / kRate;
  const std::vector<double> R = feed(a, 4000, [&](int k) { return 4.0 * std::sin(w * k) + white(rng); }, rng);
  EXPECT_NEAR(median({R.begin() + 1000, R.end()}) / kRnom, (kRnom + 8.0) / kRnom, 0.35);
}

INSTANTIATE_TEST_SUITE_P(Lines, AccelNoiseVibration, ::testing::Values(25.0, 125.0));

TEST(AccelNoise, AForceBeingCaughtUpWithIsNotNoise) {
  // A touchdown: the innovation jumps by 12 m/s^2 and decays over 25 samples while the force
  // state catches up, on the nominal white noise. Its variance about the window mean exceeds
  // the 2x threshold (a variance test would call it vibration and stop listening to the
  // accelerometer just when the force changes), its successive differences do not.
  std::mt19937 rng(4);
  std::normal_distribution<double> white(0.0, std::sqrt(kRnom));
  auto r_x = [&](int k) { return (k >= 2000 ? 12.0 * std::exp(-(k - 2000) / 25.0) : 0.0) + white(rng); };
  double mean = 0.0, sq = 0.0;  // the transient's own contribution over one window
  for (int k = 0; k < static_cast<int>(kWindow); ++k) {
    const double t = 12.0 * std::exp(-k / 25.0);
    mean += t / kWindow;
    sq += t * t / kWindow;
  }
  ASSERT_GT(sq - mean * mean + kRnom, 2.0 * kRnom) << "the case would not fool a variance test";
  AccelNoiseAdapter a(kRnom, kWindow_s, kRate);
  const std::vector<double> R = feed(a, 3000, r_x, rng);
  EXPECT_LT(*std::max_element(R.begin() + 2000, R.end()), 1.5 * kRnom);
}

TEST(AccelNoise, OffKeepsTheNominalNoise) {
  AccelNoiseAdapter a(kRnom, 0.0, kRate);
  std::mt19937 rng(5);
  std::normal_distribution<double> loud(0.0, 5.0 * std::sqrt(kRnom));
  const std::vector<double> R = feed(a, 1000, [&](int) { return loud(rng); }, rng);
  EXPECT_EQ(*std::max_element(R.begin(), R.end()), kRnom);
  EXPECT_EQ(a.inflated_samples(), 0);
}

}  // namespace
}  // namespace vid
