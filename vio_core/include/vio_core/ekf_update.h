#pragma once
/// @file ekf_update.h
/// @brief EKF measurement updates on FilterState: a generic update (H, r, R) that exploits
/// H's column sparsity, and the accelerometer update of dynamics mode
/// (a_m = T_m + F_ext + b_a + n_a; H touches only the b_a and F_ext columns, O(n^2)).

#include <Eigen/Core>
#include <vector>

#include "vio_core/state.h"

namespace vid {

/// @brief Outcome of one update.
struct UpdateResult {
  bool applied = false;     ///< false if gated out or degenerate
  double chi2 = 0.0;        ///< r^T S^-1 r
  double threshold = 0.0;   ///< gating threshold used (0 = no gating)
};

/// @brief Generic EKF update with H of size (m x dim) and noise covariance R (m x m).
/// Only columns of H with a non-zero entry take part in P H^T (structure of H is used).
/// P is updated as P - K S K^T and symmetrized. chi2_threshold <= 0 disables gating.
UpdateResult ekf_update(FilterState& state, const Eigen::MatrixXd& H, const Eigen::VectorXd& r,
                        const Eigen::MatrixXd& R, double chi2_threshold = 0.0);

/// @brief Same with H given only on the listed columns (H_cols is m x cols.size()).
UpdateResult ekf_update_columns(FilterState& state, const std::vector<int>& cols,
                                const Eigen::MatrixXd& H_cols, const Eigen::VectorXd& r,
                                const Eigen::MatrixXd& R, double chi2_threshold = 0.0);

/// @brief Predicted accelerometer reading of dynamics mode: T_m + F_ext + b_a.
Eigen::Vector3d predict_accel(const ImuState& x, const Eigen::Vector3d& T_m);

/// @brief Accelerometer update (dynamics mode) with isotropic discrete noise variance
/// noise_var [(m/s^2)^2]. O(n^2): P H^T is the sum of the b_a and F_ext column blocks.
UpdateResult accel_update(FilterState& state, const Eigen::Vector3d& a_m, const Eigen::Vector3d& T_m,
                          double noise_var, double chi2_threshold);

/// @brief 0.95 / 0.99 quantiles of chi2 with dof degrees of freedom (Wilson-Hilferty for
/// large dof, table for dof <= 10).
double chi2_quantile(int dof, double prob);

}  // namespace vid
