/// @file projection.cpp
/// @brief Camera measurement model in normalized coordinates and its analytic Jacobians.

#include "vio_core/msckf/projection.h"

#include "geometry/so3.h"

namespace vid::msckf {

bool project_point(const Eigen::Matrix3d& R_WI, const Eigen::Vector3d& p_WI,
                   const Eigen::Isometry3d& T_IC, const Eigen::Vector3d& p_W,
                   Eigen::Vector2d* z, double min_depth) {
  const Eigen::Vector3d p_I = R_WI.transpose() * (p_W - p_WI);
  const Eigen::Vector3d p_C = T_IC.linear().transpose() * (p_I - T_IC.translation());
  if (!(p_C.z() > min_depth)) return false;
  *z = p_C.head<2>() / p_C.z();
  return true;
}

bool project_with_jacobians(const Eigen::Matrix3d& R_WI, const Eigen::Vector3d& p_WI,
                            const Eigen::Isometry3d& T_IC, const Eigen::Vector3d& p_W,
                            ProjectionJacobians* out, double min_depth) {
  const Eigen::Matrix3d R_CI = T_IC.linear().transpose();
  const Eigen::Matrix3d R_IW = R_WI.transpose();
  const Eigen::Vector3d p_I = R_IW * (p_W - p_WI);
  const Eigen::Vector3d p_C = R_CI * (p_I - T_IC.translation());
  if (!(p_C.z() > min_depth)) return false;
  const double inv_z = 1.0 / p_C.z();
  out->p_C = p_C;
  out->z = p_C.head<2>() * inv_z;

  // d z / d p_C of the pinhole division.
  Eigen::Matrix<double, 2, 3> dz_dpc;
  dz_dpc << inv_z, 0.0, -out->z.x() * inv_z, 0.0, inv_z, -out->z.y() * inv_z;

  // Right perturbation: R^T Exp(-dtheta) ... gives +[p]x dtheta for both rotations.
  const Eigen::Matrix<double, 2, 3> dz_dpi = dz_dpc * R_CI;
  out->H_clone.leftCols<3>() = dz_dpi * so3::skew(p_I);
  out->H_clone.rightCols<3>() = -dz_dpi * R_IW;
  out->H_extrinsic.leftCols<3>() = dz_dpc * so3::skew(p_C);
  out->H_extrinsic.rightCols<3>() = -dz_dpi;
  out->H_feature = dz_dpi * R_IW;
  return true;
}

}  // namespace vid::msckf
