/// @file swls_residuals.cpp
/// @brief Pre-integration (docs/model.md eq. (58)) and residual weights of the SWLS.
#include "massid/filters/swls_residuals.h"

#include <Eigen/Cholesky>

#include "geometry/so3.h"

namespace vid::massid {

void swls_pack(const QuadMassState& x, double* a) {
  const Eigen::Quaterniond q = x.q_WI.normalized();
  a[0] = q.x();
  a[1] = q.y();
  a[2] = q.z();
  a[3] = q.w();
  for (int i = 0; i < 3; ++i) {
    a[4 + i] = x.p_WI(i);
    a[7 + i] = x.v_WI(i);
  }
  a[10] = x.mass_kg;
}

QuadMassState swls_unpack(const double* a) {
  QuadMassState x;
  x.q_WI = Eigen::Quaterniond(a[3], a[0], a[1], a[2]).normalized();
  x.p_WI = Eigen::Vector3d(a[4], a[5], a[6]);
  x.v_WI = Eigen::Vector3d(a[7], a[8], a[9]);
  x.mass_kg = a[10];
  return x;
}

void SwlsPreintegration::add(const QuadMassInput& u, double dt, double q_var, double p_var,
                             double v_var, double m_var, double mass_lin) {
  const Eigen::Vector3d phi = u.w_I * dt;
  const Eigen::Matrix3d G = gamma.toRotationMatrix();
  const Eigen::Vector3d jl_e3 = so3::left_jacobian(phi).col(2);
  const Eigen::Vector3d g2_e3 = so3_gamma2(phi).col(2);
  // Covariance of [theta, p, v] errors: the model's Jacobian with R = gamma, a = T / m.
  QuadMassState lin;
  lin.q_WI = gamma;
  lin.mass_kg = mass_lin;
  const QuadrotorMassModel::StateMat F = QuadrotorMassModel().state_jacobian(lin, u, dt);
  Eigen::Matrix<double, 9, 9> Q = Eigen::Matrix<double, 9, 9>::Zero();
  Q.diagonal().segment<3>(0).setConstant(q_var * dt);
  Q.diagonal().segment<3>(3).setConstant(p_var * dt);
  Q.diagonal().segment<3>(6).setConstant(v_var * dt);
  cov = F.topLeftCorner<9, 9>() * cov * F.topLeftCorner<9, 9>().transpose() + Q;
  mass_var += m_var * dt;
  alpha += beta * dt + u.thrust_N * G * g2_e3 * dt * dt;
  beta += u.thrust_N * G * jl_e3 * dt;
  gamma = so3::boxplus(gamma, phi);
  dt_sum += dt;
}

SwlsDynamicResidual::SwlsDynamicResidual(const SwlsPreintegration& p, double g)
    : pre(p), gravity(g) {
  // sqrt_info = L^-1 with cov = L L^T, so |sqrt_info r|^2 = r^T cov^-1 r.
  Eigen::LLT<Eigen::Matrix<double, 9, 9>> llt(p.cov);
  sqrt_info = llt.matrixL().solve(Eigen::Matrix<double, 9, 9>::Identity());
  sqrt_info_m = 1.0 / std::sqrt(p.mass_var);
}

}  // namespace vid::massid
