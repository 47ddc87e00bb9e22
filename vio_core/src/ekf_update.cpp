/// @file ekf_update.cpp
/// @brief EKF updates exploiting measurement-Jacobian column sparsity.
#include "vio_core/ekf_update.h"

#include <cmath>
#include <optional>
#include <stdexcept>

#include "geometry/so3.h"
#include "vio_core/kalman.h"

namespace vid {

UpdateResult ekf_update_columns(FilterState& state, const std::vector<int>& cols,
                                const Eigen::MatrixXd& H_cols, const Eigen::VectorXd& r,
                                const Eigen::MatrixXd& R, double chi2_threshold) {
  UpdateResult res;
  const int m = static_cast<int>(r.size());
  if (m == 0) return res;
  Eigen::MatrixXd& P = state.P();
  const int n = state.dim();
  const int k = static_cast<int>(cols.size());
  // P H^T = P[:, cols] H_cols^T  (n x m)
  Eigen::MatrixXd P_cols(n, k);
  for (int j = 0; j < k; ++j) P_cols.col(j) = P.col(cols[j]);
  const Eigen::MatrixXd PHt = P_cols * H_cols.transpose();
  Eigen::MatrixXd HPHt(m, m);
  {
    Eigen::MatrixXd PHt_rows(k, m);
    for (int j = 0; j < k; ++j) PHt_rows.row(j) = PHt.row(cols[j]);
    HPHt = H_cols * PHt_rows;
  }
  const Eigen::MatrixXd S = 0.5 * (HPHt + HPHt.transpose()) + R;
  InnovationFactor<Eigen::Dynamic> f;
  if (!f.compute(S, r)) return res;
  res.chi2 = f.chi2();
  res.threshold = chi2_threshold;
  if (f.past_gate(chi2_threshold)) return res;
  Eigen::MatrixXd W;
  f.whitened_gain(PHt, &W);
  state.apply_correction(W * f.whitened_innovation());
  subtract_outer(P, W);
  res.applied = true;
  return res;
}

UpdateResult ekf_update(FilterState& state, const Eigen::MatrixXd& H, const Eigen::VectorXd& r,
                        const Eigen::MatrixXd& R, double chi2_threshold) {
  if (H.cols() != state.dim() || H.rows() != r.size() || R.rows() != r.size()) {
    throw std::invalid_argument("ekf_update: H is " + std::to_string(H.rows()) + "x" +
                                std::to_string(H.cols()) + ", r has " +
                                std::to_string(r.size()) + " rows, state dim " +
                                std::to_string(state.dim()));
  }
  std::vector<int> cols;
  for (int j = 0; j < H.cols(); ++j) {
    if (H.col(j).cwiseAbs().maxCoeff() > 0.0) cols.push_back(j);
  }
  Eigen::MatrixXd H_cols(H.rows(), static_cast<int>(cols.size()));
  for (std::size_t j = 0; j < cols.size(); ++j) H_cols.col(static_cast<int>(j)) = H.col(cols[j]);
  return ekf_update_columns(state, cols, H_cols, r, R, chi2_threshold);
}

Eigen::Vector3d predict_accel(const ImuState& x, const Eigen::Vector3d& T_m, ForceFrame frame,
                              const Eigen::Vector3d& linear_drag) {
  const Eigen::Vector3d a = x.thrust_scale * T_m + force_in_body(x, frame) + x.b_a;
  return linear_drag.isZero(0.0) ? a : Eigen::Vector3d(a + drag_in_body(x, linear_drag));
}

AccelJacobian accel_jacobian(const ImuState& x, const Eigen::Quaterniond& q_WI_lin, ForceFrame frame) {
  AccelJacobian J;
  if (frame == ForceFrame::kBody) {
    J.H_F.setIdentity();
    J.H_theta.setZero();
  } else {
    // h = T_m + (R Exp(dtheta))^T F_W + b_a = T_m + R^T F_W + [R^T F_W]x dtheta + ...
    const Eigen::Matrix3d R = q_WI_lin.toRotationMatrix();
    J.H_F = R.transpose();
    J.H_theta = so3::skew(R.transpose() * x.F_ext);
  }
  return J;
}

DragJacobian drag_jacobian(const ImuState& x, const Eigen::Vector3d& linear_drag) {
  // h_drag = -D u with u = R^T v and R = R_hat Exp(dtheta): u = u_hat + [u_hat]x dtheta.
  const Eigen::DiagonalMatrix<double, 3> D(linear_drag);
  const Eigen::Matrix3d R = x.T_WI.q.toRotationMatrix();
  DragJacobian J;
  J.H_v = -(D * R.transpose());
  J.H_theta = -(D * so3::skew(R.transpose() * x.v_WI));
  return J;
}

namespace {
// P H^T of the drag's rows: the velocity and orientation columns of P.
void add_drag_columns(const Eigen::MatrixXd& P, const DragJacobian& J, Eigen::MatrixXd* PHt) {
  PHt->noalias() += P.middleCols<3>(imu_idx::kV) * J.H_v.transpose();
  PHt->noalias() += P.middleCols<3>(imu_idx::kTheta) * J.H_theta.transpose();
}
}  // namespace

UpdateResult accel_update(FilterState& state, const Eigen::Vector3d& a_m, const Eigen::Vector3d& T_m,
                          double noise_var, double chi2_threshold, AccelInnovation* info, bool downweight) {
  return accel_update(state, a_m, T_m, Eigen::Vector3d::Constant(noise_var), chi2_threshold, info, downweight);
}

UpdateResult accel_update(FilterState& state, const Eigen::Vector3d& a_m, const Eigen::Vector3d& T_m,
                          const Eigen::Vector3d& noise_var, double chi2_threshold, AccelInnovation* info,
                          bool downweight) {
  if (!state.with_force()) throw std::logic_error("accel_update needs the F_ext state (dynamics mode)");
  UpdateResult res;
  Eigen::MatrixXd& P = state.P();
  thread_local Eigen::MatrixXd PHt;
  // H = [H_theta (world force only) | I at b_a | H_F at F_ext | T_m at s (if estimated)]:
  // P H^T from those columns of P, then S = H (P H^T) from the same rows.
  const int is = state.with_thrust_scale() ? state.layout().thrust_scale_index() : -1;
  const std::optional<DragJacobian> drag =
      state.with_drag() ? std::optional<DragJacobian>(drag_jacobian(state.imu(), state.linear_drag())) : std::nullopt;
  const Eigen::Vector3d D = drag ? state.linear_drag() : Eigen::Vector3d::Zero();
  Eigen::Matrix3d S;
  if (state.force_frame() == ForceFrame::kBody) {
    // H_F = I, H_theta = 0.
    PHt = P.middleCols<3>(imu_idx::kBa) + P.middleCols<3>(imu_idx::kF);
    if (is >= 0) PHt.noalias() += P.col(is) * T_m.transpose();
    if (drag) add_drag_columns(P, *drag, &PHt);
    S = PHt.middleRows<3>(imu_idx::kBa) + PHt.middleRows<3>(imu_idx::kF);
  } else {
    // World-frame force: H_theta = [R^T F_W]x, H_F = R^T, linearized at the first estimate of R
    // so that H annihilates the yaw direction of the propagation's nullspace.
    const AccelJacobian J = accel_jacobian(state.imu(), state.imu_fej().T_WI.q, ForceFrame::kWorld);
    PHt = P.middleCols<3>(imu_idx::kBa);
    PHt.noalias() += P.middleCols<3>(imu_idx::kTheta) * J.H_theta.transpose();
    PHt.noalias() += P.middleCols<3>(imu_idx::kF) * J.H_F.transpose();
    if (is >= 0) PHt.noalias() += P.col(is) * T_m.transpose();
    if (drag) add_drag_columns(P, *drag, &PHt);
    S = PHt.middleRows<3>(imu_idx::kBa) + J.H_theta * PHt.middleRows<3>(imu_idx::kTheta) +
        J.H_F * PHt.middleRows<3>(imu_idx::kF);
  }
  if (drag) {
    S.noalias() += drag->H_theta * PHt.middleRows<3>(imu_idx::kTheta);
    S.noalias() += drag->H_v * PHt.middleRows<3>(imu_idx::kV);
  }
  if (is >= 0) S.noalias() += T_m * PHt.row(is);
  S = 0.5 * (S + S.transpose()).eval();
  S.diagonal() += noise_var;
  const Eigen::Vector3d r = a_m - predict_accel(state.imu(), T_m, state.force_frame(), D);
  InnovationFactor<3> f;
  if (!f.compute(S, r)) return res;
  res.chi2 = f.chi2();
  res.threshold = chi2_threshold;
  const bool gated = f.past_gate(chi2_threshold);
  if (info != nullptr) {
    const bool world = state.force_frame() == ForceFrame::kWorld;
    const Eigen::Matrix3d R = world ? state.imu().T_WI.q.toRotationMatrix() : Eigen::Matrix3d::Identity();
    info->t_ns = state.time();
    info->w = R * r;
    info->S = R * S * R.transpose();
    // The force state's own measurement: the drag the model predicts is not part of it.
    info->y = drag ? Eigen::Vector3d(R * (a_m - state.imu().thrust_scale * T_m - drag_in_body(state.imu(), D)))
                   : Eigen::Vector3d(R * (a_m - state.imu().thrust_scale * T_m));
    info->T = R * T_m;
    info->R_WI = state.imu().T_WI.q.toRotationMatrix();  // the estimate itself, in both force models
    info->dx_imu.setZero();
    info->gated = gated;
  }
  if (gated && !downweight) return res;
  if (gated) {
    // Scale the innovation covariance so that this sample's chi2 sits at the threshold.
    f.inflate(res.chi2 / chi2_threshold);
    res.downweighted = true;
  }
  thread_local Eigen::Matrix<double, Eigen::Dynamic, 3> W;
  thread_local Eigen::VectorXd dx;
  f.whitened_gain(PHt, &W);
  dx.noalias() = W * f.whitened_innovation();
  state.apply_correction(dx);
  if (info != nullptr) info->dx_imu.head(state.imu_dim()) = dx.head(state.imu_dim());
  subtract_outer(P, W);  // rank 3: one fused pass per column of P
  res.applied = true;
  return res;
}

}  // namespace vid
