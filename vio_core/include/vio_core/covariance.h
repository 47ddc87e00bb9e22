#pragma once
/// @file covariance.h
/// @brief The project's one covariance bookkeeping on a joint error-state covariance P whose
/// leading block is the propagated state and whose later blocks (clones, calibration) stay put
/// between updates: propagation of the leading block with its cross-covariances, stochastic
/// cloning (docs/model.md eq. (27)), marginalization and insertion of a variable. Used by vio_core's
/// FilterState and by the mass-identification window MSCKF (dynamics/massid).
///
/// Every function acts on the used top-left n x n part of P (n = `used`); P may be larger (the
/// window MSCKF keeps one allocation for its whole window).

#include <Eigen/Core>

namespace vid::covariance {

/// @brief Propagate the leading d x d block by Phi and add Q: P_xx <- Phi P_xx Phi^T + Q
/// (symmetrized), P_xr <- Phi P_xr for the rest r = [d, used) (clones, calibration are static).
/// Fixed-size Phi (e.g. the mass study's 10 x 10) keeps fixed-size products.
template <typename DerivedPhi, typename DerivedQ>
void propagate_leading(Eigen::MatrixXd& P, int used, const Eigen::MatrixBase<DerivedPhi>& Phi,
                       const Eigen::MatrixBase<DerivedQ>& Q) {
  constexpr int D = DerivedPhi::RowsAtCompileTime;
  using MatD = Eigen::Matrix<double, D, D>;
  const int d = static_cast<int>(Phi.rows());
  MatD P_xx;
  if constexpr (D != Eigen::Dynamic) {
    P_xx = Phi * P.template topLeftCorner<D, D>() * Phi.transpose();
  } else {
    P_xx = Phi * P.topLeftCorner(d, d) * Phi.transpose();
  }
  P_xx += Q;
  P.topLeftCorner(d, d) = 0.5 * (P_xx + P_xx.transpose());
  if (used > d) {
    const Eigen::Matrix<double, D, Eigen::Dynamic> P_xr = Phi * P.block(0, d, d, used - d);
    P.block(0, d, d, used - d) = P_xr;
    P.block(d, 0, used - d, d) = P_xr.transpose();
  }
}

/// @brief Stochastic cloning in place (docs/model.md eq. (27)): the error states [first, first + k) are
/// copied to [used, used + k) of P's storage, P_aug = [P, P J^T; J P, J P J^T] with J selecting
/// them. P must already hold used + k rows and columns.
inline void clone_into(Eigen::MatrixXd& P, int used, int first, int k) {
  P.block(used, 0, k, used) = P.block(first, 0, k, used);
  P.block(0, used, used, k) = P.block(0, first, used, k);
  P.block(used, used, k, k) = P.block(first, first, k, k);
}

/// @brief Stochastic cloning that grows P by k (P is exactly used x used before).
/// @return the clone's first column (the old dimension).
inline int append_clone(Eigen::MatrixXd& P, int first, int k) {
  const int n = static_cast<int>(P.rows());
  P.conservativeResize(n + k, n + k);
  clone_into(P, n, first, k);
  return n;
}

/// @brief A linear change of variables x_a <- x_a + g x_b for a k-vector variable at a and a
/// scalar variable at b (b outside [a, a + k)): P <- T P T^T with T = I + E_a g e_b^T. A clone
/// taken at an uncertain time (the camera-IMU time offset) is the clone plus its rate times the
/// offset's error.
inline void add_scaled(Eigen::MatrixXd& P, int a, const Eigen::VectorXd& g, int b) {
  const int k = static_cast<int>(g.size());
  const Eigen::RowVectorXd row_b = P.row(b);
  P.middleRows(a, k) += g * row_b;
  const Eigen::VectorXd col_b = P.col(b);  // after the row operation (T P, then (T P) T^T)
  P.middleCols(a, k) += col_b * g.transpose();
}

/// @brief Marginalize the variable at [at, at + k): drop its rows and columns (P shrinks by k;
/// the caller shifts the indices of the variables behind it).
inline void remove(Eigen::MatrixXd& P, int at, int k) {
  const int n = static_cast<int>(P.rows());
  const int tail = n - at - k;
  Eigen::MatrixXd P_new(n - k, n - k);
  P_new.topLeftCorner(at, at) = P.topLeftCorner(at, at);
  P_new.topRightCorner(at, tail) = P.topRightCorner(at, tail);
  P_new.bottomLeftCorner(tail, at) = P.bottomLeftCorner(tail, at);
  P_new.bottomRightCorner(tail, tail) = P.bottomRightCorner(tail, tail);
  P.swap(P_new);
}

/// @brief Insert an uncorrelated variable with covariance cov at [at, at + cov.rows()) (P grows;
/// the caller shifts the indices of the variables behind it).
inline void insert(Eigen::MatrixXd& P, int at, const Eigen::MatrixXd& cov) {
  const int n = static_cast<int>(P.rows());
  const int k = static_cast<int>(cov.rows());
  const int tail = n - at;
  Eigen::MatrixXd P_new = Eigen::MatrixXd::Zero(n + k, n + k);
  P_new.topLeftCorner(at, at) = P.topLeftCorner(at, at);
  P_new.topRightCorner(at, tail) = P.topRightCorner(at, tail);
  P_new.bottomLeftCorner(tail, at) = P.bottomLeftCorner(tail, at);
  P_new.bottomRightCorner(tail, tail) = P.bottomRightCorner(tail, tail);
  P_new.block(at, at, k, k) = cov;
  P.swap(P_new);
}

}  // namespace vid::covariance
