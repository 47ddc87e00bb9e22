// The gyro fit behind the time-offset clone Jacobian (rate_fit.h): exact on a quadratic,
// noise down by the expected factor, centre-weighted at a one-sided window, refuses too few samples;
// the adaptive window keeps the longest window on a smooth rate and shortens near an impact.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "types/median.h"
#include "vio_core/rate_fit.h"

namespace {
using namespace vid;
using Eigen::Vector3d;

constexpr TimeNs kDt = 2'500'000;   // 400 Hz
constexpr TimeNs kH = 250'000'000;  // +-0.25 s

Vector3d truth(double t) { return Vector3d(0.3 + 0.2 * t - 0.5 * t * t, -1.0 + 2.0 * t, 0.1 * t * t); }

// One fixed window: the adaptive fit with its shortest window equal to its longest.
std::optional<Vector3d> fit_rate(const std::vector<GyroSample>& data, TimeNs t, TimeNs h) {
  const auto r = fit_rate_adaptive(data, t, h, h);
  if (!r) return std::nullopt;
  return r->rate_I;
}

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

// An impact's gyro swing (impacts preset: -3.7 rad/s and back within ~0.25 s) starting at t_hit.
double swing(double t, double t_hit) {
  const double s = t - t_hit;
  return s <= 0.0 || s >= 0.25 ? 0.0 : -3.7 * std::sin(M_PI * s / 0.125) * std::exp(-8.0 * s);
}

std::vector<GyroSample> impact_samples(double t_hit, double sigma, unsigned seed) {
  std::vector<GyroSample> out = samples(0, 2'000'000'000, sigma, seed);
  for (GyroSample& s : out) s.gyro_I.y() += swing(s.t_ns * 1e-9, t_hit);
  return out;
}

constexpr TimeNs kMaxH = 400'000'000;
constexpr TimeNs kMinH = 25'000'000;

TEST(RateFit, AdaptiveKeepsTheLongWindowOnASmoothRate) {
  int kept = 0;
  for (unsigned r = 0; r < 50; ++r) {
    const auto w = fit_rate_adaptive(samples(0, 2'000'000'000, 0.02, 300 + r), 1'000'000'000, kMaxH, kMinH);
    ASSERT_TRUE(w.has_value());
    EXPECT_TRUE(w->passed);
    kept += w->half_window_ns == kMaxH;
  }
  EXPECT_GE(kept, 49);  // the residual ratio of a pure-noise window is 1 +- 0.08 < 1.5
}

TEST(RateFit, AdaptiveFollowsAnImpactTheFixedWindowMisses) {
  // An impact 0.15 s after the clone: the +-0.4 s quadratic bends towards it, the adaptive fit
  // shrinks the window until the impact is outside it.
  const TimeNs t = 1'000'000'000;
  double fixed2 = 0.0, adaptive2 = 0.0;
  const int runs = 50;
  int passed = 0;
  for (unsigned r = 0; r < runs; ++r) {
    const auto data = impact_samples(1.15, 0.02, 500 + r);
    const auto fixed = fit_rate(data, t, kMaxH);
    const auto adaptive = fit_rate_adaptive(data, t, kMaxH, kMinH);
    ASSERT_TRUE(fixed && adaptive);
    EXPECT_LT(adaptive->half_window_ns, 150'000'000);
    passed += adaptive->passed;
    fixed2 += (*fixed - truth(1.0)).squaredNorm();
    adaptive2 += (adaptive->rate_I - truth(1.0)).squaredNorm();
  }
  const double fixed_rms = std::sqrt(fixed2 / runs), adaptive_rms = std::sqrt(adaptive2 / runs);
  EXPECT_GE(passed, 45);  // a short noise-only window fails the ratio test now and then
  EXPECT_GT(fixed_rms, 0.1);        // rad/s: the error that put t_d 5 ms off
  EXPECT_LT(adaptive_rms, 0.015);   // the +-0.1 s window's noise: 0.02 * sqrt(9/(4*81)) = 0.0033 per axis
}

TEST(RateFit, AdaptiveMeasuresTheNoiseInsteadOfAssumingIt) {
  // Ten times the noise (a vibrating airframe): still the long window on a smooth rate.
  const auto w = fit_rate_adaptive(samples(0, 2'000'000'000, 0.2, 7), 1'000'000'000, kMaxH, kMinH);
  ASSERT_TRUE(w.has_value());
  EXPECT_EQ(w->half_window_ns, kMaxH);
  EXPECT_FALSE(fit_rate_adaptive(samples(0, 2'000'000'000, 0.0, 1), 5'000'000'000, kMaxH, kMinH).has_value());
}

TEST(UpperMedian, MiddleElementOfOddAndUpperOfEvenCounts) {
  std::vector<int> odd{9, 1, 5, 3, 7};
  EXPECT_EQ(upper_median(odd), 5);
  std::vector<double> even{4.0, 1.0, 3.0, 2.0};
  EXPECT_EQ(upper_median(even), 3.0);
  std::vector<long> one{42};
  EXPECT_EQ(upper_median(one), 42);
}

}  // namespace
