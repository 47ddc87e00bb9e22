#pragma once
/// @file controller.h
/// @brief Geometric SE(3) tracking controller (Lee et al.) with differential-flatness
/// feed-forward (body rate and angular acceleration of the reference), an integral term and
/// an accelerometer-style disturbance observer, mapping to rotor speeds within limits.

#include <Eigen/Core>
#include <limits>

#include "dynamics/quadrotor.h"
#include "sim/trajectory.h"

namespace vid::sim {

/// @brief Gains (per axis for position) and observer settings.
struct ControllerGains {
  Eigen::Vector3d kp{16.0, 16.0, 20.0};   ///< [1/s^2]
  Eigen::Vector3d kv{8.0, 8.0, 9.0};      ///< [1/s]
  Eigen::Vector3d ki{2.0, 2.0, 2.0};      ///< [1/s^3]
  Eigen::Vector3d kr{250.0, 250.0, 80.0};  ///< attitude, scaled by inertia [1/s^2]
  Eigen::Vector3d kw{30.0, 30.0, 16.0};    ///< body rate, scaled by inertia [1/s]
  double integral_limit = 1.0;            ///< clamp of each integral component [m s]
  double disturbance_tau_s = 0.05;        ///< low-pass of the disturbance observer; <= 0 off
};

/// @brief What the controller measures at an update (ideal, noise-free vehicle state plus
/// the accelerometer-like specific force a_W - g_W).
struct ControllerInput {
  double t_s = 0.0;
  dynamics::QuadrotorState state;
  Eigen::Vector3d accel_W = Eigen::Vector3d::Zero();  ///< current true acceleration
  /// The gear touches the floor (an autopilot's ground-contact flag, idealised as the true
  /// contact): the integral and the disturbance observer hold their values, since the ground
  /// reaction is no disturbance to fly against.
  bool in_contact = false;
  /// Collective thrust limit [N] (the take-off spin-up ramp); infinity = none.
  double max_thrust_N = std::numeric_limits<double>::infinity();
};

/// @brief Stateful tracking controller; call update() at the control rate.
class GeometricController {
 public:
  GeometricController(const dynamics::QuadrotorModel& model, const ControllerGains& gains);
  /// @brief Rotor speed command for the reference at input.t_s; dt_s since the last update.
  Eigen::VectorXd update(const ControllerInput& input, const Trajectory& ref, double dt_s);
  /// @brief Desired attitude and body rate of the reference alone (flatness map), also used
  /// to initialise the vehicle on the reference.
  void flat_attitude(const Trajectory& ref, double t_s, const Eigen::Vector3d& disturbance_W,
                     Eigen::Matrix3d* R_WI, Eigen::Vector3d* w_I, Eigen::Vector3d* dw_I) const;
  /// @brief Rotor speeds producing collective thrust T [N] and torque M_I [N m] (clipped).
  Eigen::VectorXd allocate(double thrust_N, const Eigen::Vector3d& torque_I) const;
  /// @brief Rotor speeds for collective thrust @p thrust_N with the attitude held level at
  /// heading @p yaw (zero desired rate): spin-up and spin-down on the ground.
  Eigen::VectorXd attitude_hold(const dynamics::QuadrotorState& x, double thrust_N, double yaw) const;
  /// @brief Start tracking afresh (e.g. at lift-off): integral zero, observer seeded with
  /// @p disturbance_W.
  void reset(const Eigen::Vector3d& disturbance_W);
  /// @brief Current disturbance estimate (world force, N).
  const Eigen::Vector3d& disturbance_W() const { return dist_W_; }
  /// @brief Seed the observer (e.g. with the initial external force).
  void set_disturbance_W(const Eigen::Vector3d& f) { dist_W_ = f; }

 private:
  Eigen::Matrix3d desired_rotation(const Eigen::Vector3d& force_W, double yaw) const;

  const dynamics::QuadrotorModel& model_;
  ControllerGains gains_;
  Eigen::MatrixXd alloc_pinv_;
  Eigen::Vector3d integral_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d dist_W_ = Eigen::Vector3d::Zero();
  bool first_ = true;
};

}  // namespace vid::sim
