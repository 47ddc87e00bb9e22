/// Nullspace projection, QR compression and chi2 quantiles.

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <random>

#include "vio_core/msckf/linear_algebra.h"

namespace vid::msckf {
namespace {

Eigen::MatrixXd random_matrix(int r, int c, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd M(r, c);
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < c; ++j) M(i, j) = g(rng);
  return M;
}

TEST(NullspaceProjection, AnnihilatesFeatureJacobianAndKeepsTheRest) {
  std::mt19937 rng(3);
  for (int m : {4, 8, 22, 44}) {
    const Eigen::MatrixXd H_f = random_matrix(m, 3, rng);
    const Eigen::MatrixXd H_x0 = random_matrix(m, 12, rng);
    const Eigen::VectorXd r0 = random_matrix(m, 1, rng);
    const Eigen::MatrixXd A0 = random_matrix(m, m, rng);
    const Eigen::MatrixXd S0 = A0 * A0.transpose();

    // Project [H_x | H_f] together: the H_f part must vanish.
    Eigen::MatrixXd HxHf(m, 15);
    HxHf << H_x0, H_f;
    Eigen::VectorXd r = r0;
    Eigen::MatrixXd S = S0;
    nullspace_project(H_f, &HxHf, &r, &S);
    ASSERT_EQ(HxHf.rows(), m - 3);
    ASSERT_EQ(r.size(), m - 3);
    ASSERT_EQ(S.rows(), m - 3);
    EXPECT_LT(HxHf.rightCols(3).norm(), 1e-12 * H_f.norm()) << "m = " << m;

    // Reference: explicit orthonormal left-nullspace basis N (N^T H_f = 0, N^T N = I).
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(H_f);
    const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(m, m);
    const Eigen::MatrixXd N = Q.rightCols(m - 3);
    EXPECT_LT((N.transpose() * H_f).norm(), 1e-12);
    EXPECT_LT((HxHf.leftCols(12) - N.transpose() * H_x0).norm(), 1e-12);
    EXPECT_LT((r - N.transpose() * r0).norm(), 1e-12);
    EXPECT_LT((S - N.transpose() * S0 * N).norm(), 1e-10 * S0.norm());
    // Projection keeps the part of r orthogonal to range(H_f).
    const Eigen::VectorXd r_perp = r0 - H_f * (H_f.colPivHouseholderQr().solve(r0));
    EXPECT_NEAR(r.norm(), r_perp.norm(), 1e-12);
  }
}

TEST(NullspaceProjection, RejectsBadShapes) {
  Eigen::MatrixXd H_f = Eigen::MatrixXd::Ones(3, 3);
  Eigen::MatrixXd H_x = Eigen::MatrixXd::Ones(3, 6);
  Eigen::VectorXd r = Eigen::VectorXd::Ones(3);
  EXPECT_THROW(nullspace_project(H_f, &H_x, &r), std::invalid_argument);
  H_f = Eigen::MatrixXd::Ones(6, 3);
  EXPECT_THROW(nullspace_project(H_f, &H_x, &r), std::invalid_argument);
}

TEST(QrCompression, KeepsNormalEquations) {
  std::mt19937 rng(5);
  for (auto [m, n] : {std::pair{200, 66}, std::pair{67, 66}, std::pair{1640, 66}}) {
    Eigen::MatrixXd H = random_matrix(m, n, rng);
    // Rank-deficient columns too (like the unobservable gauge of a visual-only system).
    H.col(3) = H.col(1) - 2.0 * H.col(2);
    Eigen::VectorXd r = random_matrix(m, 1, rng);
    const Eigen::MatrixXd HtH = H.transpose() * H;
    const Eigen::VectorXd Htr = H.transpose() * r;
    const double rr = r.squaredNorm();
    compress_qr(&H, &r);
    ASSERT_EQ(H.rows(), n);
    ASSERT_EQ(r.size(), n);
    EXPECT_LT((H.transpose() * H - HtH).norm(), 1e-10 * HtH.norm());
    EXPECT_LT((H.transpose() * r - Htr).norm(), 1e-10 * Htr.norm());
    EXPECT_LE(r.squaredNorm(), rr * (1.0 + 1e-12));
    // Upper triangular.
    EXPECT_EQ(H.triangularView<Eigen::StrictlyLower>().toDenseMatrix().norm(), 0.0);
  }
}

TEST(QrCompression, NoOpWhenFewerRowsThanColumns) {
  std::mt19937 rng(6);
  Eigen::MatrixXd H = random_matrix(10, 30, rng);
  Eigen::VectorXd r = random_matrix(10, 1, rng);
  const Eigen::MatrixXd H0 = H;
  const Eigen::VectorXd r0 = r;
  compress_qr(&H, &r);
  EXPECT_EQ(H, H0);
  EXPECT_EQ(r, r0);
}

TEST(NormalEquationFactor, ReproducesNormalEquationsOfRankDeficientSystem) {
  std::mt19937 rng(9);
  for (int rank_drop : {0, 1, 6}) {
    Eigen::MatrixXd H = random_matrix(300, 66, rng);
    for (int k = 0; k < rank_drop; ++k) H.col(10 + k) = H.col(0) + 0.5 * H.col(1 + k);
    const Eigen::VectorXd r = random_matrix(300, 1, rng);
    const Eigen::MatrixXd A = H.transpose() * H;
    const Eigen::VectorXd b = H.transpose() * r;
    Eigen::MatrixXd Hc;
    Eigen::VectorXd rc;
    factor_normal_equations(A, b, &Hc, &rc);
    EXPECT_EQ(Hc.rows(), 66 - rank_drop);
    EXPECT_EQ(Hc.cols(), 66);
    EXPECT_EQ(rc.size(), Hc.rows());
    EXPECT_LT((Hc.transpose() * Hc - A).norm(), 1e-10 * A.norm()) << "rank drop " << rank_drop;
    EXPECT_LT((Hc.transpose() * rc - b).norm(), 1e-9 * b.norm()) << "rank drop " << rank_drop;
  }
  Eigen::MatrixXd Hc;
  Eigen::VectorXd rc;
  EXPECT_THROW(factor_normal_equations(Eigen::MatrixXd::Identity(3, 3), Eigen::VectorXd::Ones(2),
                                       &Hc, &rc),
               std::invalid_argument);
}

}  // namespace
}  // namespace vid::msckf
