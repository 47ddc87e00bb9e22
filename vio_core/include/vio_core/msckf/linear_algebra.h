#pragma once
/// @file linear_algebra.h
/// @brief MSCKF linear-algebra steps: left-nullspace projection of a feature Jacobian,
/// QR measurement compression, and the chi2 quantile used by the gate.

#include <Eigen/Core>

namespace vid::msckf {

/// @brief Project H_x and r onto the left nullspace of H_f (m x 3, full column rank):
/// with H_f = Q [R; 0], keep the last m-3 rows of Q^T H_x and Q^T r (Householder).
/// If S is non-null (m x m, symmetric), it becomes Q2^T S Q2 ((m-3) x (m-3)).
/// Throws std::invalid_argument if H_f has fewer than 4 rows or not 3 columns.
void nullspace_project(const Eigen::MatrixXd& H_f, Eigen::MatrixXd* H_x, Eigen::VectorXd* r,
                       Eigen::MatrixXd* S = nullptr);

/// @brief Replace (H, r) (m x n) by (R, Q1^T r) with min(m, n) rows, H = Q R (Householder).
/// Keeps H^T H and H^T r unchanged. No-op when m <= n.
void compress_qr(Eigen::MatrixXd* H, Eigen::VectorXd* r);

/// @brief chi2 quantile: x with P(chi2_dof <= x) = p (0 < p < 1, dof >= 1).
double chi2_quantile(double p, int dof);

/// @brief chi2 95% quantile, cached for small dof.
double chi2_95(int dof);

}  // namespace vid::msckf
