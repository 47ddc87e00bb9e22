#pragma once
/// @file ekf_update.h
/// @brief EKF measurement updates on FilterState: a generic update (H, r, R) that exploits
/// H's column sparsity, and the accelerometer update of dynamics mode
/// (a_m = s T_m + F_ext + b_a + n_a, plus the body drag -D R^T v when the state has one; H touches
/// only the b_a and F_ext columns (with drag: v and theta), and the thrust scale s when it is
/// estimated, O(n^2)).

#include <Eigen/Core>
#include <vector>

#include "vio_core/accel_innovation.h"
#include "vio_core/state.h"

namespace vid {

/// @brief Outcome of one update.
struct UpdateResult {
  bool applied = false;     ///< false if gated out or degenerate
  double chi2 = 0.0;        ///< r^T S^-1 r
  double threshold = 0.0;   ///< gating threshold used (0 = no gating)
  bool downweighted = false;  ///< past the gate but applied with S scaled by chi2 / threshold
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

/// @brief Predicted accelerometer reading of dynamics mode (docs/model.md eq. (14)): s T_m + F_I + b_a, with
/// F_I = R_WI^T F_W in the world-frame force model and s = x.thrust_scale (1 when not estimated).
/// A non-zero linear_drag D adds the body drag -diag(D) R_WI^T v_WI (docs/design.md §3).
Eigen::Vector3d predict_accel(const ImuState& x, const Eigen::Vector3d& T_m,
                              ForceFrame frame = ForceFrame::kBody,
                              const Eigen::Vector3d& linear_drag = Eigen::Vector3d::Zero());

/// @brief Jacobian of the drag term -diag(D) R_WI^T v_WI of predict_accel (current estimate).
struct DragJacobian {
  Eigen::Matrix3d H_theta;  ///< d h / d dtheta = -D [R^T v]x
  Eigen::Matrix3d H_v;      ///< d h / d v_WI = -D R^T
};
DragJacobian drag_jacobian(const ImuState& x, const Eigen::Vector3d& linear_drag);

/// @brief Non-trivial blocks of the accelerometer measurement Jacobian; H_ba is always I.
struct AccelJacobian {
  Eigen::Matrix3d H_theta;  ///< d h / d dtheta (zero for a body-frame force)
  Eigen::Matrix3d H_F;      ///< d h / d dF_ext (I for a body-frame force, R_WI^T for world)
};

/// @brief Jacobian of predict_accel at x, with the rotation taken at q_WI_lin (the first
/// estimate, for observability consistency; pass x.T_WI.q for the exact Jacobian).
AccelJacobian accel_jacobian(const ImuState& x, const Eigen::Quaterniond& q_WI_lin, ForceFrame frame);

/// @brief Accelerometer update (dynamics mode) with isotropic discrete noise variance
/// noise_var [(m/s^2)^2]. O(n^2): H touches only the b_a and F_ext columns (and the
/// orientation columns in the world-frame force model), so P H^T is a few n x 3 blocks.
/// @param info if given: the innovation, its covariance and the measurement in the force
/// frame, and the IMU-block correction applied (for ForceJumpDetector / apply_force_jump).
/// @param downweight a sample past the gate is applied with its innovation covariance scaled
/// by chi2 / threshold (the measurement noise inflated to R + (k - 1) S, Huber-like: its
/// normalized innovation and so its influence is held at the gate's) instead of dropped.
UpdateResult accel_update(FilterState& state, const Eigen::Vector3d& a_m, const Eigen::Vector3d& T_m,
                          double noise_var, double chi2_threshold, AccelInnovation* info = nullptr,
                          bool downweight = false);
/// @brief The same with a diagonal noise variance per IMU axis (the vibration-aware noise,
/// vio_core/accel_noise.h).
UpdateResult accel_update(FilterState& state, const Eigen::Vector3d& a_m, const Eigen::Vector3d& T_m,
                          const Eigen::Vector3d& noise_var_I, double chi2_threshold,
                          AccelInnovation* info = nullptr, bool downweight = false);

}  // namespace vid
