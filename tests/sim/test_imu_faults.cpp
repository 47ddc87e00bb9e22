/// @file test_imu_faults.cpp
/// @brief Real-sensor effects on the IMU (`sensor_faults:`): rotor-harmonic lines and
/// broadband vibration in the spectrum, bursts, IMU rate and stamp jitter, thrust-axis tilt.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <numeric>

#include "sim/sensor_faults.h"
#include "sim_test_util.h"

namespace vid::sim {
namespace {

using test::hover_scenario;
using test::record;

/// @brief Hann-windowed one-sided power spectral density of @p x at bin k (density scaling:
/// summed over the bins of a line times fs / N it gives the line's variance).
class Spectrum {
 public:
  Spectrum(std::vector<double> x, double fs) : x_(std::move(x)), fs_(fs), w_(x_.size()) {
    const double mean = std::accumulate(x_.begin(), x_.end(), 0.0) / static_cast<double>(x_.size());
    const double n = static_cast<double>(x_.size());
    for (std::size_t i = 0; i < x_.size(); ++i) {
      w_[i] = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * static_cast<double>(i) / n);
      x_[i] = (x_[i] - mean) * w_[i];
      w2_ += w_[i] * w_[i];
    }
  }
  double df() const { return fs_ / static_cast<double>(x_.size()); }
  double psd(int k) const {  // Goertzel-free direct DFT of one bin
    std::complex<double> s = 0.0;
    const double a = -2.0 * std::numbers::pi * k / static_cast<double>(x_.size());
    for (std::size_t i = 0; i < x_.size(); ++i) s += x_[i] * std::polar(1.0, a * static_cast<double>(i));
    return 2.0 * std::norm(s) / (fs_ * w2_);
  }
  /// @brief Variance in [lo, hi] Hz.
  double band_variance(double lo, double hi) const {
    double v = 0.0;
    for (int k = static_cast<int>(std::ceil(lo / df())); k * df() <= hi; ++k) v += psd(k) * df();
    return v;
  }
  /// @brief Mean one-sided density in [lo, hi] Hz.
  double band_density(double lo, double hi) const { return band_variance(lo, hi) / (hi - lo); }

 private:
  std::vector<double> x_;
  double fs_;
  std::vector<double> w_;
  double w2_ = 0.0;
};

std::vector<double> channel(const test::Recording& rec, bool gyro, int axis) {
  std::vector<double> v;
  for (const ImuSample& s : rec.imu) v.push_back(gyro ? s.gyro_I[axis] : s.accel_I[axis]);
  return v;
}

const char* kVibration = R"(
sensor_faults:
  vibration:
    blades: 2
    accel_rotor_amplitude: [0.1, 0.15, 0.3]
    accel_blade_amplitude: [0.05, 0.08, 0.2]
    gyro_rotor_amplitude: [0.01, 0.005, 0.004]
    gyro_blade_amplitude: [0.004, 0.002, 0.006]
    accel_noise_density: 0.005
    gyro_noise_density: 0.0005
)";

