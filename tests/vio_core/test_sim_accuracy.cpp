// Accuracy on simulator feature-level sequences (vid17_like / vid18_like, full length, seed 1),
// dynamics mode: ATE (position + yaw alignment) <= 0.03 m and world force RMSE <= 0.05 m/s^2;
// imu-mode ATE on the same data is reported beside it.
//
// Force RMSE is short of its target: measured 0.130 / 0.206 m/s^2 (target 0.05) with the
// default world-frame force + force-rate model (the seed's body-frame random walk: 0.32 /
// 0.34). What is left (vio_core_diag_sim, vid17_like):
//  * roll/pitch: vision sees R_WI T_m + F_W and the accelerometer F_I + b_a, so {tilt, b_a,
//    F_ext} is only separated by yaw turns; the filter's own roll sigma stays 5-9 mrad, and
//    g * 7 mrad ~ 0.07 m/s^2 of force error in y (b_a_y off by the same amount). With noise
//    off, the tilt error is < 0.1 mrad, so this is the noise floor, not a model error;
//  * tracking: with the tilt error removed (b_a known), 0.107 m/s^2 remains. An idealized
//    1-D Kalman bound with perfect thrust, 1-2 mm position and this accelerometer noise gives
//    0.09-0.11 on the same force signal (rope, dF/dt up to 6 m/s^3).
// Reaching 0.05 needs less sensor noise than the VID-like presets simulate.
// So every figure is a ratchet at today's value (docs/testing.md) and the force target a check
// that it is still missed (the C++ strict xfail: it fails once the target is met).
#include <gtest/gtest.h>

#include <cstdio>
#include <map>

#include "ratchet.h"
#include "sim_system.h"

namespace {
using namespace vid;
using namespace vid::test;

struct Both {
  SimMetrics dyn, imu;
};

const Both& metrics(const std::string& preset) {
  static std::map<std::string, Both> cache;
  auto it = cache.find(preset);
  if (it != cache.end()) return it->second;
  const auto folder = ensure_sim_dataset(preset, 1);
  Both b{run_on_dataset(folder, PropagationMode::kDynamics), run_on_dataset(folder, PropagationMode::kImu)};
  std::printf("%s dynamics: force RMSE (W) %.4f m/s^2, ATE posyaw %.4f m, %ld visual updates, "
              "%ld features, %.3f ms/frame (%s)\n",
              preset.c_str(), b.dyn.force_rmse_W, b.dyn.ate_posyaw_m, b.dyn.visual_updates,
              b.dyn.features_used, b.dyn.mean_frame_ms, b.dyn.status.c_str());
  std::printf("  frames %ld, features rejected %ld, obs without norm %ld, accel rejected %ld\n",
              b.dyn.frames, b.dyn.features_rejected, b.dyn.obs_without_norm, b.dyn.accel_rejected);
  std::printf("%s imu: ATE posyaw %.4f m (%s)\n", preset.c_str(), b.imu.ate_posyaw_m, b.imu.status.c_str());
  return cache.emplace(preset, b).first->second;
}

// Measured on the full feature-level presets, seeds 1-3 (seed 1 is the test's), 182d56e, with
// vio_core_diag_sim (dynamics / imu) on vid_sim --features-only folders:
struct Measured {
  double force_rmse, ate_dyn, ate_imu;  // seed 1
  double force_limit, ate_dyn_limit, ate_imu_limit;  // min(1.2 x seed 1, mean + 3 sd over seeds 1-3)
};
const Measured& measured(const std::string& preset) {
  //   vid17_like force RMSE 0.1284 / 0.1005 / 0.1180 m/s^2 (sd 0.014; 1.2 x = 0.154 < mean + 3 sd 0.158),
  //              ATE dynamics 0.0117 / 0.0161 / 0.0106 m (1.2 x = 0.0140), imu 0.0111 / 0.0163 / 0.0112 (0.0133);
  //   vid18_like force RMSE 0.2062 / 0.2156 / 0.1886 m/s^2 (sd 0.014; mean + 3 sd = 0.245 < 1.2 x 0.247),
  //              ATE dynamics 0.0208 / 0.0154 / 0.0203 m (1.2 x = 0.0250), imu 0.0196 / 0.0170 / 0.0220 (0.0235).
  static const std::map<std::string, Measured> m = {
      {"vid17_like", {0.1284, 0.0117, 0.0111, 0.154, 0.0140, 0.0133}},
      {"vid18_like", {0.2062, 0.0208, 0.0196, 0.245, 0.0250, 0.0235}},
  };
  return m.at(preset);
}

void check_ate(const std::string& preset) {
  const Both& b = metrics(preset);
  const Measured& w = measured(preset);
  EXPECT_EQ(b.dyn.status, "ok");
  EXPECT_EQ(b.imu.status, "ok");
  EXPECT_LE(b.dyn.ate_posyaw_m, 0.03);  // the target (met)
  expect_ratchet((preset + " dynamics ATE [m]").c_str(), b.dyn.ate_posyaw_m, w.ate_dyn_limit, w.ate_dyn);
  expect_ratchet((preset + " imu ATE [m]").c_str(), b.imu.ate_posyaw_m, w.ate_imu_limit, w.ate_imu);
}

void check_force(const std::string& preset) {
  const Both& b = metrics(preset);
  const Measured& w = measured(preset);
  ASSERT_EQ(b.dyn.status, "ok");
  expect_ratchet((preset + " force RMSE (W) [m/s^2]").c_str(), b.dyn.force_rmse_W, w.force_limit, w.force_rmse);
}

void check_force_target(const std::string& preset) {
  const Both& b = metrics(preset);
  ASSERT_EQ(b.dyn.status, "ok");
  expect_target_not_met((preset + " force RMSE (W) [m/s^2]").c_str(), b.dyn.force_rmse_W, 0.05);
}

TEST(SimAccuracy, Vid17LikeAte) { check_ate("vid17_like"); }
TEST(SimAccuracy, Vid18LikeAte) { check_ate("vid18_like"); }
TEST(SimAccuracy, Vid17LikeForceRmseRatchet) { check_force("vid17_like"); }
TEST(SimAccuracy, Vid18LikeForceRmseRatchet) { check_force("vid18_like"); }
TEST(SimAccuracy, Vid17LikeForceRmseTargetNotMet) { check_force_target("vid17_like"); }
TEST(SimAccuracy, Vid18LikeForceRmseTargetNotMet) { check_force_target("vid18_like"); }

// Noise-free vid17_like (every sensor exact, 20 s): the filter with tiny noise densities
// reproduces the truth. Measured (182d56e): force error after 5 s 3.4e-4 m/s^2, position 8.6e-7 m,
// orientation 2.7e-5 rad; the bounds sit 3-12x above (near the floor: position and orientation
// were bounded at 1e-3, where a 1000x / 40x loss of exactness would have passed).
TEST(SimAccuracy, NoiseFreeVid17LikeIsExact) {
  const auto folder = ensure_sim_dataset("vid17_like", 1, 20.0, true);
  const SimMetrics m = run_on_dataset(folder, PropagationMode::kDynamics, true);
  std::printf("noise-free vid17_like: force error max (after 5 s) %.2e m/s^2, position %.2e m, "
              "orientation %.2e rad\n", m.force_err_max_after5_W, m.pos_err_max_m, m.theta_err_max_rad);
  EXPECT_EQ(m.status, "ok");
  EXPECT_LT(m.force_err_max_after5_W, 1e-3);
  EXPECT_LT(m.pos_err_max_m, 1e-5);
  EXPECT_LT(m.theta_err_max_rad, 1e-4);
}

}  // namespace
