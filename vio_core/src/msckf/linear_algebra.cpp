/// @file linear_algebra.cpp
/// @brief Left-nullspace projection (Householder) and QR measurement compression.

#include "vio_core/msckf/linear_algebra.h"

#include <Eigen/Householder>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace vid::msckf {

void nullspace_project(const Eigen::MatrixXd& H_f, Eigen::MatrixXd* H_x, Eigen::VectorXd* r,
                       Eigen::MatrixXd* S) {
  const Eigen::Index m = H_f.rows();
  if (H_f.cols() != 3 || m < 4 || H_x->rows() != m || r->size() != m ||
      (S != nullptr && (S->rows() != m || S->cols() != m))) {
    throw std::invalid_argument(std::string(__FILE__) + ": nullspace_project: H_f must be m x 3 "
                                "with m >= 4 and H_x, r, S must have m rows (m = " +
                                std::to_string(m) + ")");
  }
  // Q = H0 H1 H2 with Householder reflectors H_k acting on rows k..m-1; Q^T X = H2 H1 H0 X.
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(H_f);
  const Eigen::MatrixXd& v = qr.matrixQR();
  Eigen::VectorXd work(std::max<Eigen::Index>(H_x->cols(), m));
  for (Eigen::Index k = 0; k < 3; ++k) {
    const auto essential = v.col(k).tail(m - k - 1);
    const double tau = qr.hCoeffs()(k);
    H_x->bottomRows(m - k).applyHouseholderOnTheLeft(essential, tau, work.data());
    r->tail(m - k).applyHouseholderOnTheLeft(essential, tau, work.data());
    if (S != nullptr) {
      S->bottomRows(m - k).applyHouseholderOnTheLeft(essential, tau, work.data());
    }
  }
  if (S != nullptr) {
    for (Eigen::Index k = 0; k < 3; ++k) {
      const auto essential = v.col(k).tail(m - k - 1);
      S->bottomRightCorner(m - 3, m - k).applyHouseholderOnTheRight(essential, qr.hCoeffs()(k),
                                                                    work.data());
    }
    *S = S->bottomRightCorner(m - 3, m - 3).eval();
  }
  *H_x = H_x->bottomRows(m - 3).eval();
  *r = r->tail(m - 3).eval();
}

void NullspaceProjector::compute(const Eigen::Ref<const Eigen::MatrixXd>& H_f) {
  if (H_f.cols() != 3 || H_f.rows() < 4) {
    throw std::invalid_argument(std::string(__FILE__) + ": NullspaceProjector: H_f must be m x "
                                "3 with m >= 4 (got " + std::to_string(H_f.rows()) + " x " +
                                std::to_string(H_f.cols()) + ")");
  }
  qr_.compute(H_f);
}

void NullspaceProjector::apply(Eigen::Ref<Eigen::MatrixXd> X) {
  const Eigen::Index m = rows();
  if (X.rows() != m) {
    throw std::invalid_argument(std::string(__FILE__) + ": NullspaceProjector::apply: operand "
                                "has " + std::to_string(X.rows()) + " rows, H_f has " +
                                std::to_string(m));
  }
  work_.resize(X.cols());
  const Eigen::MatrixXd& v = qr_.matrixQR();
  for (Eigen::Index k = 0; k < 3; ++k) {
    X.bottomRows(m - k).applyHouseholderOnTheLeft(v.col(k).tail(m - k - 1), qr_.hCoeffs()(k),
                                                  work_.data());
  }
}