TEST(ImuFaults, VibrationLinesAtRotorAndBladePassAndBroadbandLevel) {
  const Scenario sc = hover_scenario(kVibration, 20.0);
  const test::Recording rec = record(sc);
  ASSERT_EQ(rec.imu.size(), 8001u);
  // Rotor frequencies and amplitude scales from the true speeds (steady hover).
  double k_sum = 0.0;
  for (const auto& r : sc.vehicle.rotors) k_sum += r.thrust_coeff;
  const double n_ref = std::sqrt(sc.vehicle.mass_kg * sc.vehicle.gravity / k_sum);
  const Eigen::VectorXd n = rec.truth.back().state.rotor_speeds;
  double f_lo = 1e9, f_hi = 0.0, s2_sum = 0.0, s_mean = 0.0;
  for (Eigen::Index r = 0; r < n.size(); ++r) {
    f_lo = std::min(f_lo, n[r] / 60.0);
    f_hi = std::max(f_hi, n[r] / 60.0);
    const double s = std::pow(n[r] / n_ref, 2.0);
    s2_sum += s * s;
    s_mean += s / static_cast<double>(n.size());
  }
  ASSERT_GT(f_lo, 80.0);
  ASSERT_LT(2.0 * f_hi, 195.0);  // blade pass below Nyquist (200 Hz)
  const VibrationConfig& v = sc.faults.vibration;
  for (int gyro = 0; gyro < 2; ++gyro) {
    for (int axis = 0; axis < 3; ++axis) {
      const Spectrum S(channel(rec, gyro, axis), 400.0);
      const double A1 = gyro ? v.gyro_rotor_amplitude[axis] : v.accel_rotor_amplitude[axis];
      const double A2 = gyro ? v.gyro_blade_amplitude[axis] : v.accel_blade_amplitude[axis];
      const double density = (gyro ? v.gyro_noise_density : v.accel_noise_density) * s_mean;
      // Broadband between the lines (the hover motion is below 20 Hz): one-sided = 2 density^2.
      const double measured_density = std::sqrt(S.band_density(20.0, 70.0) / 2.0);
      EXPECT_NEAR(measured_density, density, 0.08 * density) << "gyro " << gyro << " axis " << axis;
      // Lines: the rotors' sines (random phases, distinct frequencies) add in power.
      for (int h = 1; h <= 2; ++h) {
        const double lo = h * f_lo - 1.5, hi = h * f_hi + 1.5;
        const double A = h == 1 ? A1 : A2;
        const double expected = s2_sum * A * A / 2.0 + 2.0 * density * density * (hi - lo);
        EXPECT_NEAR(S.band_variance(lo, hi), expected, 0.12 * expected)
            << "gyro " << gyro << " axis " << axis << " harmonic " << h;
        // Next to the line only the floor: the line sits where the rotors put it.
        const double floor = S.band_density(h * f_hi + 4.0, h * f_hi + 12.0);
        EXPECT_NEAR(floor, 2.0 * density * density, 0.25 * 2.0 * density * density)
            << "gyro " << gyro << " axis " << axis << " harmonic " << h;
      }
    }
  }
}

TEST(ImuFaults, VibrationGrowsWithTheSquareOfRotorSpeed) {
  VibrationConfig c;
  c.enabled = true;
  c.accel_rotor_amplitude = Eigen::Vector3d(0.0, 0.0, 1.0);
  const double fs = 1000.0;
  double rms[2];
  for (int i = 0; i < 2; ++i) {
    VibrationModel model(c, "rpm", 6000.0, fs, 1, 5);
    const Eigen::VectorXd n = Eigen::VectorXd::Constant(1, i == 0 ? 6000.0 : 7200.0);
    double sum = 0.0;
    for (int k = 0; k < 10000; ++k) {
      ImuSample s;
      model.apply(k / fs, n, &s);
      sum += s.accel_I.z() * s.accel_I.z();
    }
    rms[i] = std::sqrt(sum / 10000.0);
  }
  EXPECT_NEAR(rms[0], 1.0 / std::sqrt(2.0), 1e-3);  // amplitude 1 at the reference speed
  EXPECT_NEAR(rms[1] / rms[0], 1.2 * 1.2, 2e-3);
}

TEST(ImuFaults, BurstIsBandLimitedAndConfinedToItsWindow) {
  VibrationConfig c;
  c.enabled = true;
  c.bursts.push_back({2.0, 3.0, 0.5, 0.02, 10.0, 40.0});
  const double fs = 400.0;
  VibrationModel model(c, "rpm", 5000.0, fs, 4, 9);
  const Eigen::VectorXd n = Eigen::VectorXd::Constant(4, 5000.0);
  std::vector<double> ax, flat_gz;
  double outside = 0.0, flat_sum = 0.0;
  int flat_n = 0;
  for (int k = 0; k < 8 * 400; ++k) {
    const double t = k / fs;
    ImuSample s;
    model.apply(t, n, &s);
    ax.push_back(s.accel_I.x());
    if (t < 2.0 || t > 5.0) outside = std::max(outside, s.accel_I.norm() + s.gyro_I.norm());
    if (t > 2.6 && t < 4.4) {  // flat part (ramps are a fifth of the window)
      flat_sum += s.accel_I.x() * s.accel_I.x();
      ++flat_n;
      flat_gz.push_back(s.gyro_I.z());
    }
  }
  EXPECT_EQ(outside, 0.0);
  EXPECT_NEAR(std::sqrt(flat_sum / flat_n), 0.5, 0.1);  // 12 random tones: rms within 20 %
  const Spectrum S(ax, fs);
  const double total = S.band_variance(0.5, 199.0);
  EXPECT_GT(S.band_variance(9.0, 41.0) / total, 0.97) << "burst energy must sit in its 10-40 Hz band";
  double g2 = 0.0;
  for (double g : flat_gz) g2 += g * g;
  EXPECT_NEAR(std::sqrt(g2 / flat_gz.size()), 0.02, 0.005);
}

