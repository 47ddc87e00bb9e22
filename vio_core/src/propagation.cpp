/// @file propagation.cpp
/// @brief Mean propagation (closed-form rotation + RK4 translation) and its exact Jacobians.
#include "vio_core/propagation.h"

#include <cmath>

#include "geometry/so3.h"
#include "vio_core/covariance.h"

namespace vid {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

constexpr double kStage[3] = {0.0, 0.5, 1.0};

// Accelerations at the three RK4 stage times (s = 0, dt/2, dt): the body-frame drive a[i]
// that is rotated into W, and the world-frame offset o[i] added after rotation.
struct Drive {
  Vector3d a[3];
  Vector3d o[3];
};

// imu: a = a_m - b_a; dynamics: a = s T_m (+ F_I(s) in the body-frame force model), and
// o = g (+ F_W(s) in the world-frame model), with F(s) = F_k + F_dot s (force-rate state).
// A linear body drag (dynamics mode) is evaluated at the interval's start and held over it, as a
// world-frame offset: over a 2.5-10 ms interval it changes by D dv, far below the noise.
Drive stage_drive(const ImuState& x, const ImuInterval& u, PropagationMode mode, ForceFrame frame,
                  const Vector3d& g_W, const DiscreteNoise& n, const Vector3d& drag) {
  Drive d;
  const Vector3d mid = 0.5 * (u.drive0 + u.drive1);
  const Vector3d raw[3] = {u.drive0, mid, u.drive1};
  const bool with_drag = mode == PropagationMode::kDynamics && !drag.isZero(0.0);
  const Vector3d o = with_drag ? Vector3d(g_W + x.T_WI.q * drag_in_body(x, drag)) : g_W;
  for (int i = 0; i < 3; ++i) {
    d.o[i] = o;
    if (mode == PropagationMode::kImu) {
      d.a[i] = raw[i] - x.b_a - n.n_a;
      continue;
    }
    d.a[i] = x.thrust_scale * raw[i] + n.n_a;
    const Vector3d F_s = x.F_ext + x.F_dot * (kStage[i] * u.dt);
    (frame == ForceFrame::kBody ? d.a[i] : d.o[i]) += F_s;
  }
  return d;
}

Vector3d mid_rate(const ImuState& x, const ImuInterval& u, const DiscreteNoise& n) {
  return 0.5 * (u.gyro0 + u.gyro1) - x.b_g - n.n_g;
}

// Simpson weights of the velocity (dt/6 [1 4 1]) and position (dt^2/6 [1 2 0]) increments.
template <typename T>
T simpson_v(double dt, const T& f0, const T& f1, const T& f2) {
  return dt / 6.0 * (f0 + 4.0 * f1 + f2);
}
template <typename T>
T simpson_p(double dt, const T& f0, const T& f1) {
  return dt * dt / 6.0 * (f0 + 2.0 * f1);
}

}  // namespace

ImuState propagate_mean(const ImuState& x, const ImuInterval& u, PropagationMode mode,
                        const Vector3d& g_W, const DiscreteNoise& noise, ForceFrame frame,
                        const Vector3d& linear_drag) {
  const double dt = u.dt;
  const Vector3d w = mid_rate(x, u, noise);
  const Drive d = stage_drive(x, u, mode, frame, g_W, noise, linear_drag);
  const Matrix3d R_k = x.T_WI.q.toRotationMatrix();
  Vector3d f[3];
  for (int i = 0; i < 3; ++i) {
    f[i] = R_k * (so3::exp(w * (kStage[i] * dt)) * d.a[i]) + d.o[i];
  }
  ImuState y = x;
  y.T_WI.q = so3::boxplus(x.T_WI.q, w * dt);
  y.v_WI = x.v_WI + simpson_v(dt, f[0], f[1], f[2]);
  y.T_WI.p = x.T_WI.p + x.v_WI * dt + simpson_p(dt, f[0], f[1]);
  y.b_g = x.b_g + noise.w_g;
  y.b_a = x.b_a + noise.w_a;
  if (mode == PropagationMode::kDynamics) {
    y.F_ext = x.F_ext + x.F_dot * dt + noise.w_F;
    y.F_dot = x.F_dot + noise.w_Fd;
    y.thrust_scale = x.thrust_scale + noise.w_s;
  }
  return y;
}

