#include "sim/controller.h"

#include <cmath>

#include "geometry/so3.h"

namespace vid::sim {

using so3::skew;
using so3::vee;

GeometricController::GeometricController(const dynamics::QuadrotorModel& model,
                                         const ControllerGains& gains)
    : model_(model), gains_(gains) {
  const Eigen::MatrixXd A = model_.allocation_matrix();
  alloc_pinv_ = A.completeOrthogonalDecomposition().pseudoInverse();
}

Eigen::Matrix3d GeometricController::desired_rotation(const Eigen::Vector3d& force_W, double yaw) const {
  Eigen::Vector3d b3 = force_W.norm() > 1e-9 ? Eigen::Vector3d(force_W.normalized()) : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d b1c(std::cos(yaw), std::sin(yaw), 0.0);
  Eigen::Vector3d b2 = b3.cross(b1c);
  if (b2.norm() < 1e-6) b2 = b3.cross(Eigen::Vector3d(-std::sin(yaw), std::cos(yaw), 0.0)).cross(b3);
  b2.normalize();
  const Eigen::Vector3d b1 = b2.cross(b3);
  Eigen::Matrix3d R;
  R << b1, b2, b3;
  return R;
}

void GeometricController::flat_attitude(const Trajectory& ref, double t, const Eigen::Vector3d& dist_W,
                                        Eigen::Matrix3d* R_WI, Eigen::Vector3d* w_I,
                                        Eigen::Vector3d* dw_I) const {
  const double m = model_.params().mass_kg;
  const Eigen::Vector3d g_W(0.0, 0.0, -model_.params().gravity);
  auto rot_at = [&](double tau) {
    const FlatOutput o = ref.eval(tau);
    return desired_rotation(m * (o.a - g_W) - dist_W, o.yaw);
  };
  // Central differences of the flatness map: body rate and angular acceleration feed-forward.
  constexpr double h = 2e-3;
  const Eigen::Matrix3d Rm = rot_at(t - h), R0 = rot_at(t), Rp = rot_at(t + h);
  *R_WI = R0;
  const Eigen::Vector3d w_plus = so3::log(R0.transpose() * Rp) / h;
  const Eigen::Vector3d w_minus = so3::log(Rm.transpose() * R0) / h;
  *w_I = 0.5 * (w_plus + w_minus);
  *dw_I = (w_plus - w_minus) / h;
}

Eigen::VectorXd GeometricController::allocate(double thrust_N, const Eigen::Vector3d& torque_I) const {
  const auto& p = model_.params();
  const double u_min = p.rotor_speed_min * p.rotor_speed_min;
  const double u_max = p.rotor_speed_max * p.rotor_speed_max;
  Eigen::Vector4d w(thrust_N, torque_I.x(), torque_I.y(), torque_I.z());
  Eigen::VectorXd u = alloc_pinv_ * w;
  const auto saturated = [&](const Eigen::VectorXd& x) { return x.minCoeff() < u_min || x.maxCoeff() > u_max; };
  if (saturated(u)) {
    // Give up yaw authority first: it matters least for tracking.
    for (double scale : {0.5, 0.25, 0.0}) {
      w[3] = scale * torque_I.z();
      u = alloc_pinv_ * w;
      if (!saturated(u)) break;
    }
  }
  u = u.cwiseMax(u_min).cwiseMin(u_max);
  return u.cwiseSqrt();
}

Eigen::VectorXd GeometricController::update(const ControllerInput& in, const Trajectory& ref, double dt) {
  const auto& par = model_.params();
  const double m = par.mass_kg;
  const Eigen::Vector3d g_W(0.0, 0.0, -par.gravity);
  const Eigen::Matrix3d R = in.state.q_WI.toRotationMatrix();
  const Eigen::Matrix3d& J = par.inertia;

  // Disturbance observer: what the nominal model cannot explain of the measured acceleration.
  Eigen::Vector3d thrust_I, torque_I;
  model_.thrust_and_torque(in.state.rotor_speeds, &thrust_I, &torque_I);
  const Eigen::Vector3d f_meas = m * (in.accel_W - g_W) - R * thrust_I;
  if (gains_.disturbance_tau_s > 0.0 && !in.in_contact) {
    if (first_) {
      dist_W_ = f_meas;
    } else {
      dist_W_ += (dt / (gains_.disturbance_tau_s + dt)) * (f_meas - dist_W_);
    }
  }
  first_ = false;

  const FlatOutput r = ref.eval(in.t_s);
  const Eigen::Vector3d e_p = in.state.p_WI - r.p;
  const Eigen::Vector3d e_v = in.state.v_WI - r.v;
  if (!in.in_contact) {
    integral_ = (integral_ + e_p * dt).cwiseMax(-gains_.integral_limit).cwiseMin(gains_.integral_limit);
  }
  const Eigen::Vector3d acc_cmd =
      r.a - gains_.kp.cwiseProduct(e_p) - gains_.kv.cwiseProduct(e_v) - gains_.ki.cwiseProduct(integral_);
  const Eigen::Vector3d F_d = m * (acc_cmd - g_W) - dist_W_;

  Eigen::Matrix3d R_ff;
  Eigen::Vector3d w_d, dw_d;
  flat_attitude(ref, in.t_s, dist_W_, &R_ff, &w_d, &dw_d);
  const Eigen::Matrix3d R_d = desired_rotation(F_d, r.yaw);
  const double T = F_d.dot(R.col(2));

  const Eigen::Vector3d e_R = 0.5 * vee(R_d.transpose() * R - R.transpose() * R_d);
  const Eigen::Vector3d w_d_I = R.transpose() * R_d * w_d;
  const Eigen::Vector3d e_w = in.state.w_I - w_d_I;
  const Eigen::Vector3d& w = in.state.w_I;
  const Eigen::Vector3d M = J * (-gains_.kr.cwiseProduct(e_R) - gains_.kw.cwiseProduct(e_w)) + w.cross(J * w) -
                            J * (skew(w) * w_d_I - R.transpose() * R_d * dw_d);
  return allocate(std::min(std::max(T, 0.0), in.max_thrust_N), M);
}

}  // namespace vid::sim

namespace vid::sim {

Eigen::VectorXd GeometricController::attitude_hold(const dynamics::QuadrotorState& x, double thrust_N,
                                                   double yaw) const {
  const Eigen::Matrix3d R = x.q_WI.toRotationMatrix();
  const Eigen::Matrix3d R_d = desired_rotation(Eigen::Vector3d::UnitZ(), yaw);
  const Eigen::Matrix3d& J = model_.params().inertia;
  const Eigen::Vector3d e_R = 0.5 * vee(R_d.transpose() * R - R.transpose() * R_d);
  const Eigen::Vector3d& w = x.w_I;
  const Eigen::Vector3d M = J * (-gains_.kr.cwiseProduct(e_R) - gains_.kw.cwiseProduct(w)) + w.cross(J * w);
  return allocate(std::max(thrust_N, 0.0), M);
}

void GeometricController::reset(const Eigen::Vector3d& disturbance_W) {
  integral_.setZero();
  dist_W_ = disturbance_W;
  first_ = false;
}

}  // namespace vid::sim
