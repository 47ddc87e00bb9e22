#pragma once
/// @file projection.h
/// @brief The MSCKF camera measurement model z = pi(R_IC^T (R_WI^T (p_W - p_WI) - p_IC)) in
/// normalized coordinates and its analytic Jacobians.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vid::msckf {

/// @brief Predicted measurement and Jacobians of one observation.
struct ProjectionJacobians {
  Eigen::Vector2d z = Eigen::Vector2d::Zero();   ///< (x/z, y/z)
  Eigen::Vector3d p_C = Eigen::Vector3d::Zero(); ///< point in the camera frame
  /// d z / d [dtheta_WI, dp_WI] (right perturbation of the clone)
  Eigen::Matrix<double, 2, 6> H_clone = Eigen::Matrix<double, 2, 6>::Zero();
  /// d z / d [dtheta_IC, dp_IC] (right perturbation of R_IC, additive p_IC)
  Eigen::Matrix<double, 2, 6> H_extrinsic = Eigen::Matrix<double, 2, 6>::Zero();
  /// d z / d p_W
  Eigen::Matrix<double, 2, 3> H_feature = Eigen::Matrix<double, 2, 3>::Zero();
};

/// @brief Project p_W into the camera (R_WI, p_WI, T_IC) and fill Jacobians evaluated at
/// exactly these values. Returns false if the point's depth is <= min_depth.
bool project_with_jacobians(const Eigen::Matrix3d& R_WI, const Eigen::Vector3d& p_WI,
                            const Eigen::Isometry3d& T_IC, const Eigen::Vector3d& p_W,
                            ProjectionJacobians* out, double min_depth = 1e-6);

/// @brief Projection only (no Jacobians); false if depth <= min_depth.
bool project_point(const Eigen::Matrix3d& R_WI, const Eigen::Vector3d& p_WI,
                   const Eigen::Isometry3d& T_IC, const Eigen::Vector3d& p_W,
                   Eigen::Vector2d* z, double min_depth = 1e-6);

}  // namespace vid::msckf
