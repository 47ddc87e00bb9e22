/// @file quadrotor_mass_model.cpp
/// @brief docs/model.md eq. (55): discrete propagation (exact for a held input) and its Jacobians.
#include "massid/filters/quadrotor_mass_model.h"

#include <cmath>

#include "geometry/so3.h"

namespace vid::massid {

Eigen::Matrix3d so3_gamma2(const Eigen::Vector3d& phi) {
  const double t2 = phi.squaredNorm();
  const double t = std::sqrt(t2);
  const Eigen::Matrix3d W = so3::skew(phi);
  double a, b;  // G2 = I/2 + a W + b W^2
  if (t < 0.05) {  // series: the closed form of b cancels badly for small angles
    a = 1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0;
    b = 1.0 / 24.0 - t2 / 720.0 + t2 * t2 / 40320.0;
  } else {
    a = (t - std::sin(t)) / (t2 * t);
    b = (t2 + 2.0 * std::cos(t) - 2.0) / (2.0 * t2 * t2);
  }
  return 0.5 * Eigen::Matrix3d::Identity() + a * W + b * W * W;
}

const QuadrotorMassModel::InputTerms& QuadrotorMassModel::terms(const Input& u, double dt) const {
  const Eigen::Vector3d phi = u.w_I * dt;
  if (phi != cache_.w_dt) {
    cache_.w_dt = phi;
    cache_.dq = so3::quat_exp(phi);
    cache_.exp_T = cache_.dq.toRotationMatrix().transpose();
    cache_.jl_e3 = so3::left_jacobian(phi).col(2);
    cache_.g2_e3 = so3_gamma2(phi).col(2);
  }
  return cache_;
}

QuadMassState QuadrotorMassModel::propagate(const State& x, const Input& u, double dt) const {
  const InputTerms& k = terms(u, dt);
  const Eigen::Matrix3d R_WI = x.q_WI.toRotationMatrix();
  const double a = u.thrust_N / x.mass_kg;
  const Eigen::Vector3d g = g_W();
  State y;
  y.q_WI = (x.q_WI * k.dq).normalized();
  y.v_WI = x.v_WI + (a * R_WI * k.jl_e3 + g) * dt;
  y.p_WI = x.p_WI + x.v_WI * dt + (a * R_WI * k.g2_e3 + 0.5 * g) * dt * dt;
  y.mass_kg = x.mass_kg;
  return y;
}

QuadrotorMassModel::StateMat QuadrotorMassModel::state_jacobian(const State& x, const Input& u,
                                                                double dt) const {
  using namespace qm_idx;
  const InputTerms& k = terms(u, dt);
  const Eigen::Matrix3d R_WI = x.q_WI.toRotationMatrix();
  const double a = u.thrust_N / x.mass_kg;
  const Eigen::Vector3d& jl_e3 = k.jl_e3;
  const Eigen::Vector3d& g2_e3 = k.g2_e3;
  StateMat F = StateMat::Identity();
  // R Exp(dtheta) Exp(phi) = R Exp(phi) Exp(Exp(phi)^T dtheta)
  F.block<3, 3>(kTheta, kTheta) = k.exp_T;
  // R Exp(dtheta) c ≈ R c - R [c]x dtheta
  F.block<3, 3>(kV, kTheta) = -a * dt * R_WI * so3::skew(jl_e3);
  F.block<3, 1>(kV, kM) = -(a / x.mass_kg) * dt * R_WI * jl_e3;
  F.block<3, 3>(kP, kTheta) = -a * dt * dt * R_WI * so3::skew(g2_e3);
  F.block<3, 3>(kP, kV) = dt * Eigen::Matrix3d::Identity();
  F.block<3, 1>(kP, kM) = -(a / x.mass_kg) * dt * dt * R_WI * g2_e3;
  return F;
}

QuadrotorMassModel::StateVec QuadrotorMassModel::continuous_rate(const State& x,
                                                                 const Input& u) const {
  StateVec r;
  r.segment<3>(qm_idx::kTheta) = u.w_I;
  r.segment<3>(qm_idx::kP) = x.v_WI;
  r.segment<3>(qm_idx::kV) =
      x.q_WI * Eigen::Vector3d(0.0, 0.0, u.thrust_N / x.mass_kg) + g_W();
  r(qm_idx::kM) = 0.0;
  return r;
}

QuadMassMeas QuadrotorMassModel::measure(const State& x) const {
  return Meas{x.q_WI, x.p_WI, x.v_WI};
}

QuadrotorMassModel::MeasJac QuadrotorMassModel::measurement_jacobian(const State&) const {
  MeasJac H = MeasJac::Zero();
  H.leftCols<9>().setIdentity();
  return H;
}

QuadMassState QuadrotorMassModel::boxplus(const State& x, const StateVec& dx) {
  State y;
  y.q_WI = so3::boxplus(x.q_WI, dx.segment<3>(qm_idx::kTheta));
  y.p_WI = x.p_WI + dx.segment<3>(qm_idx::kP);
  y.v_WI = x.v_WI + dx.segment<3>(qm_idx::kV);
  y.mass_kg = x.mass_kg + dx(qm_idx::kM);
  return y;
}

void QuadrotorMassModel::boxplus_pm(const State& x, const StateVec& dx, State* plus,
                                    State* minus) {
  const Eigen::Quaterniond e = so3::quat_exp(dx.segment<3>(qm_idx::kTheta));
  plus->q_WI = (x.q_WI * e).normalized();
  minus->q_WI = (x.q_WI * e.conjugate()).normalized();
  const Eigen::Vector3d dp = dx.segment<3>(qm_idx::kP);
  const Eigen::Vector3d dv = dx.segment<3>(qm_idx::kV);
  plus->p_WI = x.p_WI + dp;
  minus->p_WI = x.p_WI - dp;
  plus->v_WI = x.v_WI + dv;
  minus->v_WI = x.v_WI - dv;
  plus->mass_kg = x.mass_kg + dx(qm_idx::kM);
  minus->mass_kg = x.mass_kg - dx(qm_idx::kM);
}

QuadrotorMassModel::StateVec QuadrotorMassModel::boxminus(const State& x1, const State& x0) {
  StateVec d;
  d.segment<3>(qm_idx::kTheta) = so3::boxminus(x1.q_WI, x0.q_WI);
  d.segment<3>(qm_idx::kP) = x1.p_WI - x0.p_WI;
  d.segment<3>(qm_idx::kV) = x1.v_WI - x0.v_WI;
  d(qm_idx::kM) = x1.mass_kg - x0.mass_kg;
  return d;
}

QuadrotorMassModel::MeasVec QuadrotorMassModel::meas_boxminus(const Meas& y1, const Meas& y0) {
  MeasVec d;
  d.segment<3>(0) = so3::boxminus(y1.q_WI, y0.q_WI);
  d.segment<3>(3) = y1.p_WI - y0.p_WI;
  d.segment<3>(6) = y1.v_WI - y0.v_WI;
  return d;
}

QuadMassMeas QuadrotorMassModel::meas_of(const MassIdSample& s) {
  return Meas{s.q_WI.normalized(), s.p_WI, s.v_WI};
}

QuadMassInput QuadrotorMassModel::input_of(const MassIdSample& s) {
  return Input{s.thrust_cmd, s.w_I};
}

}  // namespace vid::massid
