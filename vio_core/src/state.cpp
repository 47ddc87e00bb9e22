/// @file state.cpp
/// @brief Covariance bookkeeping: augmentation, marginalization, corrections, health.
#include "vio_core/state.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "geometry/so3.h"
#include "vio_core/covariance.h"

namespace vid {

Eigen::Vector3d drag_in_body(const ImuState& x, const Eigen::Vector3d& D) {
  return -D.cwiseProduct(x.T_WI.q.conjugate() * x.v_WI);
}

Eigen::Vector3d force_in_body(const ImuState& x, ForceFrame frame) {
  return frame == ForceFrame::kBody ? x.F_ext : Eigen::Vector3d(x.T_WI.q.conjugate() * x.F_ext);
}

Eigen::Vector3d force_in_world(const ImuState& x, ForceFrame frame) {
  return frame == ForceFrame::kWorld ? x.F_ext : Eigen::Vector3d(x.T_WI.q * x.F_ext);
}

void set_force_from_body(ImuState& x, ForceFrame frame, const Eigen::Vector3d& F_I) {
  x.F_ext = frame == ForceFrame::kBody ? F_I : Eigen::Vector3d(x.T_WI.q * F_I);
}

ImuLayout ImuLayout::from(const EstimatorParams& p) {
  ImuLayout l;
  l.force = p.mode == PropagationMode::kDynamics;
  l.force_rate = l.force && p.force_rate_random_walk > 0.0;
  l.thrust_scale = l.force && p.thrust_scale_random_walk > 0.0;
  return l;
}

FilterState::FilterState(const EstimatorParams& params)
    : FilterState(params.mode == PropagationMode::kDynamics, params.force_frame,
                  params.force_rate_random_walk > 0.0, params.thrust_scale_random_walk > 0.0) {}

FilterState::FilterState(bool with_force, ForceFrame force_frame, bool with_force_rate, bool with_thrust_scale)
    : force_frame_(force_frame),
      layout_{with_force, with_force && with_force_rate, with_force && with_thrust_scale} {
  P_ = Eigen::MatrixXd::Identity(imu_dim(), imu_dim());
}

void FilterState::initialize(TimeNs t_ns, const ImuState& imu, const Eigen::MatrixXd& P_imu) {
  if (P_imu.rows() != imu_dim() || P_imu.cols() != imu_dim()) {
    throw std::invalid_argument("FilterState::initialize: P_imu must be " +
                                std::to_string(imu_dim()) + "x" + std::to_string(imu_dim()));
  }
  t_ns_ = t_ns;
  imu_ = imu;
  imu_.T_WI.q = so3::normalized(imu.T_WI.q);
  if (!layout_.force) imu_.F_ext.setZero();
  if (!layout_.force_rate) imu_.F_dot.setZero();
  if (!layout_.thrust_scale) imu_.thrust_scale = 1.0;
  time_offset_.reset();
  clones_.clear();
  force_clones_.clear();
  P_ = P_imu;
  reset_imu_fej();
}

void FilterState::reset_imu_fej() {
  imu_fej_.T_WI = imu_.T_WI;
  imu_fej_.v_WI = imu_.v_WI;
}

void FilterState::augment_clone(const CloneTiming& timing) {
  const int n = covariance::append_clone(P_, imu_idx::kTheta, 6);  // J selects dtheta, dp
  if (time_offset_) {  // pose(t + dt_d) = pose(t) boxplus [w_I dt_d; v_td_W dt_d]
    Eigen::VectorXd g(6);
    g << timing.w_I, timing.v_td_W;
    covariance::add_scaled(P_, n, g, time_offset_->cov_index);
  }
  if (timing.jitter_s > 0.0) {
    Eigen::Matrix<double, 6, 1> g;
    g << timing.w_I, imu_.v_WI;
    P_.block<6, 6>(n, n) += (timing.jitter_s * timing.jitter_s) * g * g.transpose();
  }
  CloneState c;
  c.t_ns = t_ns_;
  c.T_WI = imu_.T_WI;
  c.T_WI_fej = imu_fej_.T_WI;
  c.cov_index = n;
  clones_.push_back(c);
}

void FilterState::marginalize_oldest_clone() {
  if (clones_.empty()) return;
  const int idx = clones_.front().cov_index;
  clones_.pop_front();
  remove_block(idx, 6);
}

void FilterState::augment_force_clone() {
  if (!layout_.force) throw std::logic_error("FilterState::augment_force_clone needs the F_ext state");
  const int n = covariance::append_clone(P_, imu_idx::kF, 3);  // x_aug = [x; J x], J selects dF_ext (docs/model.md eq. (35))
  ForceClone c;
  c.t_ns = t_ns_;
  c.F_ext = imu_.F_ext;
  c.cov_index = n;
  force_clones_.push_back(c);
}

void FilterState::marginalize_oldest_force_clone() {
  if (force_clones_.empty()) return;
  const int idx = force_clones_.front().cov_index;
  force_clones_.pop_front();
  remove_block(idx, 3);
}

void FilterState::remove_block(int idx, int k) {
  covariance::remove(P_, idx, k);
  if (time_offset_ && time_offset_->cov_index > idx) time_offset_->cov_index -= k;
  for (CloneState& c : clones_) {
    if (c.cov_index > idx) c.cov_index -= k;
  }
  for (ForceClone& c : force_clones_) {
    if (c.cov_index > idx) c.cov_index -= k;
  }
}

void FilterState::add_time_offset(double t_d_s, double sigma_s) {
  if (time_offset_) throw std::logic_error("FilterState::add_time_offset: already there");
  const int at = imu_dim();
  covariance::insert(P_, at, Eigen::MatrixXd::Constant(1, 1, sigma_s * sigma_s));
  for (CloneState& c : clones_) c.cov_index += 1;
  for (ForceClone& c : force_clones_) c.cov_index += 1;
  time_offset_ = TimeOffsetState{t_d_s, at};
}

double FilterState::time_offset_sigma() const {
  if (!time_offset_) return 0.0;
  return std::sqrt(std::max(0.0, P_(time_offset_->cov_index, time_offset_->cov_index)));
}

void FilterState::apply_correction(const Eigen::VectorXd& dx) {
  if (dx.size() != dim()) {
    throw std::invalid_argument("FilterState::apply_correction: size " + std::to_string(dx.size()) +
                                " != state dimension " + std::to_string(dim()));
  }
  imu_.T_WI.q = so3::boxplus(imu_.T_WI.q, dx.segment<3>(imu_idx::kTheta));
  imu_.T_WI.p += dx.segment<3>(imu_idx::kP);
  imu_.v_WI += dx.segment<3>(imu_idx::kV);
  imu_.b_g += dx.segment<3>(imu_idx::kBg);
  imu_.b_a += dx.segment<3>(imu_idx::kBa);
  if (layout_.force) imu_.F_ext += dx.segment<3>(imu_idx::kF);
  if (layout_.force_rate) imu_.F_dot += dx.segment<3>(imu_idx::kFdot);
  if (layout_.thrust_scale) imu_.thrust_scale += dx(layout_.thrust_scale_index());
  if (time_offset_) time_offset_->t_d_s += dx(time_offset_->cov_index);
  for (CloneState& c : clones_) {
    c.T_WI.q = so3::boxplus(c.T_WI.q, dx.segment<3>(c.cov_index));
    c.T_WI.p += dx.segment<3>(c.cov_index + 3);
  }
  for (ForceClone& c : force_clones_) c.F_ext += dx.segment<3>(c.cov_index);
}

CovarianceHealth FilterState::check_and_symmetrize() {
  CovarianceHealth h;
  h.finite = P_.allFinite();
  if (!h.finite) {
    h.positive_definite = false;
    return h;
  }
  h.max_asymmetry = (P_ - P_.transpose()).cwiseAbs().maxCoeff();
  Eigen::MatrixXd sym = 0.5 * (P_ + P_.transpose());  // temporary: transpose aliases
  P_.swap(sym);
  // A clone taken at the current time is an exact linear function of the IMU block (and of t_d),
  // so P is only semidefinite then; LDLT's pivots on a singular P carry round-off amplified by
  // its condition (-3e-10 where the smallest eigenvalue is -2e-17, a fast-yaw clone with t_d).
  // Such copies are PSD if the rest is: test the rest, to a small round-off tolerance.
  std::vector<int> keep;
  keep.reserve(P_.rows());
  const auto is_copy = [&](int i) {
    const auto in = [i](int at, int k) { return i >= at && i < at + k; };
    return (!clones_.empty() && clones_.back().t_ns == t_ns_ && in(clones_.back().cov_index, 6)) ||
           (!force_clones_.empty() && force_clones_.back().t_ns == t_ns_ && in(force_clones_.back().cov_index, 3));
  };
  for (int i = 0; i < P_.rows(); ++i)
    if (!is_copy(i)) keep.push_back(i);
  const Eigen::MatrixXd P_rest = P_(keep, keep);
  Eigen::LDLT<Eigen::MatrixXd> ldlt(P_rest);
  const double tol = 1e-12 * std::max(1.0, P_.diagonal().cwiseAbs().maxCoeff());
  // (info() flags exact zero pivots, which are legitimate here; the pivots decide.)
  h.positive_definite = ldlt.vectorD().allFinite() && ldlt.vectorD().minCoeff() >= -tol &&
                        P_.diagonal().minCoeff() > 0.0;
  return h;
}

}  // namespace vid
