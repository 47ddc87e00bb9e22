/// @file test_model_jacobians.cpp
/// @brief Seed eq. 47: analytic on-manifold Jacobians against central differences, the
/// discrete map against RK4, and the SWLS dynamic residual / manifold against the model.
#include <gtest/gtest.h>

#include <random>

#include "geometry/so3.h"
#include "massid/filters/quadrotor_mass_model.h"
#include "massid/filters/swls_residuals.h"

namespace vid::massid {
namespace {

using Model = QuadrotorMassModel;

Model::State random_state(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Model::State x;
  x.q_WI = so3::quat_exp(Eigen::Vector3d(u(rng), u(rng), u(rng)));
  x.p_WI = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 3.0;
  x.v_WI = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 2.0;
  x.mass_kg = 1.5 + 0.5 * u(rng);
  return x;
}

double rel_err(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / std::max(1.0, b.norm());
}

TEST(QuadMassModel, StateJacobianMatchesNumeric) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Model model(9.81);
  for (int trial = 0; trial < 20; ++trial) {
    const Model::State x = random_state(rng);
    const Model::Input in{15.0 + 5.0 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)) * 3.0};
    const double dt = trial % 2 ? 0.01 : 0.2;  // also a large step (rotation within the step)
    const Model::StateMat F = model.state_jacobian(x, in, dt);
    Model::StateMat Fn;
    const double h = 1e-6;
    const Model::State fx = model.propagate(x, in, dt);
    for (int j = 0; j < 10; ++j) {
      Model::StateVec d = Model::StateVec::Zero();
      d(j) = h;
      Fn.col(j) = (Model::boxminus(model.propagate(Model::boxplus(x, d), in, dt), fx) -
                   Model::boxminus(model.propagate(Model::boxplus(x, -d), in, dt), fx)) /
                  (2 * h);
    }
    EXPECT_LT(rel_err(F, Fn), 1e-6) << "trial " << trial << "\n" << F - Fn;
  }
}

TEST(QuadMassModel, MeasurementJacobianMatchesNumeric) {
  std::mt19937_64 rng(4);
  const Model model;
  const Model::State x = random_state(rng);
  const Model::MeasJac H = model.measurement_jacobian(x);
  Model::MeasJac Hn;
  const double h = 1e-6;
  for (int j = 0; j < 10; ++j) {
    Model::StateVec d = Model::StateVec::Zero();
    d(j) = h;
    Hn.col(j) = (Model::meas_boxminus(model.measure(Model::boxplus(x, d)), model.measure(x)) -
                 Model::meas_boxminus(model.measure(Model::boxplus(x, -d)), model.measure(x))) /
                (2 * h);
  }
  EXPECT_LT(rel_err(H, Hn), 1e-6);
}

TEST(QuadMassModel, Gamma2MatchesSeries) {
  for (double s : {1e-6, 1e-3, 0.3, 2.0}) {
    const Eigen::Vector3d phi = s * Eigen::Vector3d(0.3, -0.5, 0.8);
    const Eigen::Matrix3d W = so3::skew(phi);
    Eigen::Matrix3d series = Eigen::Matrix3d::Zero(), term = Eigen::Matrix3d::Identity();
    double fact = 2.0;  // (n + 2)!
    for (int n = 0; n < 30; ++n) {
      series += term / fact;
      term = term * W;
      fact *= (n + 3);
    }
    EXPECT_LT((so3_gamma2(phi) - series).norm(), 1e-12) << "scale " << s;
  }
}

TEST(QuadMassModel, DiscreteMapMatchesFineIntegration) {
  // Held input: Euler with 20000 sub-steps converges to the exact solution.
  const Model model(9.81);
  std::mt19937_64 rng(5);
  const Model::State x = random_state(rng);
  const Model::Input in{20.0, Eigen::Vector3d(1.0, -2.0, 0.5)};
  const double dt = 0.1;
  const Model::State y = model.propagate(x, in, dt);
  Model::State z = x;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const double h = dt / n;
    const Eigen::Matrix3d R = z.q_WI.toRotationMatrix();
    const Eigen::Vector3d a = R * Eigen::Vector3d(0, 0, in.thrust_N / z.mass_kg) + model.g_W();
    z.p_WI += z.v_WI * h + 0.5 * a * h * h;
    z.v_WI += a * h;
    z.q_WI = so3::boxplus(z.q_WI, in.w_I * h);
  }
  EXPECT_LT(Model::boxminus(y, z).norm(), 1e-4);
  EXPECT_LT(so3::boxminus(y.q_WI, z.q_WI).norm(), 1e-9);
}

TEST(SwlsResiduals, DynamicResidualVanishesOnModelPropagation) {
  const Model model(9.81);
  std::mt19937_64 rng(6);
  const Model::State x0 = random_state(rng);
  SwlsPreintegration pre;
  Model::State x = x0;
  // Three held inputs pre-integrated into one factor.
  for (int k = 0; k < 3; ++k) {
    const Model::Input in{18.0 + k, Eigen::Vector3d(0.5 * k, -1.0, 0.3)};
    pre.add(in, 0.02, 1e-4, 1e-4, 1e-2, 1e-4, x0.mass_kg);
    x = model.propagate(x, in, 0.02);
  }
  const SwlsDynamicResidual res(pre, 9.81);
  double a0[kSwlsAmbient], a1[kSwlsAmbient], r[10];
  swls_pack(x0, a0);
  swls_pack(x, a1);
  res(a0, a1, r);
  EXPECT_LT((Eigen::Map<Eigen::Matrix<double, 10, 1>>(r).norm()), 1e-9);
  // A wrong end mass shows up in r_m, a wrong start mass in r_p / r_v.
  x.mass_kg += 0.1;
  swls_pack(x, a1);
  res(a0, a1, r);
  EXPECT_GT(std::abs(r[9]), 1.0);
}

TEST(SwlsResiduals, QuaternionLogMatchesSo3) {
  for (double s : {0.0, 1e-9, 1e-4, 0.5, 3.0}) {
    const Eigen::Vector3d phi = s * Eigen::Vector3d(0.6, 0.0, -0.8);
    const Eigen::Quaterniond q = so3::quat_exp(phi);
    EXPECT_LT((quat_log_t<double>(q) - phi).norm(), 1e-12) << s;
    Eigen::Quaterniond qn = q;
    qn.coeffs() = -qn.coeffs();
    EXPECT_LT((quat_log_t<double>(qn) - phi).norm(), 1e-12) << s;
  }
}

}  // namespace
}  // namespace vid::massid
