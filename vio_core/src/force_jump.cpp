/// @file force_jump.cpp
/// @brief GLR step detection in the accelerometer innovations and the force re-estimate.
#include "vio_core/force_jump.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "geometry/so3.h"
#include "vio_core/accel_noise.h"
#include "vio_core/ekf_update.h"

namespace vid {

ForceJumpDetector::ForceJumpDetector(const EstimatorParams& p)
    : threshold_(p.force_jump_threshold),
      vib_sum_gain_max_(p.imu_rate_hz > 0.0
                            ? 1.0 / std::pow(std::sin(M_PI * AccelNoiseAdapter::kHighpassHz / p.imu_rate_hz), 2)
                            : 0.0),
      split_sigma_(p.force_jump_split_sigma),
      min_step_(p.force_jump_min_step),
      max_window_(p.force_jump_window) {
  if (max_window_ < 2) throw std::invalid_argument("force_jump_window must be >= 2");
  if (!(min_step_ >= 0.0)) throw std::invalid_argument("force_jump_min_step must be >= 0");
}

std::optional<AccelInnovation> ForceJumpDetector::push(const AccelInnovation& s) {
  buf_.push_back(s);
  // The test sums innovations clipped at kClipSigma (Mahalanobis): one outlier can then weigh
  // no more than a 3-sigma sample, and a step must show in several samples to be found.
  constexpr double kClipSigma = 3.0;
  const Eigen::LLT<Eigen::Matrix3d> llt(s.S);
  const double d = llt.info() == Eigen::Success ? std::sqrt(s.w.dot(llt.solve(s.w))) : 0.0;
  buf_.back().w_test = d > kClipSigma ? Eigen::Vector3d(s.w * (kClipSigma / d)) : s.w;
  if (static_cast<int>(buf_.size()) <= max_window_) return std::nullopt;
  AccelInnovation out = buf_.front();
  buf_.pop_front();
  return out;
}

Eigen::Matrix3d ForceJumpDetector::coloured_excess(int n, const Eigen::Matrix3d& X_n) const {
  // sum_k v_k over n samples of a stationary tone of variance x at frequency f: variance
  // x sin^2(n pi f dt) / sin^2(pi f dt) <= x min(n^2, 1 / sin^2(pi f dt)), largest at the lowest
  // f in the band. X_n = n x; the white sum counted n x of it already.
  const double dn = static_cast<double>(n);
  const double gain = std::min(dn * dn, vib_sum_gain_max_);
  return gain > dn ? Eigen::Matrix3d((gain / dn - 1.0) * X_n) : Eigen::Matrix3d::Zero();
}

std::optional<ForceJump> ForceJumpDetector::test() const {
  std::optional<ForceJump> best;
  double best_stat = threshold_;
  // Every onset n = 2 .. max_window samples back (the maximum-likelihood onset of the step is
  // the n with the largest statistic). Cumulative sums from the newest sample back; the newer
  // half of window n is the sum at n / 2, kept in a small table.
  const int count = std::min(size(), max_window_);
  cum_w_.resize(static_cast<std::size_t>(count) + 1);
  cum_S_.resize(static_cast<std::size_t>(count) + 1);
  cum_X_.resize(static_cast<std::size_t>(count) + 1);
  cum_w_[0].setZero();
  cum_S_[0].setZero();
  cum_X_[0].setZero();
  bool vibration = false;
  for (int i = 0; i < count; ++i) {
    const auto k = static_cast<std::size_t>(i);
    cum_w_[k + 1] = cum_w_[k] + recent(i).w_test;
    cum_S_[k + 1] = cum_S_[k] + recent(i).S;
    cum_X_[k + 1] = cum_X_[k] + recent(i).S_vib;
    vibration = vibration || !recent(i).S_vib.isZero(0.0);
  }
  // Onsets: every n up to 16, then every 2nd up to 32, 4th up to 64, ... (the relative
  // resolution of a long window's onset need not be finer; keeps the test O(log N) windows).
  for (int n = 2; n <= count; n += std::max(1, n / 16)) {
    const auto un = static_cast<std::size_t>(n), uh = static_cast<std::size_t>(n / 2);
    const Eigen::Vector3d& C = cum_w_[un];
    const Eigen::Vector3d& C_half = cum_w_[uh];
    Eigen::Matrix3d SS = cum_S_[un];
    Eigen::Matrix3d SS_half = cum_S_[uh];
    Eigen::Matrix3d SS_old = SS - SS_half;
    if (vibration) {
      SS_old += coloured_excess(n - n / 2, cum_X_[un] - cum_X_[uh]);
      SS += coloured_excess(n, cum_X_[un]);
      SS_half += coloured_excess(n / 2, cum_X_[uh]);
    }
    // Closed-form 3x3 inverse (cofactors): several times cheaper than a Cholesky per window,
    // and this runs for ~50 windows after every accelerometer sample.
    Eigen::Matrix3d SS_inv;
    bool invertible = false;
    SS.computeInverseWithCheck(SS_inv, invertible);
    if (!invertible) continue;
    const Eigen::Vector3d a = SS_inv * C;  // (sum S)^-1 C
    const double l = C.dot(a);
    if (!(l > threshold_)) continue;
    // Each half must carry the step: its projection on the step direction u = a / sqrt(l)
    // at >= split_sigma standard deviations (u^T sum_half S u under no step).
    const Eigen::Vector3d u = a / std::sqrt(l);
    const Eigen::Vector3d C_old = C - C_half;
    const double z_new = u.dot(C_half) / std::sqrt(u.dot(SS_half * u));
    const double z_old = u.dot(C_old) / std::sqrt(u.dot(SS_old * u));
    if (!(z_new >= split_sigma_ && z_old >= split_sigma_)) continue;
    if (l > best_stat) {
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();  // the step's size from the raw innovations
      for (int i = 0; i < n; ++i) mean += recent(i).w;
      mean /= n;
      // A step smaller than the floor is left to the force(-rate) random walk: on real sensors
      // vibration and thrust-model error make such "steps" by the hundred (docs/real_sensors.md).
      if (mean.norm() < min_step_) continue;
      best_stat = l;
      best = ForceJump{n, l, mean, recent(0).t_ns};
    }
  }
  return best;
}

void apply_force_jump(FilterState& state, const std::vector<AccelInnovation>& window, const ForceJump& jump,
                      double noise_var, double sigma_rate0) {
  if (window.empty()) return;
  const int imu_dim = state.imu_dim();
  const int n = static_cast<int>(window.size());
  // 1. Undo what these samples did to the IMU block from the velocity on: they were explained
  //    by a force that had changed (b_a and the velocity took part of the step). Not to the pose:
  //    the clones share it (the newest is a copy), so undoing it alone opened a step between
  //    the IMU pose and the clones that the next visual update explained with what moves the
  //    clones' relative poses - the time offset at fast-turning clones (rope_snap, noise-free:
  //    t_d +0.15 ms at sigma 0.05, 6 sigma on the way; the tilt comes back through the images).
  Eigen::VectorXd undo = Eigen::VectorXd::Zero(state.dim());
  for (const AccelInnovation& s : window)
    undo.segment(imu_idx::kV, imu_dim - imu_idx::kV) -= s.dx_imu.segment(imu_idx::kV, imu_dim - imu_idx::kV);
  state.apply_correction(undo);

  // 2. The step's prior: the force is unknown to within a few times the detected step, and its
  //    rate starts anew as at initialization: zero mean (a step, not a ramp, was detected; the
  //    old rate belonged to the force before it), sigma_rate0, independent of everything else.
  Eigen::MatrixXd& P = state.P();
  const double step = jump.delta.norm();
  P.block<3, 3>(imu_idx::kF, imu_idx::kF).diagonal().array() += 4.0 * step * step;
  if (state.with_force_rate()) {
    state.imu().F_dot.setZero();
    P.middleRows<3>(imu_idx::kFdot).setZero();
    P.middleCols<3>(imu_idx::kFdot).setZero();
    P.block<3, 3>(imu_idx::kFdot, imu_idx::kFdot) = sigma_rate0 * sigma_rate0 * Eigen::Matrix3d::Identity();
  }
  // A payload picked up or dropped is such a step too (s T_m changes): with the thrust scale
  // estimated the step's prior goes to s as well, in thrust units, and the re-update below and
  // the later thrust variation decide between the two.
  Eigen::Vector3d T_bar = Eigen::Vector3d::Zero();
  for (const AccelInnovation& s : window) T_bar += s.T / n;
  const int is = state.with_thrust_scale() ? state.layout().thrust_scale_index() : -1;
  if (is >= 0 && T_bar.norm() > 1e-6) P(is, is) += 4.0 * step * step / T_bar.squaredNorm();

  // 3. The window's mean measurement, once: y_bar = F(t_bar) + R_bar b_a + noise (world
  //    model; body model: F + b_a), F(t_bar) = F - dF/dt (t - t_bar).
  const ImuState& x = state.imu();
  const bool world = state.force_frame() == ForceFrame::kWorld;
  Eigen::Vector3d y_bar = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R_bar = Eigen::Matrix3d::Zero();
  double dt_bar = 0.0;
  for (const AccelInnovation& s : window) {
    y_bar += s.y;
    R_bar += world ? s.R_WI : Eigen::Matrix3d::Identity();
    dt_bar += static_cast<double>(state.time() - s.t_ns) * 1e-9;
  }
  y_bar /= n;
  R_bar /= n;
  dt_bar /= n;
  std::vector<int> cols;
  const int blocks = state.with_force_rate() ? 4 : 3;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3, 3 * blocks + (is >= 0 ? 1 : 0));
  Eigen::Vector3d h = x.F_ext + R_bar * x.b_a;
  // theta: the rotation that brought each sample into the force frame carries the attitude
  // error, y = F + R b_a + R [R^T y]x dtheta (right perturbation; zero in the body model).
  const Eigen::Matrix3d R = x.T_WI.q.toRotationMatrix();
  H.block<3, 3>(0, 0) = world ? Eigen::Matrix3d(R * so3::skew(R.transpose() * y_bar)) : Eigen::Matrix3d::Zero();
  H.block<3, 3>(0, 3) = R_bar;
  H.block<3, 3>(0, 6).setIdentity();
  for (int k = 0; k < 3; ++k) cols.push_back(imu_idx::kTheta + k);
  for (int k = 0; k < 3; ++k) cols.push_back(imu_idx::kBa + k);
  for (int k = 0; k < 3; ++k) cols.push_back(imu_idx::kF + k);
  if (state.with_force_rate()) {
    H.block<3, 3>(0, 9) = -dt_bar * Eigen::Matrix3d::Identity();
    h -= dt_bar * x.F_dot;
    for (int k = 0; k < 3; ++k) cols.push_back(imu_idx::kFdot + k);
  }
  if (is >= 0) {
    // y = a_m - s T_m: a change ds of the thrust scale moves the model by + T_bar ds.
    H.col(3 * blocks) = T_bar;
    cols.push_back(is);
  }
  const Eigen::Matrix3d Rn = (noise_var / n) * Eigen::Matrix3d::Identity();
  ekf_update_columns(state, cols, H, y_bar - h, Rn, 0.0);

