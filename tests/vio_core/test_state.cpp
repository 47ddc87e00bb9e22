// State/covariance bookkeeping: clone augmentation and marginalization, the time-offset
// variable, corrections, generic and accelerometer EKF updates vs the dense textbook formula.
#include <gtest/gtest.h>

#include <random>

#include "geometry/so3.h"
#include "vio_core/chi2.h"
#include "vio_core/ekf_update.h"
#include "vio_core/state.h"
#include "error_state.h"

namespace {
using namespace vid;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

MatrixXd random_spd(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd(0, 1);
  MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = nd(rng);
  return 0.1 * A * A.transpose() / n + 0.01 * MatrixXd::Identity(n, n);
}

FilterState make_state(bool dyn, ForceFrame frame = ForceFrame::kBody, bool rate = false,
                       bool thrust_scale = false) {
  FilterState s(dyn, frame, rate, thrust_scale);
  ImuState x;
  x.T_WI.q = so3::quat_exp(Vector3d(0.1, 0.2, -0.3));
  x.T_WI.p = Vector3d(1, 2, 3);
  if (dyn) x.F_ext = Vector3d(0.4, -0.6, 0.3);
  if (thrust_scale) x.thrust_scale = 0.8;
  s.initialize(1000, x, random_spd(s.imu_dim(), 3));
  return s;
}

TEST(FilterState, AugmentationCopiesImuPoseBlock) {
  FilterState s = make_state(true);
  const MatrixXd P0 = s.P();
  s.augment_clone();
  ASSERT_EQ(s.dim(), 24);
  ASSERT_EQ(s.clones().size(), 1u);
  const CloneState& c = s.clones().back();
  EXPECT_EQ(c.cov_index, 18);
  EXPECT_EQ(c.t_ns, 1000);
  EXPECT_TRUE(c.T_WI.q.isApprox(s.imu().T_WI.q));
  EXPECT_TRUE(c.T_WI_fej.p.isApprox(s.imu_fej().T_WI.p));
  // P_new = J P J^T with J = [I; selection of dtheta, dp]
  MatrixXd J = MatrixXd::Zero(24, 18);
  J.topRows(18).setIdentity();
  J.block(18, 0, 6, 6).setIdentity();
  EXPECT_LT((s.P() - J * P0 * J.transpose()).norm(), 1e-15);
}

TEST(FilterState, CloneAtAnUncertainTimeCarriesTheTimeOffset) {
  // With t_d in the state the clone is the pose at t + dt_d: its error is the IMU pose's plus
  // [w_I; v_WI] dt_d, and a correction of t_d moves it through that correlation.
  FilterState s = make_state(true);
  s.imu().v_WI = Vector3d(1.0, -0.5, 0.2);
  s.add_time_offset(0.004, 0.01);
  ASSERT_TRUE(s.time_offset().has_value());
  EXPECT_EQ(s.time_offset()->cov_index, 18);
  EXPECT_DOUBLE_EQ(s.time_offset_or(0.0), 0.004);
  const MatrixXd P0 = s.P();
  const Vector3d w(0.3, -2.0, 0.7);
  s.augment_clone({w, s.imu().v_WI});
  ASSERT_EQ(s.dim(), 25);
  EXPECT_EQ(s.clones().back().cov_index, 19);
  MatrixXd J = MatrixXd::Zero(25, 19);
  J.topRows(19).setIdentity();
  J.block(19, 0, 6, 6).setIdentity();
  J.block(19, 18, 3, 1) = w;
  J.block(22, 18, 3, 1) = s.imu().v_WI;
  EXPECT_LT((s.P() - J * P0 * J.transpose()).norm(), 1e-14 * P0.norm());
  // Marginalizing the clone keeps the offset; a correction moves it.
  s.marginalize_oldest_clone();
  VectorXd dx = VectorXd::Zero(s.dim());
  dx(18) = 0.001;
  s.apply_correction(dx);
  EXPECT_DOUBLE_EQ(s.time_offset()->t_d_s, 0.005);
  s.initialize(2000, s.imu(), random_spd(s.imu_dim(), 5));
  EXPECT_FALSE(s.time_offset().has_value());
}

TEST(FilterState, MarginalizationDropsOldestCloneAndReindexes) {
  FilterState s = make_state(false);
  for (int i = 0; i < 3; ++i) {
    s.set_time(1000 + i);
    s.imu().T_WI.p.x() += 1.0;
    s.augment_clone();
  }
  // Make the clone blocks distinguishable.
  s.P() = random_spd(s.dim(), 5);
  const MatrixXd P_before = s.P();
  s.marginalize_oldest_clone();
  ASSERT_EQ(s.clones().size(), 2u);
  EXPECT_EQ(s.clones().front().t_ns, 1001);
  EXPECT_EQ(s.clones()[0].cov_index, 15);
  EXPECT_EQ(s.clones()[1].cov_index, 21);
  std::vector<int> keep;
  for (int i = 0; i < 15; ++i) keep.push_back(i);
  for (int i = 21; i < 33; ++i) keep.push_back(i);
  for (std::size_t i = 0; i < keep.size(); ++i)
    for (std::size_t j = 0; j < keep.size(); ++j)
      EXPECT_EQ(s.P()(i, j), P_before(keep[i], keep[j]));
}

TEST(FilterState, HealthDetectsNonPdAndNaN) {
  FilterState s = make_state(true);
  EXPECT_TRUE(s.check_and_symmetrize().positive_definite);
  s.P()(3, 3) = -1.0;
  EXPECT_FALSE(s.check_and_symmetrize().positive_definite);
  s.P()(3, 3) = std::numeric_limits<double>::quiet_NaN();
  const CovarianceHealth h = s.check_and_symmetrize();
  EXPECT_FALSE(h.finite);
  EXPECT_FALSE(h.positive_definite);
}

TEST(FilterState, TimestampJitterIsIndependentCloneNoise) {
  // A frame whose time is off by j ~ N(0, s^2) has the pose at t + j: the clone gets
  // [w; v][w; v]^T s^2 on its own block and no new correlation (with or without t_d).
  for (const bool with_td : {false, true}) {
    FilterState s = make_state(true);
    s.imu().v_WI = Vector3d(1.0, -0.5, 0.2);
    if (with_td) s.add_time_offset(0.0, 0.01);
    FilterState ref = s;
    const Vector3d w(0.3, -2.0, 0.7);
    s.augment_clone({w, Vector3d::Zero(), 5e-4});
    ref.augment_clone({w, Vector3d::Zero(), 0.0});
    Eigen::Matrix<double, 6, 1> g;
    g << w, s.imu().v_WI;
    const int c = s.clones().back().cov_index;
    MatrixXd expected = ref.P();
    expected.block(c, c, 6, 6) += 2.5e-7 * g * g.transpose();
    EXPECT_LT((s.P() - expected).norm(), 1e-15) << with_td;
  }
}

TEST(FilterState, HealthSkipsOnlyTheFreshCloneCopy) {
  // The check leaves out the clone taken at the current time (an exact copy of the IMU pose plus
  // [w; v] dt_d: P is singular with it, test_time_offset.py has the fast_yaw run LDLT called
  // non-PD). Everything else is still tested: an indefinite IMU block beside it fails.
  FilterState s = make_state(true);
  s.add_time_offset(0.0, 0.02);
  s.augment_clone({Vector3d(0.2, -0.1, 3.0)});
  s.set_time(s.time() + 33'000'000);
  s.P().topLeftCorner(s.imu_dim(), s.imu_dim()).diagonal().array() += 1e-6;
  s.augment_clone({Vector3d(0.2, -0.1, 3.1)});
  EXPECT_TRUE(s.check_and_symmetrize().positive_definite);
  s.P()(3, 3) = -1e-3;
  EXPECT_FALSE(s.check_and_symmetrize().positive_definite);
  s.P()(3, 3) = 1e-2;
  const int older = s.clones().front().cov_index;
  s.P()(older + 3, older + 3) = -1e-3;  // an older clone is tested as before
  EXPECT_FALSE(s.check_and_symmetrize().positive_definite);
}

// Textbook dense update as the reference.
void dense_update(MatrixXd& P, const MatrixXd& H, const VectorXd& r, const MatrixXd& R, VectorXd* dx) {
  const MatrixXd S = H * P * H.transpose() + R;
  const MatrixXd K = P * H.transpose() * S.inverse();
  *dx = K * r;
  P = (MatrixXd::Identity(P.rows(), P.rows()) - K * H) * P;
}

TEST(EkfUpdate, SparseGenericUpdateMatchesDense) {
  FilterState s = make_state(true);
  for (int i = 0; i < 4; ++i) s.augment_clone();
  s.P() = random_spd(s.dim(), 11);
  std::mt19937 rng(2);
  std::normal_distribution<double> nd(0, 1);
  MatrixXd H = MatrixXd::Zero(5, s.dim());
  for (int i = 0; i < 5; ++i)
    for (int j : {24, 25, 29, 30, 40, 41}) H(i, j) = nd(rng);
  VectorXd r(5);
  for (int i = 0; i < 5; ++i) r(i) = 0.01 * nd(rng);
  const MatrixXd R = 0.01 * MatrixXd::Identity(5, 5);
  MatrixXd P_ref = s.P();
  VectorXd dx_ref;
  dense_update(P_ref, H, r, R, &dx_ref);
  const Vector3d p_clone_before = s.clones()[1].T_WI.p;
  const UpdateResult res = ekf_update(s, H, r, R);
  ASSERT_TRUE(res.applied);
  EXPECT_LT((s.P() - P_ref).norm(), 1e-12);
  EXPECT_LT((s.clones()[1].T_WI.p - p_clone_before - dx_ref.segment<3>(27)).norm(), 1e-12);
  // gating rejects a huge residual and leaves the state untouched
  const MatrixXd P_after = s.P();
  const UpdateResult gated = ekf_update(s, H, r * 1e4, R, chi2_quantile(0.95, 5));
  EXPECT_FALSE(gated.applied);
  EXPECT_GT(gated.chi2, gated.threshold);
  EXPECT_EQ((s.P() - P_after).norm(), 0.0);
}

void check_accel_update(ForceFrame frame, bool rate, bool thrust_scale = false,
                        const Vector3d& drag = Vector3d::Zero()) {
  FilterState s = make_state(true, frame, rate, thrust_scale);
  s.set_linear_drag(drag);
  s.imu().v_WI = Vector3d(1.5, -2.0, 0.4);
  for (int i = 0; i < 3; ++i) s.augment_clone();
  s.P() = random_spd(s.dim(), 13);
  const Vector3d Tm(0, 0, 9.7), a_m(0.2, -0.1, 9.9);
  const AccelJacobian J = accel_jacobian(s.imu(), s.imu_fej().T_WI.q, frame);
  MatrixXd H = MatrixXd::Zero(3, s.dim());
  H.block<3, 3>(0, imu_idx::kTheta) = J.H_theta;
  H.block<3, 3>(0, imu_idx::kBa).setIdentity();
  H.block<3, 3>(0, imu_idx::kF) = J.H_F;
  if (thrust_scale) H.col(s.layout().thrust_scale_index()) = Tm;  // d (s T_m) / d s
  const DragJacobian Jd = drag_jacobian(s.imu(), drag);
  H.block<3, 3>(0, imu_idx::kTheta) += Jd.H_theta;
  H.block<3, 3>(0, imu_idx::kV) = Jd.H_v;
  // The columns written by hand above (b_a, thrust scale, drag) against central differences of
  // the measurement model over the whole IMU block (the clones' columns stay zero).
  ASSERT_TRUE(s.imu_fej().T_WI.q.isApprox(s.imu().T_WI.q));  // else H is not d h / d x at x
  MatrixXd H_num = MatrixXd::Zero(3, s.dim());
  for (int i = 0; i < s.layout().dim(); ++i) {
    VectorXd e = VectorXd::Zero(s.layout().dim());
    e(i) = 1e-6;
    H_num.col(i) = (predict_accel(test::perturb(s.imu(), e, s.layout()), Tm, frame, drag) -
                    predict_accel(test::perturb(s.imu(), -e, s.layout()), Tm, frame, drag)) / 2e-6;
  }
  EXPECT_LT((H - H_num).norm(), 1e-7 * H.norm()) << "analytic\n" << H << "\nnumeric\n" << H_num;
  const VectorXd r = a_m - predict_accel(s.imu(), Tm, frame, drag);
  MatrixXd P_ref = s.P();
  VectorXd dx_ref;
  dense_update(P_ref, H, r, 0.04 * MatrixXd::Identity(3, 3), &dx_ref);
  const ImuState x0 = s.imu();
  const UpdateResult res = accel_update(s, a_m, Tm, 0.04, 100.0);
  ASSERT_TRUE(res.applied);
  EXPECT_LT((s.P() - P_ref).norm(), 1e-12);
  // symmetric to round-off (the column-wise W W^T update has no mirror pass)
  EXPECT_LE((s.P() - s.P().transpose()).norm(), 1e-15 * s.P().norm());
  EXPECT_LT((s.imu().F_ext - x0.F_ext - dx_ref.segment<3>(imu_idx::kF)).norm(), 1e-12);
  EXPECT_LT((s.imu().v_WI - x0.v_WI - dx_ref.segment<3>(imu_idx::kV)).norm(), 1e-12);
  if (rate) {
    EXPECT_LT((s.imu().F_dot - x0.F_dot - dx_ref.segment<3>(imu_idx::kFdot)).norm(), 1e-12);
  }
  if (thrust_scale) {
    EXPECT_NEAR(s.imu().thrust_scale - x0.thrust_scale, dx_ref(s.layout().thrust_scale_index()), 1e-12);
    EXPECT_NE(s.imu().thrust_scale, x0.thrust_scale);
  }
  // chi2 gating: an absurd reading is rejected
  const UpdateResult bad = accel_update(s, a_m + Vector3d(100, 0, 0), Tm, 0.04, 11.345);
  EXPECT_FALSE(bad.applied);
  // ... or, down-weighted, applied as a dense update whose innovation covariance is scaled by
  // k = chi2 / threshold: R_eff = k (H P H^T + R) - H P H^T, so its chi2 sits at the gate.
  const Vector3d a_bad = a_m + Vector3d(100, 0, 0);
  const AccelJacobian J1 = accel_jacobian(s.imu(), s.imu_fej().T_WI.q, frame);  // at the updated F
  const DragJacobian Jd1 = drag_jacobian(s.imu(), drag);
  H.block<3, 3>(0, imu_idx::kTheta) = J1.H_theta + Jd1.H_theta;
  H.block<3, 3>(0, imu_idx::kV) = Jd1.H_v;
  H.block<3, 3>(0, imu_idx::kF) = J1.H_F;
  const VectorXd r_bad = a_bad - predict_accel(s.imu(), Tm, frame, drag);
  const MatrixXd HPHt = H * s.P() * H.transpose();
  const MatrixXd S = HPHt + 0.04 * MatrixXd::Identity(3, 3);
  const double k = r_bad.dot(S.ldlt().solve(r_bad)) / 11.345;
  ASSERT_GT(k, 1.0);
  MatrixXd P_down = s.P();
  VectorXd dx_down;
  dense_update(P_down, H, r_bad, k * S - HPHt, &dx_down);
  const ImuState x1 = s.imu();
  const UpdateResult down = accel_update(s, a_bad, Tm, 0.04, 11.345, nullptr, true);
  EXPECT_TRUE(down.applied);
  EXPECT_TRUE(down.downweighted);
  EXPECT_NEAR(down.chi2, k * 11.345, 1e-9 * k * 11.345);
  EXPECT_LT((s.P() - P_down).norm(), 1e-10 * P_down.norm());
  EXPECT_LT((s.imu().F_ext - x1.F_ext - dx_down.segment<3>(imu_idx::kF)).norm(), 1e-10);
  // a sample inside the gate is not down-weighted
  EXPECT_FALSE(accel_update(s, a_m, Tm, 0.04, 1e6, nullptr, true).downweighted);
}

TEST(EkfUpdate, AccelUpdateMatchesDenseUpdate) { check_accel_update(ForceFrame::kBody, false); }
TEST(EkfUpdate, AccelUpdateMatchesDenseUpdateWorldForceWithRate) {
  check_accel_update(ForceFrame::kWorld, true);
}
TEST(EkfUpdate, AccelUpdateWithDragMatchesDenseUpdate) {
  const Vector3d D(0.35, 0.4, 0.3);
  check_accel_update(ForceFrame::kBody, false, false, D);
  check_accel_update(ForceFrame::kWorld, true, true, D);
}
TEST(EkfUpdate, AccelUpdateMatchesDenseUpdateWithThrustScale) {
  check_accel_update(ForceFrame::kBody, false, true);
  check_accel_update(ForceFrame::kWorld, true, true);
}

TEST(FilterState, ForceRateStateExtendsTheImuBlock) {
  EXPECT_EQ(FilterState(true, ForceFrame::kWorld, true).imu_dim(), 21);
  EXPECT_EQ(FilterState(true, ForceFrame::kWorld, false).imu_dim(), 18);
  EXPECT_EQ(FilterState(false, ForceFrame::kWorld, true).imu_dim(), 15);  // no force, no rate
  // The layout from the estimator settings: the defaults are EstimatorParams'.
  const EstimatorParams params;
  const FilterState from_params(params);
  EXPECT_EQ(from_params.with_force(), params.mode == PropagationMode::kDynamics);
  EXPECT_EQ(from_params.force_frame(), params.force_frame);
  EXPECT_EQ(from_params.with_force_rate(), params.force_rate_random_walk > 0.0);
  EstimatorParams imu_mode;
  imu_mode.mode = PropagationMode::kImu;
  EXPECT_EQ(FilterState(imu_mode).imu_dim(), 15);
  FilterState s = make_state(true, ForceFrame::kWorld, true);
  s.augment_clone();
  EXPECT_EQ(s.clones().front().cov_index, 21);
}

TEST(FilterState, ThrustScaleStateIsLastInTheImuBlock) {
  EXPECT_EQ(FilterState(true, ForceFrame::kWorld, true, true).imu_dim(), 22);
  EXPECT_EQ(FilterState(true, ForceFrame::kWorld, false, true).imu_dim(), 19);
  EXPECT_EQ(FilterState(false, ForceFrame::kWorld, false, true).imu_dim(), 15);  // needs the force
  EstimatorParams params;
  EXPECT_FALSE(FilterState(params).with_thrust_scale()) << "off by default";
  params.thrust_scale_random_walk = 0.01;
  const FilterState on(params);
  ASSERT_TRUE(on.with_thrust_scale());
  EXPECT_EQ(on.layout().thrust_scale_index(), on.imu_dim() - 1);
  // A correction moves s; off, s stays 1.
  FilterState s = make_state(true, ForceFrame::kWorld, true, true);
  s.augment_clone();
  EXPECT_EQ(s.clones().front().cov_index, 22);
  Eigen::VectorXd dx = Eigen::VectorXd::Zero(s.dim());
  dx(s.layout().thrust_scale_index()) = 0.05;
  s.apply_correction(dx);
  EXPECT_DOUBLE_EQ(s.imu().thrust_scale, 0.85);
  FilterState off = make_state(true, ForceFrame::kWorld, true, false);
  EXPECT_EQ(off.imu().thrust_scale, 1.0);
}

TEST(ForceFrames, BodyAndWorldViewsAgree) {
  ImuState x;
  x.T_WI.q = so3::quat_exp(Vector3d(0.2, -0.4, 1.1));
  const Vector3d F_I(0.5, -1.0, 0.25);
  set_force_from_body(x, ForceFrame::kWorld, F_I);
  EXPECT_LT((force_in_body(x, ForceFrame::kWorld) - F_I).norm(), 1e-15);
  EXPECT_LT((force_in_world(x, ForceFrame::kWorld) - x.T_WI.q * F_I).norm(), 1e-15);
  set_force_from_body(x, ForceFrame::kBody, F_I);
  EXPECT_EQ(x.F_ext, F_I);
  EXPECT_LT((force_in_world(x, ForceFrame::kBody) - x.T_WI.q * F_I).norm(), 1e-15);
}

}  // namespace
