#pragma once
/// @file propagation.h
/// @brief IMU-block propagation over one sample interval, both modes.
///
/// Mean: rotation integrated in closed form with the interval's mid-point rate
/// (R_{k+1} = R_k Exp((w_mid - b_g) dt), exact for a constant rate), translation with RK4 on
/// p' = v, v' = R(t) a(t) + o(t), where a(t) is linearly interpolated between the interval's
/// end samples (imu: a_m - b_a; dynamics: T_m, plus F_I for a body-frame force) and
/// o(t) = g (plus F_W for a world-frame force); with the force-rate state the force is
/// F_k + F_dot s over the interval and F_{k+1} = F_k + F_dot dt. R(t) at the RK4 stage times is
/// the closed-form rotation. Because v' does not depend on p or v, RK4 reduces to Simpson's rule.
///
/// Covariance: the exact Jacobians Phi = d x_{k+1} / d x_k and G = d x_{k+1} / d n of this
/// discrete map, with FEJ on the orientation/position/velocity columns (OpenVINS idea written
/// for right perturbation) so that global position and yaw stay unobservable.

#include <Eigen/Core>

#include "vio_core/estimator_params.h"
#include "vio_core/state.h"

namespace vid {

/// @brief Inputs of one interval [t_k, t_k + dt].
struct ImuInterval {
  double dt = 0.0;                                    ///< [s]
  Eigen::Vector3d gyro0 = Eigen::Vector3d::Zero();    ///< w_m at t_k
  Eigen::Vector3d gyro1 = Eigen::Vector3d::Zero();    ///< w_m at t_k + dt
  /// imu mode: a_m at both ends; dynamics mode: T_m at both ends [m/s^2]
  Eigen::Vector3d drive0 = Eigen::Vector3d::Zero();
  Eigen::Vector3d drive1 = Eigen::Vector3d::Zero();
};

/// @brief Discrete noise of one interval. n_g, n_a (imu: accel; dynamics: thrust) are held
/// constant over the interval; w_* are the random-walk increments.
struct DiscreteNoise {
  Eigen::Vector3d n_g = Eigen::Vector3d::Zero();
  Eigen::Vector3d n_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_g = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_F = Eigen::Vector3d::Zero();
  Eigen::Vector3d w_Fd = Eigen::Vector3d::Zero();  ///< force-rate random-walk increment
  double w_s = 0.0;  ///< thrust-scale random-walk increment
};

/// @brief Column offsets of the noise vector [n_g, n_a, w_g, w_a, (w_F), (w_Fd), (w_s)]; w_s is
/// last (ImuLayout::noise_dim() - 1).
namespace noise_idx {
constexpr int kNg = 0;
constexpr int kNa = 3;
constexpr int kWg = 6;
constexpr int kWa = 9;
constexpr int kWF = 12;
constexpr int kWFd = 15;
}  // namespace noise_idx

/// @brief Propagate the IMU mean over one interval (with optional noise, for testing).
/// In dynamics mode v' = R_WI (s T_m + F_I) + g (body-frame force) or R_WI s T_m + F_W + g
/// (world-frame force), with the thrust scale s = x.thrust_scale (1 when it is not estimated).
/// A non-zero linear_drag D (dynamics mode) adds the body drag R_WI (-diag(D) R_WI^T v_WI), taken
/// at the interval's start and held over it.
ImuState propagate_mean(const ImuState& x, const ImuInterval& u, PropagationMode mode,
                        const Eigen::Vector3d& g_W, const DiscreteNoise& noise = {},
                        ForceFrame frame = ForceFrame::kBody,
                        const Eigen::Vector3d& linear_drag = Eigen::Vector3d::Zero());

/// @brief Phi (d x d) and G (d x nn), d = ImuLayout::dim(), nn = ImuLayout::noise_dim() (15 / 18
/// / 21 and 12 / 15 / 18 for imu / dynamics / dynamics with the force-rate state, one more each
/// with the thrust scale).
/// x_k: current estimate at t_k; fej_k: its first estimates; x_k1: propagate_mean(x_k, u).
/// With fej_k equal to x_k these are the exact Jacobians of propagate_mean.
void propagation_jacobians(const ImuState& x_k, const ImuFej& fej_k, const ImuState& x_k1,
                           const ImuInterval& u, PropagationMode mode, const Eigen::Vector3d& g_W,
                           Eigen::MatrixXd* Phi, Eigen::MatrixXd* G,
                           ForceFrame frame = ForceFrame::kBody, bool force_rate = false,
                           bool thrust_scale = false,
                           const Eigen::Vector3d& linear_drag = Eigen::Vector3d::Zero());

/// @brief Diagonal covariance of DiscreteNoise for an interval of length dt.
/// noise_scale multiplies the measurement noises (gaps); thrust noise replaces accel noise in
/// dynamics mode.
Eigen::VectorXd discrete_noise_variances(const EstimatorParams& params, double dt,
                                         double noise_scale = 1.0, double thrust_noise_scale = 1.0);

/// @brief Propagate state mean and covariance (IMU block and its cross terms with clones) by
/// one interval; updates the IMU first estimates (FEJ) and the state time by dt.
void propagate(FilterState& state, const ImuInterval& u, const EstimatorParams& params,
               double noise_scale = 1.0, double thrust_noise_scale = 1.0);

}  // namespace vid