void propagation_jacobians(const ImuState& x_k, const ImuFej& fej_k, const ImuState& x_k1,
                           const ImuInterval& u, PropagationMode mode, const Vector3d& g_W,
                           Eigen::MatrixXd* Phi_out, Eigen::MatrixXd* G_out, ForceFrame frame,
                           bool force_rate, bool thrust_scale, const Vector3d& linear_drag) {
  namespace ix = imu_idx;
  const bool dyn = mode == PropagationMode::kDynamics;
  const bool rate = dyn && force_rate;
  const ImuLayout layout{dyn, rate, dyn && thrust_scale};
  const int d = layout.dim();
  const int nn = layout.noise_dim();
  const double dt = u.dt;
  const Vector3d w = mid_rate(x_k, u, DiscreteNoise{});
  const Drive drv = stage_drive(x_k, u, mode, frame, g_W, DiscreteNoise{}, linear_drag);
  const bool world_force = dyn && frame == ForceFrame::kWorld;
  const Matrix3d R_k = x_k.T_WI.q.toRotationMatrix();
  const Matrix3d R_k_fej = fej_k.T_WI.q.toRotationMatrix();
  const Matrix3d R_k1 = x_k1.T_WI.q.toRotationMatrix();  // first estimate of t_{k+1}

  Eigen::MatrixXd& Phi = *Phi_out;
  Phi.setIdentity(d, d);
  // Orientation: dtheta_{k+1} = R_{k+1}^T R_k dtheta_k - Jr(w dt) dt db_g  (FEJ rotations).
  Phi.block<3, 3>(ix::kTheta, ix::kTheta) = R_k1.transpose() * R_k_fej;
  const Matrix3d Jr_dt = so3::right_jacobian(w * dt) * dt;
  Phi.block<3, 3>(ix::kTheta, ix::kBg) = -Jr_dt;
  // Position/velocity vs orientation in the "global difference" form, which equals the exact
  // Jacobian -R_k [sum w_i dR_i a_i]x when the first estimates equal the current estimate.
  // The world offset (g, and F_W in the world-force model) does not turn with dtheta.
  const Vector3d dv = x_k1.v_WI - fej_k.v_WI - simpson_v(dt, drv.o[0], drv.o[1], drv.o[2]);
  const Vector3d dp = x_k1.T_WI.p - fej_k.T_WI.p - fej_k.v_WI * dt - simpson_p(dt, drv.o[0], drv.o[1]);
  Phi.block<3, 3>(ix::kV, ix::kTheta) = -so3::skew(dv) * R_k_fej;
  Phi.block<3, 3>(ix::kP, ix::kTheta) = -so3::skew(dp) * R_k_fej;
  Phi.block<3, 3>(ix::kP, ix::kV) = Matrix3d::Identity() * dt;
  if (dyn && !linear_drag.isZero(0.0)) {
    // Drag a_W = -R D R^T v, held over the interval (velocity += a dt, position += a dt^2 / 2).
    // With u = R^T v and R = R_hat Exp(dtheta): d a_W / d dtheta = R ([D u]x - D [u]x),
    // d a_W / d v = -R D R^T, at the first estimates like the other columns: then Phi maps the
    // yaw direction of the nullspace at t_k to the one at t_k+1 (drag adds [e_z]x a_drag dt).
    const Eigen::DiagonalMatrix<double, 3> D(linear_drag);
    const Vector3d u_I = R_k_fej.transpose() * fej_k.v_WI;
    const Matrix3d A_theta = R_k_fej * (so3::skew(D * u_I) - D * so3::skew(u_I));
    const Matrix3d A_v = -R_k_fej * D * R_k_fej.transpose();
    Phi.block<3, 3>(ix::kV, ix::kTheta) += A_theta * dt;
    Phi.block<3, 3>(ix::kP, ix::kTheta) += A_theta * (0.5 * dt * dt);
    Phi.block<3, 3>(ix::kV, ix::kV) += A_v * dt;
    Phi.block<3, 3>(ix::kP, ix::kV) += A_v * (0.5 * dt * dt);
  }

  // Bias / force columns: sensitivities of the stage accelerations f_i.
  Matrix3d Bg[3];  // d f_i / d b_g
  Matrix3d Ba[3];  // d f_i / d (drive offset): -dR for imu b_a, +dR for dynamics F_ext
  for (int i = 0; i < 3; ++i) {
    const double s = kStage[i] * dt;
    const Matrix3d dR = so3::exp(w * s);
    Bg[i] = R_k * dR * so3::skew(drv.a[i]) * so3::right_jacobian(w * s) * s;
    Ba[i] = R_k * dR;
  }
  const Matrix3d v_bg = simpson_v(dt, Bg[0], Bg[1], Bg[2]);
  const Matrix3d p_bg = simpson_p(dt, Bg[0], Bg[1]);
  const Matrix3d v_a = simpson_v(dt, Ba[0], Ba[1], Ba[2]);
  const Matrix3d p_a = simpson_p(dt, Ba[0], Ba[1]);
  Phi.block<3, 3>(ix::kV, ix::kBg) = v_bg;
  Phi.block<3, 3>(ix::kP, ix::kBg) = p_bg;
  if (dyn) {
    // Stage i sees F_k + F_dot s_i, through R_k dR_i (body force) or directly (world force).
    const Matrix3d I3 = Matrix3d::Identity();
    const Matrix3d M[3] = {world_force ? I3 : Ba[0], world_force ? I3 : Ba[1], world_force ? I3 : Ba[2]};
    Phi.block<3, 3>(ix::kV, ix::kF) = simpson_v(dt, M[0], M[1], M[2]);
    Phi.block<3, 3>(ix::kP, ix::kF) = simpson_p(dt, M[0], M[1]);
    if (rate) {
      const Matrix3d Ms0 = Matrix3d::Zero();  // s_0 = 0
      const Matrix3d Ms1 = M[1] * (0.5 * dt);
      const Matrix3d Ms2 = M[2] * dt;
      Phi.block<3, 3>(ix::kV, ix::kFdot) = simpson_v(dt, Ms0, Ms1, Ms2);
      Phi.block<3, 3>(ix::kP, ix::kFdot) = simpson_p(dt, Ms0, Ms1);
      Phi.block<3, 3>(ix::kF, ix::kFdot) = I3 * dt;
    }
    if (layout.thrust_scale) {
      // Stage i's drive is s T_m,i, turned by R_k dR_i: d f_i / d s = R_k dR_i T_m,i.
      const Vector3d T[3] = {u.drive0, 0.5 * (u.drive0 + u.drive1), u.drive1};
      const int is = layout.thrust_scale_index();
      Phi.block<3, 1>(ix::kV, is) = simpson_v(dt, Vector3d(Ba[0] * T[0]), Vector3d(Ba[1] * T[1]), Vector3d(Ba[2] * T[2]));
      Phi.block<3, 1>(ix::kP, is) = simpson_p(dt, Vector3d(Ba[0] * T[0]), Vector3d(Ba[1] * T[1]));
    }
  } else {
    Phi.block<3, 3>(ix::kV, ix::kBa) = -v_a;
    Phi.block<3, 3>(ix::kP, ix::kBa) = -p_a;
  }

  Eigen::MatrixXd& G = *G_out;
  G.setZero(d, nn);
  // Gyro noise enters exactly like a gyro-bias error held over the interval.
  G.block<3, 3>(ix::kTheta, noise_idx::kNg) = -Jr_dt;
  G.block<3, 3>(ix::kV, noise_idx::kNg) = v_bg;
  G.block<3, 3>(ix::kP, noise_idx::kNg) = p_bg;
  // Accel noise (imu: like -b_a) or thrust noise (dynamics: like +F_ext).
  const double sgn = dyn ? 1.0 : -1.0;
  G.block<3, 3>(ix::kV, noise_idx::kNa) = sgn * v_a;
  G.block<3, 3>(ix::kP, noise_idx::kNa) = sgn * p_a;
  G.block<3, 3>(ix::kBg, noise_idx::kWg).setIdentity();
  G.block<3, 3>(ix::kBa, noise_idx::kWa).setIdentity();
  if (dyn) G.block<3, 3>(ix::kF, noise_idx::kWF).setIdentity();
  if (rate) G.block<3, 3>(ix::kFdot, noise_idx::kWFd).setIdentity();
  if (layout.thrust_scale) G(layout.thrust_scale_index(), nn - 1) = 1.0;
}

