#pragma once
/// @file rk4.h
/// @brief The project's one ODE integrator: a classical Runge-Kutta (RK4) step over any state
/// type. The simulator's vehicle (QuadrotorModel::rk4_step) and the mass-identification study's
/// run generator both step with it.

namespace vid::dynamics {

/// @brief One classical RK4 step of x' = f(t, x) from (t, x) over h:
///   k1 = f(t, x),              k2 = f(t + h/2, x + h/2 k1),
///   k3 = f(t + h/2, x + h/2 k2), k4 = f(t + h, x + h k3),
///   x(t + h) = x + h/6 (k1 + 2 k2 + 2 k3 + k4).
///
/// The state lives on whatever type suits the model (a struct of Eigen vectors, a quaternion
/// kept as four plain coefficients, ...): the caller says how a derivative moves it.
/// @tparam Deriv  derivative type, given explicitly (an Eigen f may return an expression):
///                a vector space (Deriv + Deriv, double * Deriv)
/// @param f           (double t, const State& x) -> Deriv
/// @param add_scaled  (const State& x, const Deriv& d, double s) -> State, the state x + s d
/// @return the state at t + h (not renormalized: projecting it, e.g. a quaternion back onto
///         the unit sphere, is the caller's)
template <class Deriv, class State, class F, class AddScaled>
State rk4_step(double t, double h, const State& x, F&& f, AddScaled&& add_scaled) {
  // The sums keep the textbook order ((k1 + 2 k2) + 2 k3) + k4: outputs recorded with the
  // hand-written steps this replaced stay bit-identical.
  const Deriv k1 = f(t, x);
  const Deriv k2 = f(t + 0.5 * h, add_scaled(x, k1, 0.5 * h));
  const Deriv k3 = f(t + 0.5 * h, add_scaled(x, k2, 0.5 * h));
  const Deriv k4 = f(t + h, add_scaled(x, k3, h));
  const Deriv sum = k1 + 2.0 * k2 + 2.0 * k3 + k4;
  return add_scaled(x, sum, h / 6.0);
}

}  // namespace vid::dynamics
