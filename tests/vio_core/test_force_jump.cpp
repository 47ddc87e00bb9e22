/// Force-jump detection (vio_core/force_jump.h): the GLR test against white innovations, steps
/// and spikes, and apply_force_jump's undo, re-estimate and velocity/position catch-up.
#include <gtest/gtest.h>

#include <random>

#include "geometry/so3.h"
#include "vio_core/ekf_update.h"
#include "vio_core/force_jump.h"

namespace vid {
namespace {

constexpr double kSigma = 2.0;  // per-sample accelerometer noise of the VID IMU (0.1 * sqrt(400))

AccelInnovation innovation(TimeNs t, const Eigen::Vector3d& w) {
  AccelInnovation s;
  s.t_ns = t;
  s.w = w;
  s.S = kSigma * kSigma * Eigen::Matrix3d::Identity();
  return s;
}

struct Noise {
  std::mt19937 rng;
  std::normal_distribution<double> nd{0.0, kSigma};
  explicit Noise(unsigned seed) : rng(seed) {}
  Eigen::Vector3d operator()() { return {nd(rng), nd(rng), nd(rng)}; }
};

// White innovations of a consistent filter: the threshold (chi2(3) at 30, ~1.4e-6 per test)
// keeps false alarms rare although every sample tests up to 63 correlated windows.
TEST(ForceJumpDetector, RareFalseAlarmsOnWhiteInnovations) {
  EstimatorParams p;
  ForceJumpDetector det(p);
  Noise noise(7);
  int alarms = 0;
  const int samples = 200000;  // 500 s at 400 Hz
  for (int k = 0; k < samples; ++k) {
    det.push(innovation(k * 2'500'000LL, noise()));
    if (det.test()) {
      ++alarms;
      det.clear();
    }
  }
  EXPECT_LE(alarms, 10) << "false alarms per 500 s of white innovations";
}

// A step of 3 m/s^2 (1.5 sigma per sample) is found within the longest window, mostly at an
// onset near the true one (the maximum-likelihood onset spreads with the noise), with the mean
// innovation of its window (the step, diluted by pre-step samples when the onset is early).
TEST(ForceJumpDetector, FindsAStepQuicklyWithItsSizeAndOnset) {
  EstimatorParams p;
  const Eigen::Vector3d step(3.0, 0.0, -0.5);
  int found = 0, onset_close = 0;
  double delay_sum = 0.0;
  for (unsigned seed = 1; seed <= 50; ++seed) {
    ForceJumpDetector det(p);
    Noise noise(seed);
    for (int k = 0; k < 40; ++k) det.push(innovation(k, noise()));
    for (int k = 0; k < 64; ++k) {
      det.push(innovation(40 + k, step + noise()));
      if (auto j = det.test()) {
        ++found;
        delay_sum += k + 1;
        onset_close += std::abs(j->n - (k + 1)) <= 8 ? 1 : 0;
        const Eigen::Vector3d expected = step * (std::min(j->n, k + 1) / static_cast<double>(j->n));
        EXPECT_LT((j->delta - expected).norm(), 4.0 * kSigma * std::sqrt(3.0 / j->n)) << "seed " << seed;
        break;
      }
    }
  }
  EXPECT_EQ(found, 50);
  EXPECT_GE(onset_close, 40) << "onsets within 8 samples of the truth";
  EXPECT_LT(delay_sum / found, 25.0) << "mean detection delay [samples]";  // theory: ~30 / (9.25 / 4) = 13
}

// A small step (0.5 m/s^2 against 0.15 m/s^2 noise: far past the GLR threshold) is left to the force
// random walk under the default floor force_jump_min_step = 1 m/s^2, and found without it.
TEST(ForceJumpDetector, StepsBelowTheFloorAreNotJumps) {
  for (double floor : {1.0, 0.0}) {
    EstimatorParams p;
    p.force_jump_min_step = floor;
    int found = 0;
    for (unsigned seed = 1; seed <= 20; ++seed) {
      ForceJumpDetector det(p);
      Noise noise(seed);
      // A real 100 Hz IMU's per-sample noise (0.15 m/s^2): the noise here scaled by 0.075.
      for (int k = 0; k < 64; ++k) {
        AccelInnovation s = innovation(k, Eigen::Vector3d(0.5, 0.0, 0.0) + 0.075 * noise());
        s.S *= 0.075 * 0.075;
        det.push(s);
      }
      if (det.test()) ++found;
    }
    if (floor > 0.0) {
      EXPECT_EQ(found, 0) << "floor " << floor;
    } else {
      EXPECT_EQ(found, 20) << "floor " << floor;
    }
  }
}

// One sample of 30 m/s^2 (an outlier, not a step): each half of a window must carry the step.
TEST(ForceJumpDetector, ASingleSpikeIsNotAStep) {
  EstimatorParams p;
  int detected = 0;
  for (unsigned seed = 1; seed <= 200; ++seed) {
    ForceJumpDetector det(p);
    Noise noise(seed);
    bool hit = false;
    for (int k = 0; k < 100; ++k) {
      const Eigen::Vector3d spike = k == 50 ? Eigen::Vector3d(30.0, 0.0, 0.0) : Eigen::Vector3d::Zero();
      det.push(innovation(k, spike + noise()));
      hit = hit || det.test().has_value();
    }
    detected += hit ? 1 : 0;
  }
  EXPECT_LE(detected, 10) << "of 200 spikes taken for steps";  // ~2.3 % pass the 2-sigma split test
}

// A 10-40 Hz vibration burst (1 m/s^2 rms per axis on 0.5 m/s^2 white noise, 400 Hz) whose power
// the filter knows (S carries it, as the adapted noise does): counted as white, half a cycle of
// it reads as a step; counted as the coloured excess it is (S_vib), it does not, while a 4 m/s^2
// step inside the burst is still found (docs/model.md eq. (22)).
TEST(ForceJumpDetector, VibrationIsNotAStepButAStepInVibrationIs) {
  EstimatorParams p;
  p.imu_rate_hz = 400.0;
  const double white = 0.5, vib = 1.0;
  const auto burst = [&](bool coloured, double step, unsigned seed) {
    ForceJumpDetector det(p);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uf(10.0, 40.0), ph(0.0, 2.0 * M_PI);
    std::normal_distribution<double> nd(0.0, white);
    double f[3][6], phase[3][6];  // six tones per axis, each of variance vib^2 / 6
    for (int a = 0; a < 3; ++a)
      for (int j = 0; j < 6; ++j) f[a][j] = uf(rng), phase[a][j] = ph(rng);
    int alarms = 0;
    for (int k = 0; k < 1200; ++k) {  // 3 s
      const double t = k / p.imu_rate_hz;
      Eigen::Vector3d w;
      for (int a = 0; a < 3; ++a) {
        w(a) = nd(rng) + (k >= 600 ? step : 0.0) * (a == 0 ? 1.0 : 0.0);
        for (int j = 0; j < 6; ++j) w(a) += vib * std::sqrt(2.0 / 6.0) * std::sin(2.0 * M_PI * f[a][j] * t + phase[a][j]);
      }
      AccelInnovation s;
      s.t_ns = static_cast<TimeNs>(k) * 2'500'000;
      s.w = w;
      s.S = (white * white + vib * vib) * Eigen::Matrix3d::Identity();
      if (coloured) s.S_vib = vib * vib * Eigen::Matrix3d::Identity();
      det.push(s);
      if (auto j = det.test()) {
        if (step > 0.0 && k >= 600 && k < 664) return 1000 + alarms;  // found within 160 ms
        ++alarms;
        det.clear();
      }
    }
    return alarms;
  };
  int white_alarms = 0, coloured_alarms = 0, steps_found = 0;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    white_alarms += burst(false, 0.0, seed);
    coloured_alarms += burst(true, 0.0, seed);
    const int r = burst(true, 4.0, seed);
    steps_found += r >= 1000 && r - 1000 <= 1 ? 1 : 0;  // found, after at most one false alarm
  }
  EXPECT_GT(white_alarms, 50) << "30 s of burst counted as white noise";
  EXPECT_LE(coloured_alarms, 3) << "30 s of burst counted as coloured";
  EXPECT_GE(steps_found, 9) << "of 10 steps of 4 m/s^2 inside a burst";
}

TEST(ForceJumpDetector, WindowIsBounded) {
  EstimatorParams p;
  p.force_jump_window = 8;
  ForceJumpDetector det(p);
  for (int k = 0; k < 8; ++k) EXPECT_FALSE(det.push(innovation(k, Eigen::Vector3d::Zero())).has_value());
  const auto out = det.push(innovation(8, Eigen::Vector3d::Zero()));
  ASSERT_TRUE(out.has_value());
  EXPECT_EQ(out->t_ns, 0);
  EXPECT_EQ(det.size(), 8);
}

/// Feed a constant accelerometer reading a_m (noise-free) at 400 Hz as the estimator does, until
/// the detector fires; returns the jump and its window (newest first), t = the filter time.
struct Detected {
  ForceJump jump;
  std::vector<AccelInnovation> window;
  TimeNs t = 0;
};
Detected feed_until_jump(FilterState& state, const Eigen::Vector3d& a_m, const Eigen::Vector3d& T_m) {
  EstimatorParams p;
  ForceJumpDetector det(p);
  Detected d;
  for (d.t = 2'500'000; d.t < 200'000'000; d.t += 2'500'000) {
    state.set_time(d.t);
    AccelInnovation info;
    accel_update(state, a_m, T_m, kSigma * kSigma, 0.0, &info);
    det.push(info);
    if (auto j = det.test()) {
      d.jump = *j;
      for (int i = 0; i < j->n; ++i) d.window.push_back(det.recent(i));
      return d;
    }
  }
  ADD_FAILURE() << "no detection";
  return d;
}

// A world-force filter whose force jumped by dF: feed the accelerometer as the estimator does,
// then apply the detected jump. The force reaches the new level, the window's corrections of
// attitude and bias are undone, and velocity/position catch up with the step they missed.
TEST(ApplyForceJump, ReEstimatesTheForceAndKeepsAttitudeAndBias) {
  FilterState state(true, ForceFrame::kWorld, true);
  ImuState x;
  x.T_WI.q = so3::quat_exp(Eigen::Vector3d(0.05, -0.03, 0.8));
  x.b_a = Eigen::Vector3d(0.05, -0.02, 0.03);
  x.F_ext = Eigen::Vector3d(0.5, 0.0, 0.0);
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(state.imu_dim(), state.imu_dim()) * 1e-4;
  P.block<3, 3>(imu_idx::kTheta, imu_idx::kTheta) *= 0.25;
  P.block<3, 3>(imu_idx::kBa, imu_idx::kBa) = 0.0064 * Eigen::Matrix3d::Identity();
  P.block<3, 3>(imu_idx::kF, imu_idx::kF) = 0.01 * Eigen::Matrix3d::Identity();
  state.initialize(0, x, P);
  const ImuState before = state.imu();

  const Eigen::Vector3d F_true = x.F_ext + Eigen::Vector3d(0.0, 4.0, -2.0);  // W
  const Eigen::Vector3d T_m(0.0, 0.0, 9.81);
  const double noise_var = kSigma * kSigma;
  const Detected d = feed_until_jump(state, T_m + x.T_WI.q.toRotationMatrix().transpose() * F_true + x.b_a, T_m);
  ASSERT_FALSE(d.window.empty());
  const std::vector<AccelInnovation>& window = d.window;
  const TimeNs t = d.t;
  const Eigen::Vector3d v_before = state.imu().v_WI;
  apply_force_jump(state, window, d.jump, noise_var, EstimatorParams{}.init_sigma_force_rate);
  const ImuState& after = state.imu();
  EXPECT_LT((after.F_ext - F_true).norm(), 0.05) << after.F_ext.transpose();
  EXPECT_LT((after.b_a - before.b_a).norm(), 0.01) << "bias kept";
  EXPECT_LT(so3::quat_log(before.T_WI.q.conjugate() * after.T_WI.q).norm(), 1e-3) << "attitude kept";
  // velocity: the step acted for the window's duration (plus half a sample)
  const double tau = static_cast<double>(t - window.back().t_ns) * 1e-9 + 1.25e-3;
  const Eigen::Vector3d dv_expected = tau * (F_true - before.F_ext);
  EXPECT_LT(((after.v_WI - v_before) - dv_expected).norm(), 0.2 * dv_expected.norm());
  EXPECT_GT(state.P()(imu_idx::kV, imu_idx::kV), 1e-4) << "velocity inherits the force's uncertainty";
  EXPECT_TRUE(state.check_and_symmetrize().positive_definite);
}

}  // namespace
}  // namespace vid