Eigen::VectorXd discrete_noise_variances(const EstimatorParams& p, double dt, double noise_scale,
                                         double thrust_noise_scale) {
  const ImuLayout layout = ImuLayout::from(p);
  const bool dyn = layout.force;
  const bool rate = layout.force_rate;
  Eigen::VectorXd q(layout.noise_dim());
  const double s2 = noise_scale * noise_scale;
  // Held white noise of density sigma over dt has variance sigma^2 / dt.
  q.segment<3>(noise_idx::kNg).setConstant(s2 * p.gyro_noise_density * p.gyro_noise_density / dt);
  const double na = dyn ? thrust_noise_scale * p.thrust_noise_density : p.accel_noise_density;
  q.segment<3>(noise_idx::kNa).setConstant(s2 * na * na / dt);
  // Random-walk increments have variance sigma^2 dt.
  q.segment<3>(noise_idx::kWg).setConstant(p.gyro_random_walk * p.gyro_random_walk * dt);
  q.segment<3>(noise_idx::kWa).setConstant(p.accel_random_walk * p.accel_random_walk * dt);
  if (dyn) q.segment<3>(noise_idx::kWF).setConstant(p.force_random_walk * p.force_random_walk * dt);
  if (rate) {
    q.segment<3>(noise_idx::kWFd).setConstant(p.force_rate_random_walk * p.force_rate_random_walk * dt);
  }
  if (layout.thrust_scale) q(q.size() - 1) = p.thrust_scale_random_walk * p.thrust_scale_random_walk * dt;
  return q;
}

