#pragma once
/// @file swls_residuals.h
/// @brief Residuals of the sliding-window least squares (docs/model.md eqs. (57)-(59)), templated
/// on the scalar so Ceres can differentiate them. A window state is stored as 11 ambient
/// numbers [qx, qy, qz, qw, p_WI (3), v_WI (3), m] (q_WI in Eigen's coefficient order); its
/// tangent is the model's error state [dtheta, dp, dv, dm] with q = q_hat ⊗ exp(dtheta/2).
///
/// Pre-integration between window states i and j (eq. (58)), thrust in N (the mass is
/// constant over the interval, so it factors out), in the body frame of state i:
///   gamma_{k+1} = gamma_k Exp(w_k dt),  beta_{k+1} = beta_k + T_k gamma_k J_l(w_k dt) e3 dt,
///   alpha_{k+1} = alpha_k + beta_k dt + T_k gamma_k G2(w_k dt) e3 dt^2.
/// Dynamic residual (eq. (59)), whitened by the pre-integrated process covariance:
///   r_theta = Log((q_i ⊗ gamma)^-1 ⊗ q_j),
///   r_p = R_i^T (p_j - p_i - v_i Dt - g Dt^2 / 2) - alpha / m_i,
///   r_v = R_i^T (v_j - v_i - g Dt) - beta / m_i,  r_m = m_j - m_i.
/// Measurement residual (eq. (57)): y_k ⊟ h(x_k), whitened by R^-1/2.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

#include "massid/filters/quadrotor_mass_model.h"

namespace vid::massid {

constexpr int kSwlsAmbient = 11;  ///< [q(4), p(3), v(3), m]
constexpr int kSwlsTangent = 10;

/// @brief Rotation vector of a unit quaternion (any scalar type; small-angle branch keeps
/// derivatives finite at the identity).
template <class T>
Eigen::Matrix<T, 3, 1> quat_log_t(const Eigen::Quaternion<T>& q_in) {
  using std::atan2;
  using std::sqrt;
  Eigen::Quaternion<T> q = q_in;
  if (q.w() < T(0)) q.coeffs() = -q.coeffs();
  const T sq = q.vec().squaredNorm();
  if (sq < T(1e-16)) return T(2) * q.vec() / q.w();
  const T n = sqrt(sq);
  return (T(2) * atan2(n, q.w()) / n) * q.vec();
}

/// @brief Pack / unpack the ambient vector of a window state.
void swls_pack(const QuadMassState& x, double* ambient);
QuadMassState swls_unpack(const double* ambient);

/// @brief Pre-integrated thrust and rotation between two window states, with the covariance
/// of [r_theta, r_p, r_v] from the process random walks.
struct SwlsPreintegration {
  double dt_sum = 0.0;
  Eigen::Quaterniond gamma = Eigen::Quaterniond::Identity();  ///< rotation I_i -> I_j
  Eigen::Vector3d alpha = Eigen::Vector3d::Zero();            ///< [N s^2] in I_i
  Eigen::Vector3d beta = Eigen::Vector3d::Zero();             ///< [N s] in I_i
  Eigen::Matrix<double, 9, 9> cov = Eigen::Matrix<double, 9, 9>::Zero();
  double mass_var = 0.0;  ///< variance of r_m
  /// @brief Add one held input over dt; q_var, p_var, v_var, m_var are random-walk spectral
  /// densities; mass_lin linearizes the covariance propagation.
  void add(const QuadMassInput& u, double dt, double q_var, double p_var, double v_var,
           double m_var, double mass_lin);
};

/// @brief Whitened dynamic residual between consecutive window states (10 residuals).
struct SwlsDynamicResidual {
  SwlsPreintegration pre;
  double gravity = kDefaultGravity;
  Eigen::Matrix<double, 9, 9> sqrt_info = Eigen::Matrix<double, 9, 9>::Identity();
  double sqrt_info_m = 1.0;

  SwlsDynamicResidual(const SwlsPreintegration& p, double g);

  template <class T>
  bool operator()(const T* xi, const T* xj, T* res) const {
    using Vec3 = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Eigen::Quaternion<T>> q_i(xi), q_j(xj);
    const Eigen::Map<const Vec3> p_i(xi + 4), v_i(xi + 7), p_j(xj + 4), v_j(xj + 7);
    const T m_i = xi[10], m_j = xj[10];
    const double Dt = pre.dt_sum;
    const Vec3 g_W(T(0), T(0), T(-gravity));
    const Eigen::Quaternion<T> q_pred = q_i * pre.gamma.cast<T>();
    Eigen::Matrix<T, 9, 1> r;
    r.template segment<3>(0) = quat_log_t<T>(q_pred.conjugate() * q_j);
    const Eigen::Matrix<T, 3, 3> Rt = q_i.conjugate().toRotationMatrix();
    r.template segment<3>(3) =
        Rt * (p_j - p_i - v_i * T(Dt) - T(0.5 * Dt * Dt) * g_W) - pre.alpha.cast<T>() / m_i;
    r.template segment<3>(6) = Rt * (v_j - v_i - g_W * T(Dt)) - pre.beta.cast<T>() / m_i;
    Eigen::Map<Eigen::Matrix<T, 9, 1>> out(res);
    out = sqrt_info.cast<T>() * r;
    res[9] = T(sqrt_info_m) * (m_j - m_i);
    return true;
  }
};

/// @brief Whitened measurement residual y ⊟ h(x) (9 residuals).
struct SwlsMeasurementResidual {
  QuadMassMeas y;
  Eigen::Matrix<double, 9, 1> sqrt_info_diag;

  template <class T>
  bool operator()(const T* x, T* res) const {
    using Vec3 = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Eigen::Quaternion<T>> q(x);
    const Eigen::Map<const Vec3> p(x + 4), v(x + 7);
    Eigen::Matrix<T, 9, 1> r;
    r.template segment<3>(0) = quat_log_t<T>(q.conjugate() * y.q_WI.cast<T>());
    r.template segment<3>(3) = y.p_WI.cast<T>() - p;
    r.template segment<3>(6) = y.v_WI.cast<T>() - v;
    for (int i = 0; i < 9; ++i) res[i] = T(sqrt_info_diag(i)) * r(i);
    return true;
  }
};

/// @brief Gaussian prior on one state (initial prior or marginalization prior, eq. (57)):
/// r = J (x ⊟ x_bar) + r0 (10 residuals).
struct SwlsPriorResidual {
  double x_bar[kSwlsAmbient];
  Eigen::Matrix<double, 10, 10> J;
  Eigen::Matrix<double, 10, 1> r0;

  template <class T>
  bool operator()(const T* x, T* res) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(x);
    const Eigen::Quaterniond q_bar(x_bar[3], x_bar[0], x_bar[1], x_bar[2]);
    Eigen::Matrix<T, 10, 1> d;
    d.template segment<3>(0) = quat_log_t<T>(q_bar.cast<T>().conjugate() * q);
    for (int i = 0; i < 7; ++i) d(3 + i) = x[4 + i] - T(x_bar[4 + i]);
    Eigen::Map<Eigen::Matrix<T, 10, 1>> out(res);
    out = J.cast<T>() * d + r0.cast<T>();
    return true;
  }
};

}  // namespace vid::massid
