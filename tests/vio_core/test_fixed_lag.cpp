// Fixed-lag smoothing through force clones (docs/notes/smoothing.md, docs/model.md eqs. (35)-(40)):
// on a linear-Gaussian configuration of the filter (body-frame force with its rate, observed by
// the accelerometer with its bias; no gyro noise, so nothing nonlinear couples in) a released
// force clone equals the batch least-squares estimate over the same data, mean and covariance;
// the clones change nothing in the causal estimate; index bookkeeping with interleaved clones.
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <random>

#include "geometry/so3.h"
#include "vio_core/ekf_update.h"
#include "vio_core/fixed_lag.h"
#include "vio_core/propagation.h"
#include "vio_core/state.h"

namespace {
using namespace vid;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

// The toy: per axis an integrated random walk F (rate D) plus a random-walk bias b, y = F + b + n.
struct Toy {
  double dt = 0.01;
  double sigma_F0 = 0.8, sigma_D0 = 0.5, sigma_b0 = 0.3;  // prior sigmas at step 0
  double meas_var = 0.25;
  EstimatorParams params() const {
    EstimatorParams p;
    p.mode = PropagationMode::kDynamics;
    p.force_frame = ForceFrame::kBody;
    p.force_random_walk = 0.3;
    p.force_rate_random_walk = 1.0;
    p.accel_random_walk = 0.1;
    p.gyro_noise_density = 0.0;
    p.gyro_random_walk = 0.0;
    p.use_fej = false;
    return p;
  }
};

FilterState toy_state(const Toy& toy, const EstimatorParams& p) {
  FilterState s(p);
  MatrixXd P0 = MatrixXd::Identity(s.imu_dim(), s.imu_dim()) * 1e-4;
  P0.block<3, 3>(imu_idx::kF, imu_idx::kF) = Eigen::Matrix3d::Identity() * toy.sigma_F0 * toy.sigma_F0;
  P0.block<3, 3>(imu_idx::kFdot, imu_idx::kFdot) = Eigen::Matrix3d::Identity() * toy.sigma_D0 * toy.sigma_D0;
  P0.block<3, 3>(imu_idx::kBa, imu_idx::kBa) = Eigen::Matrix3d::Identity() * toy.sigma_b0 * toy.sigma_b0;
  s.initialize(0, ImuState{}, P0);
  return s;
}

// Batch least squares over steps 0..J (unknowns [F_i, D_i, b_i] per step, 3 axes as 3 right-hand
// sides: the model is isotropic), measurements y_1..y_J. Returns the mean of F_k and its variance.
struct Batch {
  MatrixXd mean;  // (3 (J+1)) x 3
  MatrixXd cov;   // (3 (J+1)) x (3 (J+1)), per axis
};
Batch batch_solve(const Toy& toy, const EstimatorParams& p, const std::vector<Vector3d>& y, int J) {
  const int n = 3 * (J + 1);
  const int rows = 3 + 3 * J + J;
  MatrixXd A = MatrixXd::Zero(rows, n);
  MatrixXd b = MatrixXd::Zero(rows, 3);
  const auto F = [](int i) { return 3 * i; };
  const auto D = [](int i) { return 3 * i + 1; };
  const auto B = [](int i) { return 3 * i + 2; };
  int r = 0;
  A(r++, F(0)) = 1.0 / toy.sigma_F0;
  A(r++, D(0)) = 1.0 / toy.sigma_D0;
  A(r++, B(0)) = 1.0 / toy.sigma_b0;
  const double sF = p.force_random_walk * std::sqrt(toy.dt);
  const double sD = p.force_rate_random_walk * std::sqrt(toy.dt);
  const double sB = p.accel_random_walk * std::sqrt(toy.dt);
  for (int i = 1; i <= J; ++i) {
    // F_i - F_{i-1} - D_{i-1} dt = w_F; D_i - D_{i-1} = w_D; b_i - b_{i-1} = w_b (eq. S2).
    A(r, F(i)) = 1.0 / sF;
    A(r, F(i - 1)) = -1.0 / sF;
    A(r++, D(i - 1)) = -toy.dt / sF;
    A(r, D(i)) = 1.0 / sD;
    A(r++, D(i - 1)) = -1.0 / sD;
    A(r, B(i)) = 1.0 / sB;
    A(r++, B(i - 1)) = -1.0 / sB;
    const double sm = std::sqrt(toy.meas_var);
    A(r, F(i)) = 1.0 / sm;
    A(r, B(i)) = 1.0 / sm;
    b.row(r++) = y[static_cast<std::size_t>(i)].transpose() / sm;
  }
  Eigen::HouseholderQR<MatrixXd> qr(A);
  Batch out;
  out.mean = qr.solve(b);
  const MatrixXd R = qr.matrixQR().topRows(n).triangularView<Eigen::Upper>();
  const MatrixXd Rinv = R.triangularView<Eigen::Upper>().solve(MatrixXd::Identity(n, n));
  out.cov = Rinv * Rinv.transpose();
  return out;
}

TEST(FixedLag, ForceCloneEqualsBatchLeastSquaresOnLinearGaussianToy) {
  const Toy toy;
  const EstimatorParams p = toy.params();
  FilterState s = toy_state(toy, p);
  // Truth and data (fixed seed).
  std::mt19937 rng(22);
  std::normal_distribution<double> nd(0.0, 1.0);
  const auto randn3 = [&] { return Vector3d(nd(rng), nd(rng), nd(rng)); };
  Vector3d F = toy.sigma_F0 * randn3(), Dt = toy.sigma_D0 * randn3(), bias = toy.sigma_b0 * randn3();
  const int kSteps = 120, kPeriod = 5, kLag = 30;  // clone every 50 ms, lag 0.3 s
  std::vector<Vector3d> y(1, Vector3d::Zero());
  ImuInterval u;
  u.dt = toy.dt;
  int released = 0;
  std::vector<int> clone_step;
  for (int i = 1; i <= kSteps; ++i) {
    F += Dt * toy.dt + p.force_random_walk * std::sqrt(toy.dt) * randn3();
    Dt += p.force_rate_random_walk * std::sqrt(toy.dt) * randn3();
    bias += p.accel_random_walk * std::sqrt(toy.dt) * randn3();
    y.push_back(F + bias + std::sqrt(toy.meas_var) * randn3());
    propagate(s, u, p);
    if (i % kPeriod == 0) {  // clone F(t_i) before the measurement of t_i, as at a camera frame
      s.augment_force_clone();
      clone_step.push_back(i);
    }
    ASSERT_TRUE(accel_update(s, y.back(), Vector3d::Zero(), toy.meas_var, 0.0).applied);
    // The causal estimate is the batch solution's newest state (lag 0).
    if (i % 40 == 0) {
      const Batch batch = batch_solve(toy, p, y, i);
      EXPECT_LT((s.imu().F_ext - batch.mean.row(3 * i).transpose()).norm(), 1e-9) << "step " << i;
    }
    while (!s.force_clones().empty() && i - clone_step.front() >= kLag) {
      const ForceClone& c = s.force_clones().front();
      const int k = clone_step.front();
      ASSERT_EQ(c.t_ns, seconds_to_ns(k * toy.dt));
      const Batch batch = batch_solve(toy, p, y, i);
      const Vector3d F_batch = batch.mean.row(3 * k).transpose();
      EXPECT_LT((c.F_ext - F_batch).norm(), 1e-9) << "clone of step " << k << " released at step " << i;
      const double var_batch = batch.cov(3 * k, 3 * k);
      const Eigen::Matrix3d P_c = s.P().block<3, 3>(c.cov_index, c.cov_index);
      EXPECT_LT((P_c - var_batch * Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-9 * var_batch);
      // Smoothing helps: the lagged variance is below the causal variance of that time.
      EXPECT_LT(var_batch, batch_solve(toy, p, y, k).cov(3 * k, 3 * k));
      s.marginalize_oldest_force_clone();
      clone_step.erase(clone_step.begin());
      ++released;
    }
  }
  EXPECT_EQ(released, (kSteps - kLag) / kPeriod);
}

TEST(FixedLag, ForceClonesLeaveTheCausalEstimateUnchanged) {
  const Toy toy;
  EstimatorParams p = toy.params();
  p.force_frame = ForceFrame::kWorld;  // nonlinear: attitude couples into the accelerometer
  p.gyro_noise_density = 1e-3;
  FilterState plain = toy_state(toy, p), aug = toy_state(toy, p);
  std::mt19937 rng(5);
  std::normal_distribution<double> nd(0.0, 1.0);
  ImuInterval u;
  u.dt = toy.dt;
  for (int i = 1; i <= 200; ++i) {
    u.gyro0 = u.gyro1;
    u.gyro1 = Vector3d(0.3 * std::sin(0.05 * i), 0.2, -0.4);
    u.drive0 = u.drive1;
    u.drive1 = Vector3d(0.0, 0.0, 9.81 + 0.1 * nd(rng));
    propagate(plain, u, p);
    propagate(aug, u, p);
    if (i % 5 == 0) {
      plain.augment_clone();
      aug.augment_clone();
      aug.augment_force_clone();
    }
    if (i % 20 == 0) {
      plain.marginalize_oldest_clone();
      aug.marginalize_oldest_clone();
    }
    if (aug.force_clones().size() > 4) aug.marginalize_oldest_force_clone();
    const Vector3d a_m(0.2 + 0.5 * nd(rng), -0.1 + 0.5 * nd(rng), 0.5 * nd(rng));
    const UpdateResult r1 = accel_update(plain, a_m, Vector3d::Zero(), toy.meas_var, 11.3);
    const UpdateResult r2 = accel_update(aug, a_m, Vector3d::Zero(), toy.meas_var, 11.3);
    ASSERT_EQ(r1.applied, r2.applied);
    EXPECT_NEAR(r1.chi2, r2.chi2, 1e-9);
  }
  EXPECT_LT(so3::boxminus(plain.imu().T_WI.q, aug.imu().T_WI.q).norm(), 1e-9);
  EXPECT_LT((plain.imu().F_ext - aug.imu().F_ext).norm(), 1e-9);
  EXPECT_LT((plain.imu().b_a - aug.imu().b_a).norm(), 1e-9);
  EXPECT_LT((plain.imu().v_WI - aug.imu().v_WI).norm(), 1e-9);
  const int d = plain.imu_dim();
  EXPECT_LT((plain.P().topLeftCorner(d, d) - aug.P().topLeftCorner(d, d)).cwiseAbs().maxCoeff(), 1e-12);
  ASSERT_EQ(plain.clones().size(), aug.clones().size());
  for (std::size_t i = 0; i < plain.clones().size(); ++i) {
    const int a = plain.clones()[i].cov_index, b = aug.clones()[i].cov_index;
    EXPECT_LT((plain.P().block<6, 6>(a, a) - aug.P().block<6, 6>(b, b)).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(FixedLag, InterleavedClonesKeepTheirBlocks) {
  FilterState s(true, ForceFrame::kWorld, true);
  ImuState x;
  x.F_ext = Vector3d(1, 2, 3);
  MatrixXd P0 = MatrixXd::Identity(s.imu_dim(), s.imu_dim());
  for (int i = 0; i < s.imu_dim(); ++i) P0(i, i) = 1.0 + i;
  s.initialize(0, x, P0);
  s.augment_clone();        // 21..26
  s.augment_force_clone();  // 27..29
  s.augment_clone();        // 30..35
  s.augment_force_clone();  // 36..38
  ASSERT_EQ(s.dim(), 39);
  EXPECT_EQ(s.force_clones()[0].cov_index, 27);
  const Eigen::Matrix3d P_FF = P0.block<3, 3>(imu_idx::kF, imu_idx::kF);
  EXPECT_TRUE((s.P().block<3, 3>(27, 27) - P_FF).isZero(0.0));
  EXPECT_TRUE((s.P().block<3, 3>(27, imu_idx::kF) - P_FF).isZero(0.0));
  s.marginalize_oldest_clone();
  EXPECT_EQ(s.force_clones()[0].cov_index, 21);
  EXPECT_EQ(s.clones()[0].cov_index, 24);
  EXPECT_EQ(s.force_clones()[1].cov_index, 30);
  EXPECT_TRUE((s.P().block<3, 3>(21, 21) - P_FF).isZero(0.0));
  s.marginalize_oldest_force_clone();
  EXPECT_EQ(s.clones()[0].cov_index, 21);
  EXPECT_EQ(s.force_clones()[0].cov_index, 27);
  EXPECT_EQ(s.dim(), 30);
  // A correction reaches the force clone at its column.
  VectorXd dx = VectorXd::Zero(s.dim());
  dx.segment<3>(27) = Vector3d(0.5, 0.0, -0.5);
  s.apply_correction(dx);
  EXPECT_TRUE((s.force_clones()[0].F_ext - Vector3d(1.5, 2.0, 2.5)).isZero(0.0));
  EXPECT_THROW(FilterState(false, ForceFrame::kWorld, false).augment_force_clone(), std::logic_error);
}

TEST(FixedLag, AnchorsInterpolateAndHold) {
  FixedLagOutput out(ForceFrame::kWorld);
  Pose T;
  out.clone_taken(100, Vector3d(1, 0, 0), Eigen::Matrix3d::Identity(), T);
  out.clone_taken(200, Vector3d(2, 0, 0), Eigen::Matrix3d::Identity(), T);
  std::vector<EstimateOutput> got;
  const auto sink = [&got](const EstimateOutput& e) { got.push_back(e); };
  for (TimeNs t : {50, 100, 150, 200, 250}) {
    EstimateOutput e;
    e.t_ns = t;
    e.x.F_ext = Vector3d(1, 0, 0);
    e.F_ext_W = e.x.F_ext;
    e.F_ext_I = e.x.F_ext;
    e.cov_F_W = e.cov_F_I = Eigen::Matrix3d::Identity();
    e.cov_theta = e.cov_p = Eigen::Matrix3d::Identity();
    out.add_causal(e);
  }
  out.clone_released(100, Vector3d(1.2, 0, 0), 0.5 * Eigen::Matrix3d::Identity(), T);
  out.release(sink);
  ASSERT_EQ(got.size(), 2u);  // t <= 100: the first anchor held
  EXPECT_DOUBLE_EQ(got[0].F_ext_W.x(), 1.2);
  out.clone_released(200, Vector3d(2.4, 0, 0), 0.9 * Eigen::Matrix3d::Identity(), T);
  out.release(sink);
  ASSERT_EQ(got.size(), 4u);
  EXPECT_NEAR(got[2].F_ext_W.x(), 1.0 + 0.5 * (0.2 + 0.4), 1e-12);  // midway: mean correction
  EXPECT_NEAR(got[2].cov_F_W(0, 0), 1.0 - 0.5 * (0.5 + 0.1), 1e-12);
  out.release(sink, true);
  ASSERT_EQ(got.size(), 5u);
  EXPECT_NEAR(got[4].F_ext_W.x(), 1.4, 1e-12);  // past the last anchor: held
}

}  // namespace