class ImuRate : public ::testing::TestWithParam<double> {};

TEST_P(ImuRate, RateAndStampJitterStatistics) {
  const double rate = GetParam();
  const double sigma = rate > 500.0 ? 1e-4 : 1e-3, bound = 3.0 * sigma;
  const Scenario sc = hover_scenario("sensor_faults: {imu_timestamps: {jitter_s: " + std::to_string(sigma) +
                                         ", max_jitter_s: " + std::to_string(bound) + "}}\n",
                                     20.0, rate);
  const test::Recording rec = record(sc);
  ASSERT_EQ(rec.imu.size(), static_cast<std::size_t>(20.0 * rate) + 1);
  double sum = 0.0, sum2 = 0.0, worst = 0.0;
  TimeNs min_gap = INT64_MAX, max_gap = 0;
  for (std::size_t k = 0; k < rec.imu.size(); ++k) {
    const TimeNs t_true = sc.start_time_ns + std::llround(static_cast<double>(k) * 1e9 / rate);
    const double e = static_cast<double>(rec.imu[k].t_ns - t_true) * 1e-9;
    sum += e;
    sum2 += e * e;
    worst = std::max(worst, std::abs(e));
    if (k > 0) {
      min_gap = std::min(min_gap, rec.imu[k].t_ns - rec.imu[k - 1].t_ns);
      max_gap = std::max(max_gap, rec.imu[k].t_ns - rec.imu[k - 1].t_ns);
    }
  }
  const double n = static_cast<double>(rec.imu.size());
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 4.0 * sigma / std::sqrt(n) + 1e-9);
  EXPECT_NEAR(sd, sigma, 0.05 * sigma);
  EXPECT_LE(worst, bound + 1e-9);
  EXPECT_GT(worst, 2.5 * sigma);  // the tails reach toward the bound
  EXPECT_GT(min_gap, 0) << "stamps must increase";
  const double period = 1.0 / rate;
  EXPECT_GT(static_cast<double>(max_gap) * 1e-9, period + 2.0 * sigma);
  // Without noise the stamps are the true sample times.
  Scenario quiet = sc;
  quiet.noise = false;
  const test::Recording q = record(quiet);
  for (std::size_t k = 0; k < q.imu.size(); k += 97)
    ASSERT_EQ(q.imu[k].t_ns, sc.start_time_ns + std::llround(static_cast<double>(k) * 1e9 / rate));
}

INSTANTIATE_TEST_SUITE_P(Rates, ImuRate, ::testing::Values(100.0, 400.0, 1000.0));

TEST(ImuFaults, ThrustTiltShowsAsHoverAccelerometerXY) {
  for (const double tilt_deg : {0.0, 1.0, 2.0}) {
    const double az_deg = 30.0;
    const Scenario sc = hover_scenario("noise: false\nsensor_faults: {thrust_axis: {tilt_deg: " +
                                           std::to_string(tilt_deg) + ", azimuth_deg: 30}}\n",
                                       8.0);
    const test::Recording rec = record(sc);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    int cnt = 0;
    for (const ImuSample& s : rec.imu) {
      if (static_cast<double>(s.t_ns - sc.start_time_ns) * 1e-9 < 5.0) continue;  // controller settled
      mean += s.accel_I;
      ++cnt;
    }
    mean /= cnt;
    // In hover the thrust is vertical: the accelerometer reads g along the thrust axis.
    const double a = tilt_deg * std::numbers::pi / 180.0, z = az_deg * std::numbers::pi / 180.0;
    const double g = sc.vehicle.gravity;
    EXPECT_NEAR(mean.x(), g * std::sin(a) * std::cos(z), 0.002) << tilt_deg;
    EXPECT_NEAR(mean.y(), g * std::sin(a) * std::sin(z), 0.002) << tilt_deg;
    EXPECT_NEAR(std::atan2(std::hypot(mean.x(), mean.y()), mean.z()), a, 2e-4) << tilt_deg;
  }
}

}  // namespace
}  // namespace vid::sim