namespace vid {
namespace {

// Body-frame force model (the seed's eq. 58): the force and its step are in I, velocity and
// position move in W, so the catch-up is rotated by the attitude.
TEST(ApplyForceJump, BodyForceModelMovesVelocityInTheWorldFrame) {
  FilterState state(true, ForceFrame::kBody, false);
  ImuState x;
  x.T_WI.q = so3::quat_exp(Eigen::Vector3d(0.0, 0.0, 1.2));  // yawed: body x is not world x
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(state.imu_dim(), state.imu_dim()) * 1e-4;
  P.block<3, 3>(imu_idx::kF, imu_idx::kF) = 0.01 * Eigen::Matrix3d::Identity();
  state.initialize(0, x, P);
  const Eigen::Vector3d F_I(4.0, 0.0, 0.0), T_m(0.0, 0.0, 9.81);
  const Detected d = feed_until_jump(state, T_m + F_I, T_m);
  ASSERT_FALSE(d.window.empty());
  const Eigen::Vector3d v_before = state.imu().v_WI;
  apply_force_jump(state, d.window, d.jump, kSigma * kSigma, EstimatorParams{}.init_sigma_force_rate);
  EXPECT_LT((state.imu().F_ext - F_I).norm(), 0.05);
  const Eigen::Vector3d dv = state.imu().v_WI - v_before;
  const Eigen::Vector3d dir_W = x.T_WI.q * Eigen::Vector3d::UnitX();
  EXPECT_GT(dv.normalized().dot(dir_W), 0.99) << dv.transpose();
}

}  // namespace
}  // namespace vid
