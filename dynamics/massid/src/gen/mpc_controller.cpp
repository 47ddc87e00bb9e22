/// @file mpc_controller.cpp
/// @brief Condensed linear MPC per axis + thrust/attitude mapping + P attitude loop.
#include "massid/gen/mpc_controller.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "geometry/so3.h"

namespace vid::massid::gen {
namespace {

/// Condensed prediction of x = [p, v] under u = acceleration held for h:
/// p_i = p_0 + i h v_0 + sum_{j<i} h^2 (i - j - 1/2) u_j,   v_i = v_0 + sum_{j<i} h u_j.
void prediction_maps(int N, double h, Eigen::MatrixXd* Gp, Eigen::MatrixXd* Gv) {
  Gp->setZero(N, N);
  Gv->setZero(N, N);
  for (int i = 1; i <= N; ++i) {
    for (int j = 0; j < i; ++j) {
      (*Gp)(i - 1, j) = h * h * (i - j - 0.5);
      (*Gv)(i - 1, j) = h;
    }
  }
}

Eigen::MatrixXd hessian(const ControllerSettings& s) {
  Eigen::MatrixXd Gp, Gv;
  prediction_maps(s.horizon, s.mpc_dt_s, &Gp, &Gv);
  const int N = s.horizon;
  return s.weight_p * Gp.transpose() * Gp + s.weight_v * Gv.transpose() * Gv +
         s.weight_a * Eigen::MatrixXd::Identity(N, N);
}

}  // namespace

BoxQp::BoxQp(const Eigen::MatrixXd& H) : H_(H) {
  H_inv_ = H.llt().solve(Eigen::MatrixXd::Identity(H.rows(), H.cols()));
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H, Eigen::EigenvaluesOnly);
  step_ = 1.0 / eig.eigenvalues().maxCoeff();
}

int BoxQp::solve(const Eigen::VectorXd& f, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                 Eigen::VectorXd* u, int max_iterations, double tolerance) const {
  const Eigen::VectorXd u_free = -H_inv_ * f;
  Eigen::VectorXd x = u_free.cwiseMax(lo).cwiseMin(hi);
  if (x == u_free) {
    *u = x;
    return 0;
  }
  // FISTA (accelerated projected gradient) from the clamped unconstrained optimum.
  Eigen::VectorXd y = x, x_prev = x;
  double t = 1.0;
  int it = 0;
  for (it = 1; it <= max_iterations; ++it) {
    x_prev = x;
    x = (y - step_ * (H_ * y + f)).cwiseMax(lo).cwiseMin(hi);
    const double t_next = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * t * t));
    y = x + ((t - 1.0) / t_next) * (x - x_prev);
    t = t_next;
    if ((x - x_prev).lpNorm<Eigen::Infinity>() < tolerance) break;
  }
  *u = x;
  return it;
}

MpcController::MpcController(const ControllerSettings& settings, double nominal_mass_kg,
                             double gravity, double thrust_min_N, double thrust_max_N,
                             double control_dt_s)
    : s_(settings),
      mass_nominal_(nominal_mass_kg),
      gravity_(gravity),
      thrust_min_(thrust_min_N),
      thrust_max_(thrust_max_N),
      control_dt_(control_dt_s),
      qp_(hessian(settings)) {
  prediction_maps(s_.horizon, s_.mpc_dt_s, &Gp_, &Gv_);
}

