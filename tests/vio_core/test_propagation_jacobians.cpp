// Propagation Jacobians Phi and G (imu mode; dynamics mode with body- or world-frame force,
// with and without the force-rate state) and the accelerometer measurement Jacobian against
// central numeric differentiation of the discrete maps.
#include <gtest/gtest.h>

#include "geometry/so3.h"
#include "vio_core/ekf_update.h"
#include "vio_core/propagation.h"
#include "error_state.h"

namespace {
using namespace vid;
using vid::test::perturb;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

VectorXd difference(const ImuState& a, const ImuState& b, const ImuLayout& l) {
  VectorXd d(l.dim());
  d.segment<3>(imu_idx::kTheta) = so3::boxminus(a.T_WI.q, b.T_WI.q);
  d.segment<3>(imu_idx::kP) = a.T_WI.p - b.T_WI.p;
  d.segment<3>(imu_idx::kV) = a.v_WI - b.v_WI;
  d.segment<3>(imu_idx::kBg) = a.b_g - b.b_g;
  d.segment<3>(imu_idx::kBa) = a.b_a - b.b_a;
  if (l.force) d.segment<3>(imu_idx::kF) = a.F_ext - b.F_ext;
  if (l.force_rate) d.segment<3>(imu_idx::kFdot) = a.F_dot - b.F_dot;
  if (l.thrust_scale) d(l.thrust_scale_index()) = a.thrust_scale - b.thrust_scale;
  return d;
}

// n over the noise vector of the given layout.
DiscreteNoise noise_from(const VectorXd& n, const ImuLayout& l) {
  DiscreteNoise w;
  w.n_g = n.segment<3>(noise_idx::kNg);
  w.n_a = n.segment<3>(noise_idx::kNa);
  w.w_g = n.segment<3>(noise_idx::kWg);
  w.w_a = n.segment<3>(noise_idx::kWa);
  if (l.force) w.w_F = n.segment<3>(noise_idx::kWF);
  if (l.force_rate) w.w_Fd = n.segment<3>(noise_idx::kWFd);
  if (l.thrust_scale) w.w_s = n(l.noise_dim() - 1);
  return w;
}

ImuState sample_state() {
  ImuState x;
  x.T_WI.q = so3::quat_exp(Vector3d(0.3, -0.5, 2.0));
  x.T_WI.p = Vector3d(1.0, -2.0, 1.5);
  x.v_WI = Vector3d(0.8, 0.3, -0.4);
  x.b_g = Vector3d(0.01, -0.02, 0.015);
  x.b_a = Vector3d(0.1, -0.05, 0.2);
  x.F_ext = Vector3d(0.5, -0.3, 0.2);
  x.F_dot = Vector3d(-0.7, 0.4, 0.9);
  x.thrust_scale = 0.83;  // a payload of 20 % of the mass
  return x;
}

ImuInterval sample_interval(bool dyn, double dt) {
  ImuInterval u;
  u.dt = dt;
  u.gyro0 = Vector3d(0.5, -1.2, 0.9);
  u.gyro1 = Vector3d(0.7, -1.0, 1.3);
  u.drive0 = dyn ? Vector3d(0, 0, 9.6) : Vector3d(0.4, -0.2, 9.7);
  u.drive1 = dyn ? Vector3d(0, 0, 10.3) : Vector3d(0.9, 0.1, 9.3);
  return u;
}

// Compare every 3x3 block (a trailing scalar state: 3x1 / 1x3) relative to its own size (and
// the whole matrix).
void expect_blocks_near(const MatrixXd& A, const MatrixXd& N, double rel) {
  ASSERT_EQ(A.rows(), N.rows());
  ASSERT_EQ(A.cols(), N.cols());
  for (int i = 0; i < A.rows(); i += 3) {
    for (int j = 0; j < A.cols(); j += 3) {
      const int bi = std::min<int>(3, static_cast<int>(A.rows()) - i);
      const int bj = std::min<int>(3, static_cast<int>(A.cols()) - j);
      const MatrixXd a = A.block(i, j, bi, bj);
      const MatrixXd n = N.block(i, j, bi, bj);
      const double scale = std::max(a.norm(), 1e-3 * A.norm());
      EXPECT_LE((a - n).norm(), rel * scale) << "block (" << i << "," << j << ")\nanalytic\n"
                                             << a << "\nnumeric\n" << n;
    }
  }
}

void check_mode(PropagationMode mode, double dt, ForceFrame frame = ForceFrame::kBody,
                bool rate = false, bool thrust_scale = false, const Vector3d& drag = Vector3d::Zero()) {
  const bool dyn = mode == PropagationMode::kDynamics;
  const ImuLayout l{dyn, dyn && rate, dyn && thrust_scale};
  const int d = l.dim();
  const int nn = l.noise_dim();
  const Vector3d g(0, 0, -9.81);
  ImuState x = sample_state();
  if (!l.force_rate) x.F_dot.setZero();
  if (!l.thrust_scale) x.thrust_scale = 1.0;
  const ImuInterval u = sample_interval(dyn, dt);
  const ImuState y = propagate_mean(x, u, mode, g, {}, frame, drag);
  ImuFej fej;
  fej.T_WI = x.T_WI;
  fej.v_WI = x.v_WI;
  MatrixXd Phi, G;
  propagation_jacobians(x, fej, y, u, mode, g, &Phi, &G, frame, rate, thrust_scale, drag);

  const double h = 1e-6;
  MatrixXd Phi_num(d, d), G_num(d, nn);
  for (int i = 0; i < d; ++i) {
    VectorXd e = VectorXd::Zero(d);
    e(i) = h;
    const ImuState yp = propagate_mean(perturb(x, e, l), u, mode, g, {}, frame, drag);
    const ImuState ym = propagate_mean(perturb(x, -e, l), u, mode, g, {}, frame, drag);
    Phi_num.col(i) = (difference(yp, y, l) - difference(ym, y, l)) / (2 * h);
  }
  for (int i = 0; i < nn; ++i) {
    VectorXd e = VectorXd::Zero(nn);
    e(i) = h;
    const ImuState yp = propagate_mean(x, u, mode, g, noise_from(e, l), frame, drag);
    const ImuState ym = propagate_mean(x, u, mode, g, noise_from(-e, l), frame, drag);
    G_num.col(i) = (difference(yp, y, l) - difference(ym, y, l)) / (2 * h);
  }
  expect_blocks_near(Phi, Phi_num, 1e-6);
  expect_blocks_near(G, G_num, 1e-6);
}

TEST(PropagationJacobians, ImuModeMatchesNumeric) { check_mode(PropagationMode::kImu, 0.0025); }
TEST(PropagationJacobians, DynamicsModeMatchesNumeric) {
  check_mode(PropagationMode::kDynamics, 0.0025);
}
TEST(PropagationJacobians, WorldFrameForceMatchesNumeric) {
  check_mode(PropagationMode::kDynamics, 0.0025, ForceFrame::kWorld);
}
TEST(PropagationJacobians, ForceRateStateMatchesNumericBothFrames) {
  check_mode(PropagationMode::kDynamics, 0.0025, ForceFrame::kBody, true);
  check_mode(PropagationMode::kDynamics, 0.0025, ForceFrame::kWorld, true);
}
TEST(PropagationJacobians, ThrustScaleStateMatchesNumericBothFrames) {
  check_mode(PropagationMode::kDynamics, 0.0025, ForceFrame::kBody, false, true);
  check_mode(PropagationMode::kDynamics, 0.0025, ForceFrame::kWorld, true, true);
  check_mode(PropagationMode::kDynamics, 0.5, ForceFrame::kWorld, true, true);
}
// Linear body drag (docs/design.md §3): the v and theta columns gain -R D R^T and R([D u]x - D[u]x).
TEST(PropagationJacobians, LinearDragMatchesNumericEveryForceModel) {
  const Vector3d D(0.35, 0.4, 0.3);
  check_mode(PropagationMode::kDynamics, 0.0025, ForceFrame::kBody, false, false, D);
  check_mode(PropagationMode::kDynamics, 0.0025, ForceFrame::kWorld, true, false, D);
  check_mode(PropagationMode::kDynamics, 0.01, ForceFrame::kWorld, true, true, D);
  check_mode(PropagationMode::kDynamics, 0.5, ForceFrame::kBody, true, true, D);
}
TEST(PropagationMean, LinearDragDeceleratesAlongTheBodyAxes) {
  // Thrust cancels gravity, no force, yawed 90 deg: a world-x velocity is body -y, so D_y acts.
  ImuState x;
  x.T_WI.q = so3::quat_exp(Vector3d(0, 0, M_PI / 2));
  x.v_WI = Vector3d(2.0, 0, 0);
  ImuInterval u;
  u.dt = 0.01;
  u.drive0 = u.drive1 = Vector3d(0, 0, 9.81);
  const ImuState y = propagate_mean(x, u, PropagationMode::kDynamics, Vector3d(0, 0, -9.81), {},
                                    ForceFrame::kWorld, Vector3d(0.1, 0.5, 0.2));
  EXPECT_NEAR(y.v_WI.x(), 2.0 - 0.5 * 2.0 * 0.01, 1e-12);
  EXPECT_NEAR(y.v_WI.y(), 0.0, 1e-12);
  EXPECT_NEAR(y.T_WI.p.x(), 2.0 * 0.01 - 0.5 * 0.5 * 2.0 * 1e-4, 1e-12);
}
// Long intervals (gaps) exercise the non-small-angle branches.
TEST(PropagationJacobians, LongIntervalEveryModel) {
  check_mode(PropagationMode::kImu, 0.5);
  check_mode(PropagationMode::kDynamics, 0.5);
  check_mode(PropagationMode::kDynamics, 0.5, ForceFrame::kWorld, true);
  check_mode(PropagationMode::kDynamics, 0.5, ForceFrame::kBody, true);
}

TEST(PropagationMean, ForceRateIntegratesTheForceRamp) {
  // Zero rate, thrust exactly cancels gravity: the world-frame force ramp F_k + F_dot t alone
  // accelerates the vehicle, so v gains F dt + F_dot dt^2 / 2 and F gains F_dot dt.
  ImuState x;
  x.F_ext = Vector3d(0.3, -0.2, 0.1);
  x.F_dot = Vector3d(1.0, 2.0, -0.5);
  ImuInterval u;
  u.dt = 0.2;
  u.drive0 = u.drive1 = Vector3d(0, 0, 9.81);
  const ImuState y = propagate_mean(x, u, PropagationMode::kDynamics, Vector3d(0, 0, -9.81), {},
                                    ForceFrame::kWorld);
  EXPECT_LT((y.v_WI - (x.F_ext * 0.2 + x.F_dot * 0.02)).norm(), 1e-12);
  EXPECT_LT((y.T_WI.p - (x.F_ext * 0.02 + x.F_dot * (0.008 / 6.0))).norm(), 1e-12);
  EXPECT_LT((y.F_ext - (x.F_ext + x.F_dot * 0.2)).norm(), 1e-12);
  EXPECT_EQ(y.F_dot, x.F_dot);
}

TEST(PropagationMean, ConstantAccelerationIsExact) {
  // Zero rate, constant world acceleration: p and v are integrated exactly.
  ImuState x;
  x.v_WI = Vector3d(1, 2, 3);
  ImuInterval u;
  u.dt = 0.3;
  u.drive0 = u.drive1 = Vector3d(0.5, -0.5, 9.81 + 1.0);
  const ImuState y = propagate_mean(x, u, PropagationMode::kImu, Vector3d(0, 0, -9.81));
  const Vector3d a(0.5, -0.5, 1.0);
  EXPECT_LT((y.v_WI - (x.v_WI + a * 0.3)).norm(), 1e-12);
  EXPECT_LT((y.T_WI.p - (x.v_WI * 0.3 + 0.5 * a * 0.09)).norm(), 1e-12);
}

void check_accel_jacobian(ForceFrame frame) {
  // h(x) = s T_m + F_I + b_a with F_I = F_ext (body) or R^T F_ext (world); H_s = T_m (built in
  // accel_update, checked against a dense update in test_state.cpp).
  const ImuState x = sample_state();
  const ImuLayout l{true, true, true};
  const int d = l.dim();
  const Vector3d Tm(0, 0, 9.9);
  MatrixXd H_num(3, d);
  const double h = 1e-6;
  for (int i = 0; i < d; ++i) {
    VectorXd e = VectorXd::Zero(d);
    e(i) = h;
    H_num.col(i) = (predict_accel(perturb(x, e, l), Tm, frame) - predict_accel(perturb(x, -e, l), Tm, frame)) / (2 * h);
  }
  const AccelJacobian J = accel_jacobian(x, x.T_WI.q, frame);
  MatrixXd H = MatrixXd::Zero(3, d);
  H.block<3, 3>(0, imu_idx::kTheta) = J.H_theta;
  H.block<3, 3>(0, imu_idx::kBa).setIdentity();
  H.block<3, 3>(0, imu_idx::kF) = J.H_F;
  H.col(l.thrust_scale_index()) = Tm;
  EXPECT_LT((H - H_num).norm(), 1e-6 * H.norm()) << "analytic\n" << H << "\nnumeric\n" << H_num;
}

TEST(AccelMeasurement, JacobianMatchesNumericBodyForce) { check_accel_jacobian(ForceFrame::kBody); }
TEST(AccelMeasurement, DragJacobianMatchesNumeric) {
  // h_drag = -D R^T v: only the theta and v columns.
  const ImuState x = sample_state();
  const ImuLayout l{true, false, false};
  const Vector3d D(0.35, 0.4, 0.3), Tm(0, 0, 9.9);
  const Vector3d h0 = predict_accel(x, Tm, ForceFrame::kWorld, D);
  EXPECT_LT((h0 - predict_accel(x, Tm, ForceFrame::kWorld) - drag_in_body(x, D)).norm(), 1e-15);
  MatrixXd H_num(3, l.dim());
  for (int i = 0; i < l.dim(); ++i) {
    VectorXd e = VectorXd::Zero(l.dim());
    e(i) = 1e-6;
    H_num.col(i) = (drag_in_body(perturb(x, e, l), D) - drag_in_body(perturb(x, -e, l), D)) / 2e-6;
  }
  const DragJacobian J = drag_jacobian(x, D);
  MatrixXd H = MatrixXd::Zero(3, l.dim());
  H.block<3, 3>(0, imu_idx::kTheta) = J.H_theta;
  H.block<3, 3>(0, imu_idx::kV) = J.H_v;
  EXPECT_LT((H - H_num).norm(), 1e-7 * H.norm()) << "analytic\n" << H << "\nnumeric\n" << H_num;
}
TEST(AccelMeasurement, JacobianMatchesNumericWorldForce) { check_accel_jacobian(ForceFrame::kWorld); }

}  // namespace
