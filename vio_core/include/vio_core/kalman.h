#pragma once
/// @file kalman.h
/// @brief The project's one Kalman correction (docs/model.md eqs. (17)-(18); also for stacked
/// clones, eq. (51), and sigma-point moments, eq. (54)), for fixed- and dynamic-size matrices. Every filter uses it: vio_core's
/// EKF updates (ekf_update.h: visual, accelerometer, zero-velocity, force-jump) and the
/// mass-identification EKF, UKF and window MSCKF (dynamics/massid).
///
/// Whitened form: with the innovation covariance S = L L^T and W = P_xy L^-T, the correction is
/// K r = W (L^-1 r) and the covariance decrease K S K^T = W W^T. One Cholesky factor and two
/// triangular solves give the gate statistic, the correction and the new covariance; P - W W^T
/// equals the Joseph form (I - K H) P (I - K H)^T + K R K^T for this (optimal) gain and is
/// symmetric by construction, at a third of the Joseph form's products.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>

namespace vid {

/// @brief Cholesky factor of an innovation covariance S and the whitened innovation L^-1 r.
/// @tparam M measurement dimension (Eigen::Dynamic allowed).
template <int M>
class InnovationFactor {
 public:
  using MatM = Eigen::Matrix<double, M, M>;
  using VecM = Eigen::Matrix<double, M, 1>;

  /// @brief Factor S = L L^T and whiten r. @return false when S is not positive definite
  /// (nothing else may then be used).
  bool compute(const MatM& S, const VecM& r) {
    llt_.compute(S);
    if (llt_.info() != Eigen::Success) return false;
    z_ = llt_.matrixL().solve(r);
    scale_ = 1.0;
    return true;
  }

  /// @brief Gate statistic r^T S^-1 r (chi-square with M degrees of freedom under the model;
  /// of k S after inflate(k)).
  double chi2() const { return z_.squaredNorm(); }

  /// @brief True when a gate is set (threshold > 0) and chi2 is past it (or not a number).
  bool past_gate(double threshold) const { return threshold > 0.0 && !(chi2() <= threshold); }

  /// @brief Use k S in place of S from here on (k >= 1: an outlier's influence held at the
  /// gate's, Huber-like). Exact: the factor of k S is sqrt(k) L.
  void inflate(double k) {
    const double s = 1.0 / std::sqrt(k);
    z_ *= s;
    scale_ *= s;
  }

  /// @brief L^-1 r (of k S after inflate(k)).
  const VecM& whitened_innovation() const { return z_; }

  /// @brief *W = P_xy L^-T, the whitened gain (n x M): K r = W z, K S K^T = W W^T.
  /// @param W a plain matrix; its storage is reused when its size already fits.
  template <typename DerivedPxy, typename MatW>
  void whitened_gain(const Eigen::MatrixBase<DerivedPxy>& P_xy, MatW* W) const {
    *W = llt_.matrixL().solve(P_xy.transpose()).transpose();
    if (scale_ != 1.0) *W *= scale_;
  }

 private:
  Eigen::LLT<MatM> llt_;
  VecM z_;
  double scale_ = 1.0;  ///< 1 / sqrt(k) after inflate(k)
};

/// @brief P <- P - W W^T with P kept symmetric (the covariance decrease of a Kalman update).
/// Fixed sizes use an unrolled product; a dynamic P with three gain columns (the accelerometer
/// update, at IMU rate) one fused pass per column; wider gains a symmetric rank update of the
/// lower triangle mirrored to the upper one.
template <typename DerivedP, typename DerivedW>
void subtract_outer(Eigen::MatrixBase<DerivedP>& P, const Eigen::MatrixBase<DerivedW>& W) {
  if constexpr (DerivedP::RowsAtCompileTime != Eigen::Dynamic) {
    P.noalias() -= W.lazyProduct(W.transpose());  // small fixed size: no blocked GEMM
    P = (0.5 * (P + P.transpose())).eval();
  } else if (W.cols() == 3) {
    // Element (i, j) and (j, i) get the same three products in the same order: exactly symmetric.
    const auto w0 = W.col(0);
    const auto w1 = W.col(1);
    const auto w2 = W.col(2);
    for (Eigen::Index j = 0; j < P.cols(); ++j) {
      P.col(j) -= w0 * W(j, 0) + w1 * W(j, 1) + w2 * W(j, 2);
    }
  } else {
    P.template selfadjointView<Eigen::Lower>().rankUpdate(W, -1.0);
    P.template triangularView<Eigen::StrictlyUpper>() = P.transpose();
  }
}

/// @brief One whole Kalman correction on a plain covariance: with the state-measurement
/// cross-covariance P_xy and the innovation covariance S of residual r, *dx = K r and
/// P <- P - K S K^T (docs/model.md eq. (17)).
/// @return false (P unchanged, dx zero) when S is not positive definite.
template <typename DerivedP, typename DerivedPxy, int M, typename VecX>
bool kalman_correct(Eigen::MatrixBase<DerivedP>& P, const Eigen::MatrixBase<DerivedPxy>& P_xy,
                    const Eigen::Matrix<double, M, M>& S, const Eigen::Matrix<double, M, 1>& r,
                    VecX* dx) {
  InnovationFactor<M> f;
  if (!f.compute(S, r)) {
    dx->setZero(P.rows());
    return false;
  }
  Eigen::Matrix<double, DerivedPxy::RowsAtCompileTime, M> W;
  f.whitened_gain(P_xy, &W);
  *dx = W * f.whitened_innovation();
  subtract_outer(P, W);
  return true;
}

}  // namespace vid
