#pragma once
/// @file linear_algebra.h
/// @brief MSCKF linear-algebra steps: left-nullspace projection of a feature Jacobian,
/// QR measurement compression (the gate's quantile is vio_core/chi2.h).

#include <Eigen/Core>
#include <Eigen/QR>

namespace vid::msckf {

/// @brief Project H_x and r onto the left nullspace of H_f (m x 3, full column rank):
/// with H_f = Q [R; 0], keep the last m-3 rows of Q^T H_x and Q^T r (Householder).
/// If S is non-null (m x m, symmetric), it becomes Q2^T S Q2 ((m-3) x (m-3)).
/// Throws std::invalid_argument if H_f has fewer than 4 rows or not 3 columns.
void nullspace_project(const Eigen::MatrixXd& H_f, Eigen::MatrixXd* H_x, Eigen::VectorXd* r,
                       Eigen::MatrixXd* S = nullptr);

/// @brief The same left-nullspace projection as nullspace_project, split so that one
/// factorization of H_f serves several operands without temporaries: compute() factors H_f
/// (m x 3, m >= 4) into three Householder reflectors, apply() forms Q^T X in place.
class NullspaceProjector {
 public:
  /// @brief Factor H_f. Throws std::invalid_argument unless H_f is m x 3 with m >= 4.
  void compute(const Eigen::Ref<const Eigen::MatrixXd>& H_f);
  /// @brief Rows of H_f (m).
  Eigen::Index rows() const { return qr_.rows(); }
  /// @brief X (m rows) <- Q^T X; the nullspace part is X.bottomRows(m - 3).
  void apply(Eigen::Ref<Eigen::MatrixXd> X);

 private:
  Eigen::HouseholderQR<Eigen::MatrixXd> qr_;
  Eigen::VectorXd work_;
};

/// @brief MSCKF gate statistic of the left-nullspace projected residual without projecting:
/// r_o^T (Q2^T S Q2)^-1 r_o (r_o = Q2^T r, Q2 spanning the left nullspace of H_f) equals
/// min_x |y - Y x|^2 with S = L L^T, y = L^-1 r, Y = L^-1 H_f, because
/// Q2 (Q2^T S Q2)^-1 Q2^T = S^-1 - S^-1 H_f (H_f^T S^-1 H_f)^-1 H_f^T S^-1.
/// Costs one m x m Cholesky with four right-hand sides and a QR of m x 4, instead of three
/// two-sided reflections of S and an (m-3) x (m-3) Cholesky.
class ProjectedChi2 {
 public:
  /// @brief S (m x m, symmetric positive definite; only its lower triangle is read), H_f
  /// m x 3 (m >= 4), r m x 1. Returns false (chi2 untouched) if S is not numerically
  /// positive definite. Throws std::invalid_argument on bad shapes.
  bool compute(const Eigen::Ref<const Eigen::MatrixXd>& S,
               const Eigen::Ref<const Eigen::MatrixXd>& H_f,
               const Eigen::Ref<const Eigen::VectorXd>& r, double* chi2);

 private:
  /// [S; H_f^T; r^T] ((m + 4) x m), factored in place: [L; (L^-1 H_f)^T; (L^-1 r)^T]
  Eigen::MatrixXd W_;
  Eigen::Matrix<double, Eigen::Dynamic, 4> B_;  ///< [L^-1 H_f, L^-1 r]
  Eigen::HouseholderQR<Eigen::Matrix<double, Eigen::Dynamic, 4>> qr_;
};

/// @brief Replace (H, r) (m x n) by (R, Q1^T r) with min(m, n) rows, H = Q R (Householder).
/// Keeps H^T H and H^T r unchanged. No-op when m <= n.
void compress_qr(Eigen::MatrixXd* H, Eigen::VectorXd* r);

/// @brief From normal equations A = H^T H (symmetric positive semi-definite) and b = H^T r,
/// build (H_c, r_c) with H_c^T H_c = A and H_c^T r_c = b by pivoted Cholesky (complete
/// diagonal pivoting) stopped at the numerical rank (remaining pivots <= rel_tol * max diag
/// of A), so H_c has rank rows and b must lie in the range of A (it does when it came from
/// the same H).
void factor_normal_equations(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                             Eigen::MatrixXd* H_c, Eigen::VectorXd* r_c,
                             double rel_tol = 1e-12);

}  // namespace vid::msckf