bool ProjectedChi2::compute(const Eigen::Ref<const Eigen::MatrixXd>& S,
                            const Eigen::Ref<const Eigen::MatrixXd>& H_f,
                            const Eigen::Ref<const Eigen::VectorXd>& r, double* chi2) {
  const Eigen::Index m = S.rows();
  if (S.cols() != m || H_f.rows() != m || H_f.cols() != 3 || r.size() != m || m < 4) {
    throw std::invalid_argument(std::string(__FILE__) + ": ProjectedChi2: need S m x m, H_f m x "
                                "3, r m x 1 with m >= 4 (m = " + std::to_string(m) + ")");
  }
  // Left-looking Cholesky of [S, B; B^T, .] with B = [H_f, r], stopped after the S block: the
  // columns of W = [S; B^T] become [L; (L^-1 B)^T], one gemv per column.
  W_.resize(m + 4, m);
  W_.topRows(m).triangularView<Eigen::Lower>() = S;
  W_.bottomRows(4).topRows<3>() = H_f.transpose();
  W_.bottomRows(1) = r.transpose();
  const Eigen::Index rows = m + 4;
  for (Eigen::Index j = 0; j < m; ++j) {
    if (j > 0) {
      W_.col(j).tail(rows - j).noalias() -=
          W_.block(j, 0, rows - j, j) * W_.row(j).head(j).transpose();
    }
    const double d = W_(j, j);
    if (!(d > 0.0)) return false;
    const double l = std::sqrt(d);
    W_(j, j) = l;
    W_.col(j).tail(rows - j - 1) /= l;
  }
  // Least-squares residual of y on Y: the last diagonal entry of R in [Y, y] = Q R.
  B_ = W_.bottomRows(4).transpose();
  qr_.compute(B_);
  const double rho = qr_.matrixQR()(3, 3);
  *chi2 = rho * rho;
  return true;
}

void compress_qr(Eigen::MatrixXd* H, Eigen::VectorXd* r) {
  const Eigen::Index m = H->rows();
  const Eigen::Index n = H->cols();
  if (r->size() != m) {
    throw std::invalid_argument(std::string(__FILE__) + ": compress_qr: r has " +
                                std::to_string(r->size()) + " rows, H has " +
                                std::to_string(m));
  }
  if (m <= n) return;
  Eigen::HouseholderQR<Eigen::Ref<Eigen::MatrixXd>> qr(*H);  // in place
  r->applyOnTheLeft(qr.householderQ().adjoint());
  Eigen::MatrixXd R = H->topRows(n).triangularView<Eigen::Upper>();
  *H = std::move(R);
  r->conservativeResize(n);
}

void factor_normal_equations(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                             Eigen::MatrixXd* H_c, Eigen::VectorXd* r_c, double rel_tol) {
  const Eigen::Index n = A.rows();
  if (A.cols() != n || b.size() != n) {
    throw std::invalid_argument(std::string(__FILE__) + ": factor_normal_equations: A must be "
                                "square and b match it");
  }
  if (n == 0) {
    H_c->resize(0, 0);
    r_c->resize(0);
    return;
  }
  // Pivoted Cholesky (complete diagonal pivoting, right-looking, stops at the numerical
  // rank): A(perm, perm) = L L^T with L (n x rank) lower trapezoidal. Then A = (P L)(P L)^T,
  // so H_c = L^T P^T and r_c solves L_top r_c = b(perm)(0:rank).
  Eigen::MatrixXd W = A;
  std::vector<Eigen::Index> perm(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) perm[static_cast<std::size_t>(i)] = i;
  const double stop = rel_tol * std::max(W.diagonal().maxCoeff(), 0.0);
  Eigen::Index rank = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    Eigen::Index j = 0;
    const double piv = W.diagonal().tail(n - k).maxCoeff(&j);
    j += k;
    if (!(piv > stop)) break;
    if (j != k) {
      // Symmetric swap of rows/cols k and j (the lower triangle is kept complete).
      W.row(k).swap(W.row(j));
      W.col(k).swap(W.col(j));
      std::swap(perm[static_cast<std::size_t>(k)], perm[static_cast<std::size_t>(j)]);
    }
    const double lkk = std::sqrt(W(k, k));
    W(k, k) = lkk;
    const Eigen::Index rest = n - k - 1;
    W.col(k).tail(rest) /= lkk;
    // Full (both triangles) update keeps the trailing block exactly symmetric, so later
    // row/col swaps stay valid; a plain outer product vectorizes better than a triangular one.
    W.bottomRightCorner(rest, rest).noalias() -= W.col(k).tail(rest) *
                                                 W.col(k).tail(rest).transpose();
    ++rank;
  }
  Eigen::VectorXd pb(rank);
  for (Eigen::Index i = 0; i < rank; ++i) pb(i) = b(perm[static_cast<std::size_t>(i)]);
  const auto L_top = W.topLeftCorner(rank, rank).triangularView<Eigen::Lower>();
  L_top.solveInPlace(pb);
  H_c->setZero(rank, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index cols = std::min<Eigen::Index>(i + 1, rank);
    H_c->col(perm[static_cast<std::size_t>(i)]).head(cols) = W.row(i).head(cols).transpose();
  }
  *r_c = std::move(pb);
}

}  // namespace vid::msckf
