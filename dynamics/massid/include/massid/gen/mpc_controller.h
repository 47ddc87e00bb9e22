#pragma once
/// @file mpc_controller.h
/// @brief Tracking controller of the study: a linearized MPC on the translational double
/// integrator (condensed box-constrained QP per axis, solved by accelerated projected
/// gradient), a position integral for offset-free tracking, the thrust/attitude mapping with
/// the controller's (wrong) nominal mass, and a P attitude loop with jerk feed-forward that
/// outputs body rates. Formulation: dynamics/massid/README.md "Data generation".

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "massid/gen/reference_trajectory.h"
#include "massid/gen/study_config.h"

namespace vid::massid::gen {

/// @brief Box-constrained convex QP  min 1/2 u'Hu + f'u  s.t. lo <= u <= hi.
class BoxQp {
 public:
  /// @brief Prepare for Hessian H (symmetric positive definite).
  explicit BoxQp(const Eigen::MatrixXd& H);
  /// @brief Solve; returns the number of projected-gradient iterations (0 when the
  /// unconstrained optimum is feasible).
  int solve(const Eigen::VectorXd& f, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
            Eigen::VectorXd* u, int max_iterations = 300, double tolerance = 1e-9) const;

 private:
  Eigen::MatrixXd H_;
  Eigen::MatrixXd H_inv_;
  double step_ = 0.0;  ///< 1 / largest eigenvalue
};

/// @brief Controller output for one control period (held until the next one).
struct ControlOutput {
  double thrust_N = 0.0;                         ///< collective thrust along z_I
  Eigen::Vector3d w_I = Eigen::Vector3d::Zero(); ///< body rate command [rad/s]
  Eigen::Vector3d a_cmd_W = Eigen::Vector3d::Zero();  ///< acceleration the MPC asked for
  /// A bound was active: acceleration anywhere in the MPC horizon, or tilt, thrust or rate now.
  bool saturated = false;
};

/// @brief MPC tracking controller with a nominal (possibly wrong) mass.
class MpcController {
 public:
  /// @param nominal_mass_kg  the mass the controller believes (maps acceleration to thrust)
  /// @param thrust_min_N, thrust_max_N  physical thrust bounds
  /// @param control_dt_s  period between compute() calls (integral action)
  MpcController(const ControllerSettings& settings, double nominal_mass_kg, double gravity,
                double thrust_min_N, double thrust_max_N, double control_dt_s);
  /// @brief Command for time t from the measured state.
  ControlOutput compute(double t_s, const Eigen::Quaterniond& q_WI, const Eigen::Vector3d& p_WI,
                        const Eigen::Vector3d& v_WI, const ReferenceTrajectory& reference);

 private:
  ControllerSettings s_;
  double mass_nominal_, gravity_, thrust_min_, thrust_max_, control_dt_;
  Eigen::MatrixXd Gp_, Gv_;  ///< condensed maps from the N accelerations to positions/velocities
  BoxQp qp_;
  Eigen::Vector3d integral_W_ = Eigen::Vector3d::Zero();
};

}  // namespace vid::massid::gen
