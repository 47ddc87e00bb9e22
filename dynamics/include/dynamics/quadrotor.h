#pragma once
/// @file quadrotor.h
/// @brief Multirotor rigid-body model: per-rotor thrust T_i = k_i n_i^2, rotor drag torque,
/// first-order motor lag, rotor speed limits, optional linear rotor drag, RK4 integration.
///
/// Rotor speeds n are kept in the unit of the rotor sensor (rpm or rad/s, docs/design.md §3); k_i and
/// the drag-torque coefficients are per that unit squared.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "types/calibration.h"

namespace vid::dynamics {

/// @brief One rotor: where it is, how it spins and its coefficients.
struct RotorParams {
  Eigen::Vector3d position_I = Eigen::Vector3d::Zero();  ///< rotor hub in the body frame [m]
  int direction = 1;            ///< +1 spins counter-clockwise seen from above (+z), -1 clockwise
  double thrust_coeff = 0.0;    ///< k_i [N / unit^2]
  double torque_coeff = 0.0;    ///< c_i [N m / unit^2], reaction torque -direction * c_i n^2 about z
};

/// @brief Vehicle constants.
struct QuadrotorParams {
  double mass_kg = 1.0;                                      ///< nominal (initial) mass
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Identity() * 0.01;  ///< J about the CoM in I [kg m^2]
  double arm_length_m = 0.2;
  std::vector<RotorParams> rotors;
  double motor_time_constant_s = 0.02;  ///< first-order lag of rotor speed; 0 = instantaneous
  double rotor_speed_min = 0.0;         ///< [unit]
  double rotor_speed_max = 1e9;         ///< [unit]
  /// Linear rotor drag: F_drag_I = -diag(linear_drag) * v_I [N / (m/s)] (zero = off).
  Eigen::Vector3d linear_drag = Eigen::Vector3d::Zero();
  double gravity = kDefaultGravity;     ///< magnitude; g_W = [0, 0, -gravity]
  /// Unit direction of every rotor's thrust in I (a real thrust axis sits 1-2 deg off the
  /// IMU's z; the simulator's `sensor_faults.thrust_axis`). Default z_I.
  Eigen::Vector3d thrust_axis_I = Eigen::Vector3d::UnitZ();

  /// @brief Symmetric "x" or "+" layout with `count` rotors at `arm_length` and alternating
  /// directions (rotor 0 counter-clockwise), per-rotor k_i and torque/thrust ratio.
  static std::vector<RotorParams> symmetric_layout(const std::string& layout, double arm_length,
                                                   const std::vector<double>& thrust_coeffs,
                                                   const std::vector<int>& directions,
                                                   double torque_to_thrust_m);
  /// @brief Throws std::invalid_argument on inconsistent values (names the field).
  void validate() const;
};

/// @brief Continuous state of the vehicle.
struct QuadrotorState {
  Eigen::Vector3d p_WI = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_WI = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_WI = Eigen::Quaterniond::Identity();
  Eigen::Vector3d w_I = Eigen::Vector3d::Zero();  ///< body rate in I [rad/s]
  Eigen::VectorXd rotor_speeds;                   ///< true rotor speeds [unit]
};

/// @brief Time derivative of QuadrotorState (quaternion as 4-vector w,x,y,z).
struct QuadrotorStateDot {
  Eigen::Vector3d p_dot, v_dot, w_dot;
  Eigen::Vector4d q_dot;
  Eigen::VectorXd n_dot;
};

/// @brief Member-wise sum of two derivatives (they form a vector space, as dynamics::rk4_step needs).
QuadrotorStateDot operator+(const QuadrotorStateDot& a, const QuadrotorStateDot& b);
/// @brief Every member of a derivative scaled by s.
QuadrotorStateDot operator*(double s, const QuadrotorStateDot& d);

/// @brief Everything outside the vehicle: external force and current mass, both possibly
/// state- and time-dependent (ropes, wind, payloads). Must be deterministic.
class Environment {
 public:
  virtual ~Environment() = default;
  /// @brief External force on the CoM in W [N], excluding gravity, thrust and rotor drag.
  virtual Eigen::Vector3d force_W(double t_s, const QuadrotorState& x) const = 0;
  /// @brief Mass at time t [kg].
  virtual double mass_kg(double t_s) const = 0;
  /// @brief External torque about the CoM in I [N m] (e.g. ground contact at the landing
  /// gear); none by default.
  virtual Eigen::Vector3d torque_I(double /*t_s*/, const QuadrotorState& /*x*/) const {
    return Eigen::Vector3d::Zero();
  }
  /// @brief False when torque_I() is zero for every state (the default): the model then
  /// skips it, so environments without torque integrate exactly as before it existed.
  virtual bool has_torque() const { return false; }
};

/// @brief Forces acting at one instant (for sensors, ground truth and checks).
struct ForceBreakdown {
  Eigen::Vector3d thrust_I = Eigen::Vector3d::Zero();   ///< sum_i T_i thrust_axis_I [N]
  Eigen::Vector3d torque_I = Eigen::Vector3d::Zero();   ///< rotor torques [N m]
  Eigen::Vector3d drag_W = Eigen::Vector3d::Zero();     ///< linear rotor drag [N]
  Eigen::Vector3d env_W = Eigen::Vector3d::Zero();      ///< Environment::force_W [N]
  Eigen::Vector3d env_torque_I = Eigen::Vector3d::Zero();  ///< Environment::torque_I [N m]
  double mass_kg = 0.0;
  Eigen::Vector3d accel_W = Eigen::Vector3d::Zero();    ///< a_W [m/s^2]
  /// @brief All non-thrust, non-gravity force (env + drag) in W [N]; this is force0.
  Eigen::Vector3d external_W() const { return drag_W + env_W; }
};

/// @brief The rigid-body model and its integrator.
class QuadrotorModel {
 public:
  explicit QuadrotorModel(QuadrotorParams params);
  const QuadrotorParams& params() const { return params_; }
  int rotor_count() const { return static_cast<int>(params_.rotors.size()); }

  /// @brief Per-rotor thrust T_i = k_i n_i^2 [N].
  Eigen::VectorXd rotor_thrusts(const Eigen::VectorXd& n) const;
  /// @brief Sum of thrusts (along thrust_axis_I) and the rotor torque in I.
  void thrust_and_torque(const Eigen::VectorXd& n, Eigen::Vector3d* thrust_I,
                         Eigen::Vector3d* torque_I) const;
  /// @brief Clamp rotor speeds to [min, max].
  Eigen::VectorXd clamp_speeds(const Eigen::VectorXd& n) const;
  /// @brief 4 x N map from n_i^2 to [T, Mx, My, Mz] (allocation).
  Eigen::MatrixXd allocation_matrix() const;

  /// @brief Forces and acceleration at (t, x).
  ForceBreakdown forces(double t_s, const QuadrotorState& x, const Environment& env) const;
  /// @brief State derivative with rotor speed command n_cmd (held constant).
  QuadrotorStateDot derivative(double t_s, const QuadrotorState& x, const Eigen::VectorXd& n_cmd,
                               const Environment& env) const;
  /// @brief One classical RK4 step (dynamics/rk4.h) of length dt with n_cmd held (zero-order
  /// hold); q is integrated as four plain coefficients and normalized after the step.
  QuadrotorState rk4_step(double t_s, double dt_s, const QuadrotorState& x,
                          const Eigen::VectorXd& n_cmd, const Environment& env) const;

 private:
  QuadrotorParams params_;
};

}  // namespace vid::dynamics
