/// @file force_output.cpp
/// @brief Reported force = force state (+ body drag), first-order covariance in both frames.
#include "vio_core/force_output.h"

#include "geometry/so3.h"

namespace vid {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// Without drag: the state's block as it is, the other frame through J = [d/dtheta, d/dF].
ForceEstimate without_drag(const FilterState& state) {
  ForceEstimate f;
  const ImuState& x = state.imu();
  const ForceFrame frame = state.force_frame();
  f.F_I = force_in_body(x, frame);
  f.F_W = force_in_world(x, frame);
  const Matrix3d R = x.T_WI.q.toRotationMatrix();
  Eigen::Matrix<double, 3, 6> J;
  if (frame == ForceFrame::kBody) {
    J << -R * so3::skew(f.F_I), R;
  } else {
    J << so3::skew(f.F_I), R.transpose();
  }
  const Eigen::MatrixXd& P = state.P();
  Eigen::Matrix<double, 6, 6> P_tf;
  P_tf << P.block<3, 3>(imu_idx::kTheta, imu_idx::kTheta), P.block<3, 3>(imu_idx::kTheta, imu_idx::kF),
      P.block<3, 3>(imu_idx::kF, imu_idx::kTheta), P.block<3, 3>(imu_idx::kF, imu_idx::kF);
  const Matrix3d P_F = P.block<3, 3>(imu_idx::kF, imu_idx::kF);
  const Matrix3d P_other = J * P_tf * J.transpose();
  f.cov_F_I = frame == ForceFrame::kBody ? P_F : P_other;
  f.cov_F_W = frame == ForceFrame::kWorld ? P_F : P_other;
  return f;
}

// With drag d_I = -D u, u = R^T v: F_I = F_state,I + d_I and F_W = R F_I, both through
// J = [d/dtheta, d/dv, d/dF] (u = u_hat + [u_hat]x dtheta).
ForceEstimate with_drag(const FilterState& state) {
  ForceEstimate f;
  const ImuState& x = state.imu();
  const ForceFrame frame = state.force_frame();
  const Eigen::DiagonalMatrix<double, 3> D(state.linear_drag());
  const Matrix3d R = x.T_WI.q.toRotationMatrix();
  const Vector3d u = R.transpose() * x.v_WI;
  f.F_drag_I = drag_in_body(x, state.linear_drag());
  f.F_I = force_in_body(x, frame) + f.F_drag_I;
  f.F_W = R * f.F_I;
  const Matrix3d dI_dtheta_drag = -(D * so3::skew(u));
  const Matrix3d dI_dv = -(D * R.transpose());
  Eigen::Matrix<double, 3, 9> J_I, J_W;  // columns: theta, v, F
  if (frame == ForceFrame::kBody) {
    J_I << dI_dtheta_drag, dI_dv, Matrix3d::Identity();
  } else {
    J_I << so3::skew(R.transpose() * x.F_ext) + dI_dtheta_drag, dI_dv, R.transpose();
  }
  // F_W = R Exp(dtheta) F_I(dtheta): d/dtheta = -R [F_I]x + R dF_I/dtheta; the rest through R.
  J_W = R * J_I;
  J_W.leftCols<3>() -= R * so3::skew(f.F_I);
  const int blocks[3] = {imu_idx::kTheta, imu_idx::kV, imu_idx::kF};
  Eigen::Matrix<double, 9, 9> P_s;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) P_s.block<3, 3>(3 * a, 3 * b) = state.P().block<3, 3>(blocks[a], blocks[b]);
  f.cov_F_I = J_I * P_s * J_I.transpose();
  f.cov_F_W = J_W * P_s * J_W.transpose();
  return f;
}

}  // namespace

ForceEstimate force_output(const FilterState& state) {
  return state.with_drag() ? with_drag(state) : without_drag(state);
}

}  // namespace vid