void propagate(FilterState& state, const ImuInterval& u, const EstimatorParams& params,
               double noise_scale, double thrust_noise_scale) {
  const Vector3d g_W(0.0, 0.0, -params.gravity);
  if (!params.use_fej) state.reset_imu_fej();
  const ImuState x_k = state.imu();
  const Vector3d drag = state.with_drag() ? state.linear_drag() : Vector3d::Zero();
  const ImuState x_k1 = propagate_mean(x_k, u, params.mode, g_W, DiscreteNoise{}, state.force_frame(), drag);
  Eigen::MatrixXd Phi, G;
  propagation_jacobians(x_k, state.imu_fej(), x_k1, u, params.mode, g_W, &Phi, &G, state.force_frame(),
                        state.with_force_rate(), state.with_thrust_scale(), drag);
  const Eigen::VectorXd q = discrete_noise_variances(params, u.dt, noise_scale, thrust_noise_scale);

  // IMU block and its cross-covariances with everything else (clones, calibration).
  covariance::propagate_leading(state.P(), state.dim(), Phi, G * q.asDiagonal() * G.transpose());
  state.imu() = x_k1;
  state.imu().T_WI.q = so3::normalized(x_k1.T_WI.q);
  // The freshly propagated value is the first estimate at the new time.
  state.reset_imu_fej();
  state.set_time(state.time() + static_cast<TimeNs>(std::llround(u.dt * 1e9)));
}

}  // namespace vid
