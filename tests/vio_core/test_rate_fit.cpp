// The gyro fit behind the time-offset clone Jacobian (rate_fit.h): exact on a quadratic,
// noise down by the expected factor, centre-weighted at a one-sided window, refuses too few samples.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "vio_core/rate_fit.h"

namespace {
using namespace vid;
using Eigen::Vector3d;

constexpr TimeNs kDt = 2'500'000;   // 400 Hz
constexpr TimeNs kH = 250'000'000;  // +-0.25 s

Vector3d truth(double t) { return Vector3d(0.3 + 0.2 * t - 0.5 * t * t, -1.0 + 2.0 * t, 0.1 * t * t); }

std::vector<GyroSample> samples(TimeNs t0, TimeNs t1, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd(0.0, sigma);
  std::vector<GyroSample> out;
  for (TimeNs t = t0; t <= t1; t += kDt) out.push_back({t, truth(t * 1e-9) + Vector3d(nd(rng), nd(rng), nd(rng))});
  return out;
}

TEST(RateFit, ExactOnAQuadratic) {
  const TimeNs t = 1'001'000'000;  // between samples
  const auto w = fit_rate(samples(0, 2'000'000'000, 0.0, 1), t, kH);
  ASSERT_TRUE(w.has_value());
  EXPECT_LT((*w - truth(t * 1e-9)).norm(), 1e-10);
  // the end of a stream: only the past half of the window
  const auto end = fit_rate(samples(0, t, 0.0, 1), t, kH);
  ASSERT_TRUE(end.has_value());
  EXPECT_LT((*end - truth(t * 1e-9)).norm(), 1e-10);
}

TEST(RateFit, NoiseFallsAsTheWindowPredicts) {
  // A quadratic fit evaluated at the centre of N uniform samples: variance 9/(4N) sigma^2
  // (the centre's leverage). 201 samples of 0.02 rad/s: 0.0021 rad/s.
  const double sigma = 0.02;
  const TimeNs t = 1'000'000'000;
  double sum2 = 0.0;
  const int runs = 400;
  for (int r = 0; r < runs; ++r) {
    const auto w = fit_rate(samples(0, 2'000'000'000, sigma, 100 + r), t, kH);
    ASSERT_TRUE(w.has_value());
    sum2 += (*w - truth(1.0)).squaredNorm() / 3.0;
  }
  const double predicted = sigma * std::sqrt(9.0 / (4.0 * 201));
  EXPECT_NEAR(std::sqrt(sum2 / runs), predicted, 0.1 * predicted);
}

TEST(RateFit, TooFewSamplesFallBack) {
  const TimeNs t = 1'000'000'000;
  EXPECT_FALSE(fit_rate(samples(t - 3 * kDt, t + 3 * kDt, 0.0, 1), t, kH).has_value());  // 7 samples
  EXPECT_FALSE(fit_rate(samples(0, 500'000'000, 0.0, 1), t, kH).has_value());              // none in the window
  EXPECT_FALSE(fit_rate({}, t, kH).has_value());
}

}  // namespace
