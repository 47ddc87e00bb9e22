#include "dynamics/quadrotor.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>

#include "dynamics/rk4.h"


namespace vid::dynamics {

std::vector<RotorParams> QuadrotorParams::symmetric_layout(const std::string& layout,
                                                           double arm_length,
                                                           const std::vector<double>& thrust_coeffs,
                                                           const std::vector<int>& directions,
                                                           double torque_to_thrust_m) {
  const std::size_t count = thrust_coeffs.size();
  if (count < 3) throw std::invalid_argument("rotor layout: need at least 3 thrust coefficients");
  if (!directions.empty() && directions.size() != count)
    throw std::invalid_argument("rotor layout: rotor_directions must have one entry per rotor");
  double offset = 0.0;
  if (layout == "x") {
    offset = M_PI / static_cast<double>(count);
  } else if (layout != "plus") {
    throw std::invalid_argument("rotor layout: '" + layout + "' is not 'x' or 'plus'");
  }
  std::vector<RotorParams> rotors(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double angle = offset + 2.0 * M_PI * static_cast<double>(i) / static_cast<double>(count);
    rotors[i].position_I = Eigen::Vector3d(arm_length * std::cos(angle), arm_length * std::sin(angle), 0.0);
    rotors[i].direction = directions.empty() ? (i % 2 == 0 ? 1 : -1) : directions[i];
    rotors[i].thrust_coeff = thrust_coeffs[i];
    rotors[i].torque_coeff = torque_to_thrust_m * thrust_coeffs[i];
  }
  return rotors;
}

void QuadrotorParams::validate() const {
  if (!(mass_kg > 0.0)) throw std::invalid_argument("vehicle: mass_kg must be > 0");
  if (rotors.size() < 3) throw std::invalid_argument("vehicle: need at least 3 rotors");
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(inertia);
  if (!(es.eigenvalues().minCoeff() > 0.0))
    throw std::invalid_argument("vehicle: inertia must be symmetric positive definite");
  if (motor_time_constant_s < 0.0) throw std::invalid_argument("vehicle: motor_time_constant_s must be >= 0");
  if (!(rotor_speed_max > rotor_speed_min) || rotor_speed_min < 0.0)
    throw std::invalid_argument("vehicle: need 0 <= rotor_speed_min < rotor_speed_max");
  for (const auto& r : rotors) {
    if (!(r.thrust_coeff > 0.0)) throw std::invalid_argument("vehicle: thrust coefficients must be > 0");
    if (r.direction != 1 && r.direction != -1)
      throw std::invalid_argument("vehicle: rotor directions must be +1 or -1");
  }
  if (!(gravity > 0.0)) throw std::invalid_argument("vehicle: gravity must be > 0");
  if (!(std::abs(thrust_axis_I.norm() - 1.0) < 1e-9) || !(thrust_axis_I.z() > 0.0))
    throw std::invalid_argument("vehicle: thrust_axis_I must be a unit vector with z > 0");
}

QuadrotorModel::QuadrotorModel(QuadrotorParams params) : params_(std::move(params)) {
  params_.validate();
}

Eigen::VectorXd QuadrotorModel::rotor_thrusts(const Eigen::VectorXd& n) const {
  Eigen::VectorXd T(rotor_count());
  for (int i = 0; i < rotor_count(); ++i) T[i] = params_.rotors[i].thrust_coeff * n[i] * n[i];
  return T;
}

void QuadrotorModel::thrust_and_torque(const Eigen::VectorXd& n, Eigen::Vector3d* thrust_I,
                                       Eigen::Vector3d* torque_I) const {
  thrust_I->setZero();
  torque_I->setZero();
  for (int i = 0; i < rotor_count(); ++i) {
    const RotorParams& r = params_.rotors[i];
    const double n2 = n[i] * n[i];
    const Eigen::Vector3d f = params_.thrust_axis_I * (r.thrust_coeff * n2);  // z_I: bit-identical to (0, 0, T)
    *thrust_I += f;
    *torque_I += r.position_I.cross(f);
    // A rotor spinning counter-clockwise pushes the body clockwise (reaction torque).
    torque_I->z() -= r.direction * r.torque_coeff * n2;
  }
}

Eigen::VectorXd QuadrotorModel::clamp_speeds(const Eigen::VectorXd& n) const {
  return n.cwiseMax(params_.rotor_speed_min).cwiseMin(params_.rotor_speed_max);
}

Eigen::MatrixXd QuadrotorModel::allocation_matrix() const {
  Eigen::MatrixXd A(4, rotor_count());
  for (int i = 0; i < rotor_count(); ++i) {
    const RotorParams& r = params_.rotors[i];
    A(0, i) = r.thrust_coeff;
    A(1, i) = r.thrust_coeff * r.position_I.y();
    A(2, i) = -r.thrust_coeff * r.position_I.x();
    A(3, i) = -r.direction * r.torque_coeff;
  }
  return A;
}

ForceBreakdown QuadrotorModel::forces(double t_s, const QuadrotorState& x,
                                      const Environment& env) const {
  ForceBreakdown f;
  thrust_and_torque(x.rotor_speeds, &f.thrust_I, &f.torque_I);
  const Eigen::Matrix3d R_WI = x.q_WI.normalized().toRotationMatrix();
  const Eigen::Vector3d v_I = R_WI.transpose() * x.v_WI;
  f.drag_W = R_WI * (-params_.linear_drag.cwiseProduct(v_I));
  f.env_W = env.force_W(t_s, x);
  if (env.has_torque()) f.env_torque_I = env.torque_I(t_s, x);
  f.mass_kg = env.mass_kg(t_s);
  const Eigen::Vector3d g_W(0.0, 0.0, -params_.gravity);
  f.accel_W = (R_WI * f.thrust_I + f.external_W()) / f.mass_kg + g_W;
  return f;
}

QuadrotorStateDot QuadrotorModel::derivative(double t_s, const QuadrotorState& x,
                                             const Eigen::VectorXd& n_cmd,
                                             const Environment& env) const {
  const ForceBreakdown f = forces(t_s, x, env);
  QuadrotorStateDot d;
  d.p_dot = x.v_WI;
  d.v_dot = f.accel_W;
  const Eigen::Matrix3d& J = params_.inertia;
  if (env.has_torque()) {
    d.w_dot = J.ldlt().solve(f.torque_I + f.env_torque_I - x.w_I.cross(J * x.w_I));
  } else {
    d.w_dot = J.ldlt().solve(f.torque_I - x.w_I.cross(J * x.w_I));
  }
  // q_dot = 0.5 q (x) [0, w]
  const Eigen::Quaterniond qw(0.0, x.w_I.x(), x.w_I.y(), x.w_I.z());
  const Eigen::Quaterniond qd = x.q_WI * qw;
  d.q_dot = 0.5 * Eigen::Vector4d(qd.w(), qd.x(), qd.y(), qd.z());
  if (params_.motor_time_constant_s > 0.0) {
    d.n_dot = (clamp_speeds(n_cmd) - x.rotor_speeds) / params_.motor_time_constant_s;
  } else {
    d.n_dot = Eigen::VectorXd::Zero(rotor_count());
  }
  return d;
}

QuadrotorStateDot operator+(const QuadrotorStateDot& a, const QuadrotorStateDot& b) {
  return {a.p_dot + b.p_dot, a.v_dot + b.v_dot, a.w_dot + b.w_dot, a.q_dot + b.q_dot, a.n_dot + b.n_dot};
}

QuadrotorStateDot operator*(double s, const QuadrotorStateDot& d) {
  return {s * d.p_dot, s * d.v_dot, s * d.w_dot, s * d.q_dot, s * d.n_dot};
}

namespace {

QuadrotorState add_scaled(const QuadrotorState& x, const QuadrotorStateDot& d, double h) {
  QuadrotorState y;
  y.p_WI = x.p_WI + h * d.p_dot;
  y.v_WI = x.v_WI + h * d.v_dot;
  y.w_I = x.w_I + h * d.w_dot;
  Eigen::Vector4d q(x.q_WI.w(), x.q_WI.x(), x.q_WI.y(), x.q_WI.z());
  q += h * d.q_dot;
  // Stage quaternions are not renormalised: RK4 treats q as a plain 4-vector ODE.
  y.q_WI = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
  y.rotor_speeds = x.rotor_speeds + h * d.n_dot;
  return y;
}

}  // namespace

QuadrotorState QuadrotorModel::rk4_step(double t_s, double dt_s, const QuadrotorState& x0,
                                        const Eigen::VectorXd& n_cmd,
                                        const Environment& env) const {
  QuadrotorState x = x0;
  if (params_.motor_time_constant_s <= 0.0) x.rotor_speeds = clamp_speeds(n_cmd);
  auto f = [&](double t, const QuadrotorState& s) { return derivative(t, s, n_cmd, env); };
  QuadrotorState y = dynamics::rk4_step<QuadrotorStateDot>(t_s, dt_s, x, f, add_scaled);
  y.q_WI.normalize();
  return y;
}

}  // namespace vid::dynamics
