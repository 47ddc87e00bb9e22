/// @file test_vio_propagation.cpp
/// @brief One propagation model: the study's QuadrotorMassModel::propagate (docs/model.md
/// eq. (55), exact for an input held over dt: J_l and Gamma_2 in closed form) equals vio_core's
/// propagate_mean in dynamics mode with the thrust scale (eqs. (10)-(12): the same rotation,
/// Simpson's rule on the stage rotations for p and v), through the "vio" method's own mapping
/// (vio_interval, vio_state: s = m0 / m, F_ext = 0, biases 0, gyro = w held, T_m = T / m0 e3).
///
/// The two differ only by Simpson's quadrature error of int_0^1 Exp(phi tau) e3 dtau (v) and
/// int_0^1 (1 - tau) Exp(phi tau) e3 dtau (p), phi = w dt: |error| <= max|g''''| / 2880 with
/// |g''''| <= |phi|^4 (v) and |phi|^4 + 4 |phi|^3 (p). The tests hold the difference to that
/// bound, show it vanishes when w is along the thrust axis (Exp(phi) e3 = e3: both exact), and
/// that it falls as dt^5 (a model difference, e.g. a wrong mass, falls at most as dt).
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/so3.h"
#include "massid/filters/quadrotor_mass_model.h"
#include "massid/filters/vio_filter.h"

namespace vid::massid {
namespace {

struct Diff {
  double theta, p, v, m;
};

constexpr double kMassGuess = 1.2;  // m0: the study's 20 % high initial guess of m = 1 kg

QuadMassState start_state() {
  QuadMassState x;
  x.q_WI = so3::quat_exp(Eigen::Vector3d(0.3, -0.2, 0.8));  // tilted and yawed
  x.p_WI = Eigen::Vector3d(1.0, -2.0, 1.5);
  x.v_WI = Eigen::Vector3d(0.7, 1.2, -0.3);
  x.mass_kg = 1.0;
  return x;
}

Diff compare(const QuadMassInput& u, double dt) {
  const QuadrotorMassModel model(9.81);
  const QuadMassState x = start_state();
  const QuadMassState a = model.propagate(x, u, dt);
  const ImuState b = propagate_mean(vio_state(x, kMassGuess), vio_interval(u, kMassGuess, dt),
                                    PropagationMode::kDynamics, model.g_W());
  return {so3::boxminus(b.T_WI.q, a.q_WI).norm(), (b.T_WI.p - a.p_WI).norm(), (b.v_WI - a.v_WI).norm(),
          std::abs(kMassGuess / b.thrust_scale - a.mass_kg)};
}

// Round-off floor: a few ulps of the O(1-10) values involved.
constexpr double kRoundOff = 1e-14;

TEST(VioPropagation, EqualsStudyModelForRateAlongThrustAxis) {
  // Exp(phi) e3 = e3 for phi along e3: both discretizations are exact, only round-off remains.
  const QuadMassInput u{13.0, Eigen::Vector3d(0.0, 0.0, 1.7)};
  const Diff d = compare(u, 0.01);
  EXPECT_LT(d.theta, kRoundOff);
  EXPECT_LT(d.p, kRoundOff);
  EXPECT_LT(d.v, kRoundOff);
  EXPECT_LT(d.m, kRoundOff);
}

TEST(VioPropagation, EqualsStudyModelWithinSimpsonErrorAtStudyStep) {
  // The study's step (100 Hz) and a rate above the largest it commands (2.1 rad/s).
  const double dt = 0.01;
  const QuadMassInput u{14.0, Eigen::Vector3d(1.3, -1.6, 0.7)};  // |w| = 2.18 rad/s
  const double a = u.thrust_N / start_state().mass_kg;
  const double phi = u.w_I.norm() * dt;
  const double bound_v = a * dt * std::pow(phi, 4) / 2880.0;
  const double bound_p = a * dt * dt * (std::pow(phi, 4) + 4.0 * std::pow(phi, 3)) / 2880.0;
  const Diff d = compare(u, dt);
  EXPECT_LT(d.theta, kRoundOff);
  EXPECT_LT(d.m, kRoundOff);
  EXPECT_LE(d.v, bound_v + kRoundOff) << "bound " << bound_v;
  EXPECT_LE(d.p, bound_p + kRoundOff) << "bound " << bound_p;
  // The bounds themselves: far below anything a model difference would leave (a 1e-6 relative
  // mass error alone moves v by a dt 1e-6 = 1.4e-7 m/s).
  EXPECT_LT(bound_v, 2e-11);
  EXPECT_LT(bound_p, 1e-10);
}

TEST(VioPropagation, DifferenceFallsAsFifthPowerOfStep) {
  const QuadMassInput u{14.0, Eigen::Vector3d(1.2, -1.5, 0.6)};
  Diff prev = compare(u, 0.08);
  for (double dt : {0.04, 0.02}) {
    const Diff d = compare(u, dt);
    // Halving dt divides a quadrature error of order dt^5 by 32; allow the next order's share.
    EXPECT_GT(prev.v / d.v, 28.0) << "dt " << dt;
    EXPECT_LT(prev.v / d.v, 36.0) << "dt " << dt;
    EXPECT_GT(prev.p / d.p, 28.0) << "dt " << dt;
    EXPECT_LT(prev.p / d.p, 36.0) << "dt " << dt;
    prev = d;
  }
}

}  // namespace
}  // namespace vid::massid
