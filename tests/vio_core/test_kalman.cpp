/// @file test_kalman.cpp
/// @brief The one Kalman correction (vio_core/kalman.h) and the one covariance bookkeeping
/// (vio_core/covariance.h) against their textbook forms, at fixed and dynamic sizes.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "vio_core/covariance.h"
#include "vio_core/kalman.h"

namespace {

/// Random symmetric positive-definite matrix (fixed seed).
Eigen::MatrixXd random_spd(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd;
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < A.size(); ++i) A.data()[i] = nd(rng);
  return A * A.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
}

Eigen::MatrixXd random_matrix(int r, int c, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd;
  Eigen::MatrixXd A(r, c);
  for (int i = 0; i < A.size(); ++i) A.data()[i] = nd(rng);
  return A;
}

/// Textbook update: K = P H^T S^-1, dx = K r, Joseph form P' = (I - K H) P (I - K H)^T + K R K^T.
struct Reference {
  Eigen::VectorXd dx;
  Eigen::MatrixXd P;
  double chi2;
};
Reference textbook(const Eigen::MatrixXd& P, const Eigen::MatrixXd& H, const Eigen::MatrixXd& R,
                   const Eigen::VectorXd& r) {
  const Eigen::MatrixXd S = H * P * H.transpose() + R;
  const Eigen::MatrixXd K = P * H.transpose() * S.inverse();
  const Eigen::MatrixXd IKH = Eigen::MatrixXd::Identity(P.rows(), P.cols()) - K * H;
  return {K * r, IKH * P * IKH.transpose() + K * R * K.transpose(), r.dot(S.inverse() * r)};
}

}  // namespace

TEST(Kalman, CorrectionEqualsJosephFormDynamicSizes) {
  for (int m : {1, 3, 7}) {  // m = 3 takes subtract_outer's fused rank-3 path, others rankUpdate
    const int n = 12;
    Eigen::MatrixXd P = random_spd(n, 1 + m);
    const Eigen::MatrixXd H = random_matrix(m, n, 2 + m);
    const Eigen::MatrixXd R = random_spd(m, 3 + m);
    const Eigen::VectorXd r = random_matrix(m, 1, 4 + m);
    const Reference ref = textbook(P, H, R, r);
    const Eigen::MatrixXd PHt = P * H.transpose();
    const Eigen::MatrixXd S = H * PHt + R;
    Eigen::VectorXd dx;
    ASSERT_TRUE(vid::kalman_correct(P, PHt, S, r, &dx));
    EXPECT_LT((dx - ref.dx).norm(), 1e-10 * ref.dx.norm()) << "m = " << m;
    EXPECT_LT((P - ref.P).norm(), 1e-10 * ref.P.norm()) << "m = " << m;
    EXPECT_EQ((P - P.transpose()).cwiseAbs().maxCoeff(), 0.0) << "P exactly symmetric, m = " << m;
  }
}

TEST(Kalman, CorrectionEqualsJosephFormFixedSizes) {
  constexpr int N = 10, M = 9;
  Eigen::Matrix<double, N, N> P = random_spd(N, 11);
  const Eigen::Matrix<double, M, N> H = random_matrix(M, N, 12);
  const Eigen::Matrix<double, M, M> R = random_spd(M, 13);
  const Eigen::Matrix<double, M, 1> r = random_matrix(M, 1, 14);
  const Reference ref = textbook(P, H, R, r);
  const Eigen::Matrix<double, N, M> PHt = P * H.transpose();
  const Eigen::Matrix<double, M, M> S = H * PHt + R;
  Eigen::Matrix<double, N, 1> dx;
  ASSERT_TRUE(vid::kalman_correct(P, PHt, S, r, &dx));
  EXPECT_LT((dx - ref.dx).norm(), 1e-10 * ref.dx.norm());
  EXPECT_LT((Eigen::MatrixXd(P) - ref.P).norm(), 1e-10 * ref.P.norm());
}

TEST(Kalman, NotPositiveDefiniteLeavesCovarianceUnchanged) {
  Eigen::MatrixXd P = random_spd(4, 21);
  const Eigen::MatrixXd P0 = P;
  const Eigen::MatrixXd Pxy = random_matrix(4, 2, 22);
  Eigen::MatrixXd S(2, 2);
  S << 1.0, 0.0, 0.0, -1.0;
  Eigen::VectorXd dx = Eigen::VectorXd::Ones(4);
  EXPECT_FALSE(vid::kalman_correct(P, Pxy, S, Eigen::VectorXd::Ones(2).eval(), &dx));
  EXPECT_EQ(P, P0);
  EXPECT_EQ(dx, Eigen::VectorXd::Zero(4));
}

