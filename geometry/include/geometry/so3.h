#pragma once
/// @file so3.h
/// @brief SO(3) and unit-quaternion helpers (Hamilton, right perturbation, docs/design.md §3):
/// R = R_hat * Exp(dtheta), q = q_hat ⊗ exp(dtheta / 2). All functions are accurate for
/// angles near 0 (series expansions) and near pi (quaternion-based logarithm).

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vid::so3 {

/// @brief Skew-symmetric matrix [w]x with [w]x v = w x v.
Eigen::Matrix3d skew(const Eigen::Vector3d& w);

/// @brief Inverse of skew: the vector of a (nearly) skew-symmetric matrix (antisymmetric part).
Eigen::Vector3d vee(const Eigen::Matrix3d& W);

/// @brief Exponential map so(3) -> SO(3) (Rodrigues), rotation vector phi [rad].
Eigen::Matrix3d exp(const Eigen::Vector3d& phi);

/// @brief Logarithm SO(3) -> so(3), angle in [0, pi]. R need not be exactly orthonormal
/// (it is projected through a normalized quaternion).
Eigen::Vector3d log(const Eigen::Matrix3d& R);

/// @brief Unit quaternion of a rotation vector: q = [cos(|phi|/2), sin(|phi|/2) phi/|phi|].
Eigen::Quaterniond quat_exp(const Eigen::Vector3d& phi);

/// @brief Rotation vector of a unit quaternion (q and -q give the same result), angle in [0, pi].
Eigen::Vector3d quat_log(const Eigen::Quaterniond& q);

/// @brief Right Jacobian: Exp(phi + d) ≈ Exp(phi) Exp(Jr(phi) d).
Eigen::Matrix3d right_jacobian(const Eigen::Vector3d& phi);

/// @brief Left Jacobian: Exp(phi + d) ≈ Exp(Jl(phi) d) Exp(phi); Jl(phi) = Jr(-phi).
Eigen::Matrix3d left_jacobian(const Eigen::Vector3d& phi);

/// @brief Inverse of the right Jacobian: Log(Exp(phi) Exp(d)) ≈ phi + Jr^-1(phi) d.
/// Singular only at |phi| = 2 pi (never reached for phi from log()).
Eigen::Matrix3d right_jacobian_inv(const Eigen::Vector3d& phi);

/// @brief Inverse of the left Jacobian: Log(Exp(d) Exp(phi)) ≈ phi + Jl^-1(phi) d.
Eigen::Matrix3d left_jacobian_inv(const Eigen::Vector3d& phi);

/// @brief Right perturbation on quaternions: q ⊗ exp(delta / 2), normalized.
Eigen::Quaterniond boxplus(const Eigen::Quaterniond& q, const Eigen::Vector3d& delta);

/// @brief Inverse of boxplus: delta with boxplus(q0, delta) = q1, i.e. Log(q0^-1 ⊗ q1).
Eigen::Vector3d boxminus(const Eigen::Quaterniond& q1, const Eigen::Quaterniond& q0);

/// @brief Normalized copy with non-negative scalar part (canonical sign).
Eigen::Quaterniond normalized(const Eigen::Quaterniond& q);

/// @brief Project a nearly-orthonormal matrix onto SO(3) (via quaternion).
Eigen::Matrix3d orthonormalized(const Eigen::Matrix3d& R);

}  // namespace vid::so3
