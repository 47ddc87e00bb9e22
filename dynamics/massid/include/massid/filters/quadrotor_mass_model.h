#pragma once
/// @file quadrotor_mass_model.h
/// @brief The variable-mass quadrotor of docs/model.md eq. (55) as a ManifoldSystem:
/// x = [q_WI, p_WI, v_WI, m], u = [T^d, w_I], y = [q_WI, p_WI, v_WI],
/// q' = q ⊗ [0, w_I]/2, p' = v, v' = R_WI [0, 0, T/m] + g_W, m' = 0 (+ noise).
///
/// Error state dx = [dtheta (right perturbation, q = q_hat ⊗ exp(dtheta/2)), dp, dv, dm].
/// The discrete map holds u constant over [t_k, t_k + dt] and is exact for that input
/// (see dynamics/massid/README.md "Methods"): with phi = w dt, a = T/m,
///   R_{k+1} = R_k Exp(phi),  v_{k+1} = v_k + (a R_k J_l(phi) e3 + g_W) dt,
///   p_{k+1} = p_k + v_k dt + (a R_k G2(phi) e3 + g_W / 2) dt^2,
/// with J_l(phi) = sum phi^n / (n+1)! (left Jacobian) and G2(phi) = sum phi^n / (n+2)!.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>

#include "massid/filters/system_model.h"
#include "massid/run_data.h"

namespace vid::massid {

/// @brief Columns of the error state.
namespace qm_idx {
constexpr int kTheta = 0;
constexpr int kP = 3;
constexpr int kV = 6;
constexpr int kM = 9;
}  // namespace qm_idx

/// @brief State of eq. (55).
struct QuadMassState {
  Eigen::Quaterniond q_WI = Eigen::Quaterniond::Identity();
  Eigen::Vector3d p_WI = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_WI = Eigen::Vector3d::Zero();
  double mass_kg = 1.0;
};

/// @brief Input of eq. (55): commanded collective thrust along z_I and body rate.
struct QuadMassInput {
  double thrust_N = 0.0;
  Eigen::Vector3d w_I = Eigen::Vector3d::Zero();
};

/// @brief Measurement of eq. (55) (as a VIO gives it).
struct QuadMassMeas {
  Eigen::Quaterniond q_WI = Eigen::Quaterniond::Identity();
  Eigen::Vector3d p_WI = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_WI = Eigen::Vector3d::Zero();
};

/// @brief G2(phi) = sum_n phi^n / (n+2)! as a matrix (double integral of Exp(s phi)).
Eigen::Matrix3d so3_gamma2(const Eigen::Vector3d& phi);

/// @brief Eq. (55) with analytic on-manifold Jacobians.
///
/// The terms that depend only on the input (Exp(w dt), J_l(w dt) e3, G2(w dt) e3) are cached
/// for the last (w, dt): sigma-point filters propagate 2n+1 states with the same input. The
/// cache makes an instance unsafe to share between threads (each filter owns its copy).
class QuadrotorMassModel {
 public:
  static constexpr int kStateDim = 10;
  static constexpr int kMeasDim = 9;
  using State = QuadMassState;
  using Input = QuadMassInput;
  using Meas = QuadMassMeas;
  using StateVec = Eigen::Matrix<double, kStateDim, 1>;
  using MeasVec = Eigen::Matrix<double, kMeasDim, 1>;
  using StateMat = Eigen::Matrix<double, kStateDim, kStateDim>;
  using MeasJac = Eigen::Matrix<double, kMeasDim, kStateDim>;

  explicit QuadrotorMassModel(double gravity = kDefaultGravity) : gravity_(gravity) {}
  double gravity() const { return gravity_; }
  Eigen::Vector3d g_W() const { return Eigen::Vector3d(0.0, 0.0, -gravity_); }

  /// @brief Discrete f of eq. (49) (exact for u held over dt).
  State propagate(const State& x, const Input& u, double dt) const;
  /// @brief F = d f(x ⊞ dx) ⊟ f(x) / d dx.
  StateMat state_jacobian(const State& x, const Input& u, double dt) const;
  /// @brief Continuous dynamics in the tangent: [w_I, v, R a e3 + g, 0] (for documentation/tests).
  StateVec continuous_rate(const State& x, const Input& u) const;
  /// @brief h of eq. (49).
  Meas measure(const State& x) const;
  /// @brief H = [I_9 0] (the measurement is the state's pose and velocity).
  MeasJac measurement_jacobian(const State& x) const;

  static State boxplus(const State& x, const StateVec& dx);
  /// @brief *plus = x ⊞ dx and *minus = x ⊞ -dx with one quaternion exponential
  /// (exp(-a/2) is the conjugate of exp(a/2)); used for the UKF's symmetric sigma points.
  static void boxplus_pm(const State& x, const StateVec& dx, State* plus, State* minus);
  static StateVec boxminus(const State& x1, const State& x0);
  static MeasVec meas_boxminus(const Meas& y1, const Meas& y0);

  /// @brief Measurement and input of a study sample.
  static Meas meas_of(const MassIdSample& s);
  static Input input_of(const MassIdSample& s);

 private:
  /// @brief Input-only terms of the discrete map.
  struct InputTerms {
    Eigen::Vector3d w_dt = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    Eigen::Quaterniond dq = Eigen::Quaterniond::Identity();  ///< exp(w dt / 2)
    Eigen::Matrix3d exp_T = Eigen::Matrix3d::Identity();     ///< Exp(w dt)^T
    Eigen::Vector3d jl_e3 = Eigen::Vector3d::Zero();         ///< J_l(w dt) e3
    Eigen::Vector3d g2_e3 = Eigen::Vector3d::Zero();         ///< G2(w dt) e3
  };
  const InputTerms& terms(const Input& u, double dt) const;

  double gravity_;
  mutable InputTerms cache_;
};

static_assert(ManifoldSystem<QuadrotorMassModel>);

}  // namespace vid::massid
