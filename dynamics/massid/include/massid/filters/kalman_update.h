#pragma once
/// @file kalman_update.h
/// @brief Fixed-size Kalman correction on a plain (x, P) pair (seed eqs. 6-8), shared by the
/// EKF (Pxy = P H^T, Pyy = H P H^T + R) and the UKF (sigma-point moments, eq. 17).
///
/// vio_core's ekf_update() works on vio::FilterState, whose IMU block has no mass slot and whose
/// clones hold [theta, p] only; the mass-id states are small fixed-size vectors, so this is the
/// small generic helper vio_core lacks (same algebra: K = Pxy Pyy^-1, P -= K Pyy K^T).

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace vid::massid {

/// @brief Correction dx = K r with K = Pxy Pyy^-1, and P <- P - K Pyy K^T (symmetrized).
/// @return false (P unchanged, dx zero) when Pyy is not positive definite.
template <int N, int M>
bool kalman_correct(Eigen::Matrix<double, N, N>& P, const Eigen::Matrix<double, N, M>& Pxy,
                    const Eigen::Matrix<double, M, M>& Pyy, const Eigen::Matrix<double, M, 1>& r,
                    Eigen::Matrix<double, N, 1>* dx) {
  Eigen::LLT<Eigen::Matrix<double, M, M>> llt(Pyy);
  if (llt.info() != Eigen::Success) {
    dx->setZero();
    return false;
  }
  // W = Pxy L^-T: K r = W L^-1 r, K Pyy K^T = W W^T.
  const Eigen::Matrix<double, N, M> W =
      llt.matrixL().solve(Pxy.transpose()).transpose();
  *dx = W * llt.matrixL().solve(r);
  P.noalias() -= W.lazyProduct(W.transpose());  // small fixed size: no blocked GEMM
  P = 0.5 * (P + P.transpose()).eval();
  return true;
}

/// @brief EKF correction (eqs. 6-8) with measurement Jacobian H and noise R.
template <int N, int M>
bool ekf_correct(Eigen::Matrix<double, N, N>& P, const Eigen::Matrix<double, M, N>& H,
                 const Eigen::Matrix<double, M, 1>& r, const Eigen::Matrix<double, M, M>& R,
                 Eigen::Matrix<double, N, 1>* dx) {
  const Eigen::Matrix<double, N, M> PHt = P * H.transpose();
  Eigen::Matrix<double, M, M> S = H * PHt + R;
  S = 0.5 * (S + S.transpose()).eval();
  return kalman_correct<N, M>(P, PHt, S, r, dx);
}

}  // namespace vid::massid