ControlOutput MpcController::compute(double t, const Eigen::Quaterniond& q_WI,
                                     const Eigen::Vector3d& p_WI, const Eigen::Vector3d& v_WI,
                                     const ReferenceTrajectory& reference) {
  const int N = s_.horizon;
  const double h = s_.mpc_dt_s;
  ControlOutput out;

  // Offset-free tracking: integral of the position error, bounded (anti-windup).
  const RefPoint ref_now = reference.at(t);
  if (s_.integral_gain > 0.0) {
    integral_W_ += (ref_now.p_W - p_WI) * control_dt_;
    const double i_max = s_.integral_accel_max / s_.integral_gain;
    integral_W_ = integral_W_.cwiseMax(-i_max).cwiseMin(i_max);
  }
  const Eigen::Vector3d a_int_W = s_.integral_gain * integral_W_;

  // References over the horizon.
  Eigen::MatrixXd p_ref(3, N), v_ref(3, N), a_ref(3, N);
  for (int i = 0; i < N; ++i) {
    const RefPoint r_next = reference.at(t + (i + 1) * h);
    p_ref.col(i) = r_next.p_W;
    v_ref.col(i) = r_next.v_W;
    a_ref.col(i) = i == 0 ? ref_now.a_W : reference.at(t + i * h).a_W;
  }
  // Bounds on the MPC's acceleration: horizontal box; vertical from the thrust bounds as the
  // controller believes them (nominal mass). The integral term shares the same budget.
  const double az_lo = thrust_min_ / mass_nominal_ - gravity_;
  const double az_hi = thrust_max_ / mass_nominal_ - gravity_;
  const Eigen::Vector3d lo_W(-s_.accel_xy_max, -s_.accel_xy_max, az_lo);
  const Eigen::Vector3d hi_W(s_.accel_xy_max, s_.accel_xy_max, az_hi);

  Eigen::Vector3d a_cmd_W;
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(N);
    Eigen::VectorXd p_free(N), v_free(N);
    for (int i = 1; i <= N; ++i) {
      p_free(i - 1) = p_WI[axis] + i * h * v_WI[axis];
      v_free(i - 1) = v_WI[axis];
    }
    const Eigen::VectorXd f = s_.weight_p * Gp_.transpose() * (p_free - p_ref.row(axis).transpose()) +
                              s_.weight_v * Gv_.transpose() * (v_free - v_ref.row(axis).transpose()) -
                              s_.weight_a * a_ref.row(axis).transpose();
    const double lo = lo_W[axis] - a_int_W[axis];
    const double hi = std::max(lo, hi_W[axis] - a_int_W[axis]);
    Eigen::VectorXd u;
    if (qp_.solve(f, lo * ones, hi * ones, &u) > 0) out.saturated = true;
    a_cmd_W[axis] = u(0) + a_int_W[axis];
  }
  out.a_cmd_W = a_cmd_W;

  // Thrust direction with a tilt bound; thrust magnitude with the nominal mass.
  Eigen::Vector3d f_W = a_cmd_W + Eigen::Vector3d(0, 0, gravity_);
  f_W.z() = std::max(f_W.z(), 0.2 * gravity_);
  const double tan_tilt = std::tan(s_.tilt_max_deg * M_PI / 180.0);
  const double f_xy = f_W.head<2>().norm();
  if (f_xy > tan_tilt * f_W.z()) {
    f_W.head<2>() *= tan_tilt * f_W.z() / f_xy;
    out.saturated = true;
  }
  const double thrust_wanted = mass_nominal_ * f_W.norm();
  out.thrust_N = std::clamp(thrust_wanted, thrust_min_, thrust_max_);
  if (out.thrust_N != thrust_wanted) out.saturated = true;

  // Desired attitude: z along f, heading from the reference yaw.
  const Eigen::Vector3d z_des = f_W.normalized();
  const Eigen::Vector3d x_c(std::cos(ref_now.yaw), std::sin(ref_now.yaw), 0.0);
  const Eigen::Vector3d y_des = z_des.cross(x_c).normalized();
  Eigen::Matrix3d R_WD;
  R_WD << y_des.cross(z_des), y_des, z_des;
  const Eigen::Matrix3d R_WI = q_WI.normalized().toRotationMatrix();
  const Eigen::Vector3d e_I = so3::log(R_WI.transpose() * R_WD);

  // Feed-forward: rate of the thrust direction from the reference jerk.
  const Eigen::Vector3d z_dot_W =
      (Eigen::Matrix3d::Identity() - z_des * z_des.transpose()) * ref_now.j_W / f_W.norm();
  const Eigen::Vector3d w_ff_I = R_WI.transpose() * z_des.cross(z_dot_W);

  const Eigen::Vector3d w_wanted = s_.attitude_gain * e_I + w_ff_I;
  out.w_I = w_wanted.cwiseMax(-s_.rate_max).cwiseMin(s_.rate_max);
  if (out.w_I != w_wanted) out.saturated = true;
  return out;
}

}  // namespace vid::massid::gen
