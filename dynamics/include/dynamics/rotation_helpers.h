#pragma once
/// @file rotation_helpers.h
/// @brief Minimal rotation helpers for the vehicle model (vio_core/so3.h is the project's
/// SO(3) library; these few functions keep vid_dynamics free of a vio_core dependency).

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vid::dynamics {

/// @brief Skew-symmetric matrix [v]x such that [v]x w = v x w.
Eigen::Matrix3d skew(const Eigen::Vector3d& v);

/// @brief Unit quaternion exp(theta/2) of a rotation vector (Hamilton).
Eigen::Quaterniond quat_exp(const Eigen::Vector3d& theta);

/// @brief Rotation vector of a rotation matrix (inverse of Exp), angle in [0, pi].
Eigen::Vector3d rot_log(const Eigen::Matrix3d& R);

/// @brief vee of a skew-symmetric matrix.
Eigen::Vector3d vee(const Eigen::Matrix3d& S);

}  // namespace vid::dynamics