TEST(Kalman, GateStatisticAndInflation) {
  const Eigen::Matrix3d S = random_spd(3, 31);
  const Eigen::Vector3d r = random_matrix(3, 1, 32);
  const Eigen::MatrixXd Pxy = random_matrix(8, 3, 33);
  vid::InnovationFactor<3> f;
  ASSERT_TRUE(f.compute(S, r));
  const double chi2 = r.dot(S.inverse() * r);
  EXPECT_NEAR(f.chi2(), chi2, 1e-12 * chi2);
  EXPECT_TRUE(f.past_gate(0.5 * chi2));
  EXPECT_FALSE(f.past_gate(2.0 * chi2));
  EXPECT_FALSE(f.past_gate(0.0)) << "threshold 0 = no gate";
  // inflate(k) is exactly the factor of k S: same gain, same whitened innovation.
  const double k = 3.7;
  f.inflate(k);
  vid::InnovationFactor<3> g;
  ASSERT_TRUE(g.compute(k * S, r));
  EXPECT_NEAR(f.chi2(), chi2 / k, 1e-12 * chi2);
  Eigen::MatrixXd Wf, Wg;
  f.whitened_gain(Pxy, &Wf);
  g.whitened_gain(Pxy, &Wg);
  EXPECT_LT((Wf - Wg).norm(), 1e-12 * Wg.norm());
  EXPECT_LT((f.whitened_innovation() - g.whitened_innovation()).norm(), 1e-12 * r.norm());
}

TEST(Covariance, AppendCloneIsStochasticCloning) {
  Eigen::MatrixXd P = random_spd(9, 41);
  const Eigen::MatrixXd P0 = P;
  const int at = vid::covariance::append_clone(P, 2, 3);
  ASSERT_EQ(at, 9);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(12, 9);  // x_aug = J x: [I_9; selector of 2..4]
  J.topRows(9).setIdentity();
  J.block(9, 2, 3, 3).setIdentity();
  EXPECT_EQ(P, J * P0 * J.transpose());
}

TEST(Covariance, AddScaledIsTheChangeOfVariables) {
  const Eigen::MatrixXd P0 = random_spd(10, 47);
  Eigen::MatrixXd P = P0;
  Eigen::VectorXd g(3);
  g << 0.5, -2.0, 3.0;
  vid::covariance::add_scaled(P, 4, g, 8);  // x_4..6 += g x_8
  Eigen::MatrixXd T = Eigen::MatrixXd::Identity(10, 10);
  T.block(4, 8, 3, 1) = g;
  EXPECT_LT((P - T * P0 * T.transpose()).norm(), 1e-14 * P0.norm());
}

TEST(Covariance, CloneIntoPreallocatedEqualsAppend) {
  const Eigen::MatrixXd P0 = random_spd(10, 51);
  Eigen::MatrixXd grown = P0;
  vid::covariance::append_clone(grown, 0, 9);
  Eigen::MatrixXd big = Eigen::MatrixXd::Zero(28, 28);
  big.topLeftCorner(10, 10) = P0;
  vid::covariance::clone_into(big, 10, 0, 9);
  EXPECT_EQ(big.topLeftCorner(19, 19), grown);
  EXPECT_EQ(big.bottomRightCorner(9, 9), Eigen::MatrixXd::Zero(9, 9)) << "storage past used untouched";
}

TEST(Covariance, RemoveUndoesInsertAndAppend) {
  const Eigen::MatrixXd P0 = random_spd(8, 61);
  Eigen::MatrixXd P = P0;
  vid::covariance::insert(P, 3, 2.0 * Eigen::MatrixXd::Identity(4, 4));
  ASSERT_EQ(P.rows(), 12);
  EXPECT_EQ(P.block(3, 3, 4, 4), 2.0 * Eigen::MatrixXd::Identity(4, 4));
  EXPECT_EQ(P.block(3, 0, 4, 3), Eigen::MatrixXd::Zero(4, 3)) << "inserted uncorrelated";
  EXPECT_EQ(P(7, 0), P0(3, 0)) << "variables behind it shifted by 4";
  vid::covariance::remove(P, 3, 4);
  EXPECT_EQ(P, P0);
  vid::covariance::append_clone(P, 5, 2);
  vid::covariance::remove(P, 8, 2);
  EXPECT_EQ(P, P0);
}

TEST(Covariance, PropagateLeadingEqualsFullTransition) {
  // P = [x (6) | r (5)]: Phi_aug = blockdiag(Phi, I), Q_aug = blockdiag(Q, 0).
  const Eigen::MatrixXd P0 = random_spd(11, 71);
  const Eigen::MatrixXd Phi = random_matrix(6, 6, 72);
  const Eigen::MatrixXd Q = random_spd(6, 73);
  Eigen::MatrixXd Phi_aug = Eigen::MatrixXd::Identity(11, 11);
  Phi_aug.topLeftCorner(6, 6) = Phi;
  Eigen::MatrixXd Q_aug = Eigen::MatrixXd::Zero(11, 11);
  Q_aug.topLeftCorner(6, 6) = Q;
  const Eigen::MatrixXd expected = Phi_aug * P0 * Phi_aug.transpose() + Q_aug;
  Eigen::MatrixXd P = P0;
  vid::covariance::propagate_leading(P, 11, Phi, Q);
  EXPECT_LT((P - expected).norm(), 1e-12 * expected.norm());
  // Fixed-size transition on a larger allocation: only the used part changes.
  Eigen::MatrixXd big = Eigen::MatrixXd::Zero(14, 14);
  big.topLeftCorner(11, 11) = P0;
  const Eigen::Matrix<double, 6, 6> Phi_f = Phi;
  const Eigen::Matrix<double, 6, 6> Q_f = Q;
  vid::covariance::propagate_leading(big, 11, Phi_f, Q_f);
  EXPECT_LT((big.topLeftCorner(11, 11) - expected).norm(), 1e-12 * expected.norm());
  EXPECT_EQ(big.rightCols(3), Eigen::MatrixXd::Zero(14, 3));
}
