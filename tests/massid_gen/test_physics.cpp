/// @file test_physics.cpp
/// @brief With noise off, the recorded run obeys docs/model.md eq. (55) with the true mass: q follows the
/// held body rate, p integrates v, and v integrates R (T/m_true) e3 + g (checked against an
/// independent Gauss-Legendre quadrature of the held-input acceleration).
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "massid/gen/run_simulator.h"

using namespace vid::massid::gen;
using vid::massid::MassIdSample;

namespace {

/// 5-point Gauss-Legendre nodes/weights on [0, 1].
const double kNodes[5] = {0.04691007703066800, 0.23076534494715845, 0.5, 0.76923465505284155,
                          0.95308992296933200};
const double kWeights[5] = {0.11846344252809454, 0.23931433524968324, 0.28444444444444444,
                            0.23931433524968324, 0.11846344252809454};

void check_run(const std::string& traj, const std::string& profile, bool mass_linear_in_interval) {
  GeneratorSettings s;
  s.sigma_q = s.sigma_p = s.sigma_v = 0.0;
  const auto sim = simulate_run(s, traj, profile, 0, run_seed(9, traj, profile, 0));
  const auto& x = sim.run.samples;
  const double dt = 1.0 / s.rate_hz;
  const Eigen::Vector3d g_W(0, 0, -s.gravity);
  double worst_v = 0, worst_p = 0, worst_q = 0, worst_fd = 0;
  for (size_t k = 0; k + 1 < x.size(); ++k) {
    const MassIdSample& a = x[k];
    const MassIdSample& b = x[k + 1];
    ASSERT_NEAR(b.t - a.t, dt, 1e-12);
    EXPECT_EQ(a.p_WI, sim.truth[k].T_WI.p);  // noise off: measured = true
    EXPECT_EQ(a.v_WI, sim.truth[k].v_WI);
    const Eigen::Matrix3d R_k = a.q_WI.toRotationMatrix();
    const double w_norm = a.w_I.norm();
    Eigen::Vector3d dv = Eigen::Vector3d::Zero(), dp = Eigen::Vector3d::Zero();
    for (int i = 0; i < 5; ++i) {
      const double s_i = kNodes[i] * dt;
      const Eigen::Matrix3d R =
          w_norm > 0 ? R_k * Eigen::AngleAxisd(w_norm * s_i, a.w_I / w_norm).toRotationMatrix() : R_k;
      const double m = mass_linear_in_interval ? a.mass_true + (b.mass_true - a.mass_true) * kNodes[i]
                                               : a.mass_true;
      const Eigen::Vector3d acc = R.col(2) * (a.thrust_cmd / m) + g_W;
      dv += kWeights[i] * dt * acc;
      dp += kWeights[i] * dt * (dt - s_i) * acc;
    }
    worst_v = std::max(worst_v, (b.v_WI - a.v_WI - dv).norm());
    worst_p = std::max(worst_p, (b.p_WI - a.p_WI - a.v_WI * dt - dp).norm());
    const Eigen::Quaterniond q_pred =
        a.q_WI * Eigen::Quaterniond(Eigen::AngleAxisd(w_norm * dt, w_norm > 0 ? Eigen::Vector3d(a.w_I / w_norm)
                                                                              : Eigen::Vector3d::UnitX()));
    worst_q = std::max(worst_q, q_pred.angularDistance(b.q_WI));
    // Away from mass steps (where the acceleration jumps by ~g * 25 %).
    const bool near_step = k > 0 && (std::abs(b.mass_true - a.mass_true) > 1e-3 ||
                                     std::abs(a.mass_true - x[k - 1].mass_true) > 1e-3);
    if (k > 0 && !near_step) {
      worst_fd = std::max(worst_fd, ((b.p_WI - x[k - 1].p_WI) / (2 * dt) - a.v_WI).norm());
    }
  }
  std::printf("%s/%s: |dv err| %.2e m/s, |dp err| %.2e m, |dq err| %.2e rad, |dp/dt - v| %.2e m/s\n",
              traj.c_str(), profile.c_str(), worst_v, worst_p, worst_q, worst_fd);
  EXPECT_LT(worst_v, 1e-9) << traj << "/" << profile;
  EXPECT_LT(worst_p, 1e-11) << traj << "/" << profile;
  EXPECT_LT(worst_q, 1e-9) << traj << "/" << profile;
  // Central difference of p vs v: truncation dt^2/6 |jerk|; measured |jerk| up to ~30 m/s^3.
  EXPECT_LT(worst_fd, 1e-3) << traj << "/" << profile;
}

}  // namespace

TEST(MassIdPhysics, StepMassRunObeysEq47) { check_run("loop", "step_drop", false); }
TEST(MassIdPhysics, UpDownMassRunObeysEq47) { check_run("zigzag", "up_down", false); }
TEST(MassIdPhysics, SprayingMassRunObeysEq47) { check_run("lemniscate", "linear_decrease", true); }
TEST(MassIdPhysics, RandomTrajectoryObeysEq47) { check_run("random", "constant", false); }

TEST(MassIdPhysics, MeasurementNoiseHasTheStatedSigmas) {
  GeneratorSettings s;
  const auto sim = simulate_run(s, "loop", "constant", 0, 77);
  EXPECT_EQ(sim.run.info.sigma_p, s.sigma_p);
  double sp = 0, sv = 0, sq = 0;
  const size_t n = sim.truth.size();
  for (size_t k = 0; k < n; ++k) {
    sp += (sim.run.samples[k].p_WI - sim.truth[k].T_WI.p).squaredNorm();
    sv += (sim.run.samples[k].v_WI - sim.truth[k].v_WI).squaredNorm();
    const Eigen::AngleAxisd d(sim.truth[k].T_WI.q.conjugate() * sim.run.samples[k].q_WI);
    sq += d.angle() * d.angle();
  }
  // Per-axis sigma from 3n draws: relative standard error ~ 1/sqrt(6n) < 1 %.
  EXPECT_NEAR(std::sqrt(sp / (3.0 * n)), s.sigma_p, 0.03 * s.sigma_p);
  EXPECT_NEAR(std::sqrt(sv / (3.0 * n)), s.sigma_v, 0.03 * s.sigma_v);
  EXPECT_NEAR(std::sqrt(sq / (3.0 * n)), s.sigma_q, 0.03 * s.sigma_q);
}