  // 4. Propagation (thrust + F) integrated the old force over the window, so velocity and
  //    position missed what the accelerometer saw: the integral of the innovations (world
  //    frame), dv = sum w_k dt, dp = sum w_k dt (t - t_k). It follows the true shape of the
  //    change (a step, a ramp, a pulse), with the samples' noise as its uncertainty.
  const double dt = n > 1 ? 1e-9 * static_cast<double>(window.front().t_ns - window.back().t_ns) / (n - 1) : 0.0;
  Eigen::Vector3d dv = Eigen::Vector3d::Zero(), dp = Eigen::Vector3d::Zero();
  Eigen::Matrix3d Cvv = Eigen::Matrix3d::Zero(), Cpp = Eigen::Matrix3d::Zero(), Cvp = Eigen::Matrix3d::Zero();
  for (const AccelInnovation& s : window) {
    const double age = 1e-9 * static_cast<double>(state.time() - s.t_ns) + 0.5 * dt;
    const Eigen::Vector3d w_W = world ? s.w : Eigen::Vector3d(s.R_WI * s.w);
    const Eigen::Matrix3d S_W = world ? s.S : Eigen::Matrix3d(s.R_WI * s.S * s.R_WI.transpose());
    dv += dt * w_W;
    dp += dt * age * w_W;
    Cvv += dt * dt * S_W;
    Cvp += dt * dt * age * S_W;
    Cpp += dt * dt * age * age * S_W;
  }
  Eigen::VectorXd dx = Eigen::VectorXd::Zero(state.dim());
  dx.segment<3>(imu_idx::kV) = dv;
  dx.segment<3>(imu_idx::kP) = dp;
  state.apply_correction(dx);
  P.block<3, 3>(imu_idx::kV, imu_idx::kV) += Cvv;
  P.block<3, 3>(imu_idx::kP, imu_idx::kP) += Cpp;
  P.block<3, 3>(imu_idx::kV, imu_idx::kP) += Cvp;
  P.block<3, 3>(imu_idx::kP, imu_idx::kV) += Cvp.transpose();
}

}  // namespace vid
