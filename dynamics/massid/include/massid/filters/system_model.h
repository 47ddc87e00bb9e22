#pragma once
/// @file system_model.h
/// @brief The generic system of docs/model.md eq. (49) on a manifold, as a C++20 concept:
/// x_{k+1} = f(x_k, u_k, p) ⊞ n_x,  y_k = h(x_k) ⊞ n_y, with error states dx (tangent) and
/// residuals y ⊟ h(x). Every model-based method (EKF, UKF, MSCKF) is written against it.

#include <Eigen/Core>
#include <concepts>

namespace vid::massid {

/// @brief Requirements on a discrete-time system model (docs/model.md eq. (49)).
///
/// * State, Input, Meas: value types; kStateDim / kMeasDim: tangent dimensions.
/// * propagate(x, u, dt): the discrete map f (eq. (49) without noise).
/// * state_jacobian(x, u, dt): F = d(f(x ⊞ dx) ⊟ f(x)) / d dx at dx = 0.
/// * measure(x): h (eq. (49) without noise); measurement_jacobian(x): H = d(h(x ⊞ dx) ⊟ h(x)) / d dx.
/// * boxplus / boxminus on states, meas_boxminus on measurements (y1 ⊟ y0).
template <class M>
concept ManifoldSystem = requires(const M& model, const typename M::State& x,
                                  const typename M::Input& u, const typename M::Meas& y,
                                  double dt,
                                  const Eigen::Matrix<double, M::kStateDim, 1>& dx) {
  { model.propagate(x, u, dt) } -> std::same_as<typename M::State>;
  { model.state_jacobian(x, u, dt) } -> std::same_as<Eigen::Matrix<double, M::kStateDim, M::kStateDim>>;
  { model.measure(x) } -> std::same_as<typename M::Meas>;
  { model.measurement_jacobian(x) } -> std::same_as<Eigen::Matrix<double, M::kMeasDim, M::kStateDim>>;
  { M::boxplus(x, dx) } -> std::same_as<typename M::State>;
  { M::boxminus(x, x) } -> std::same_as<Eigen::Matrix<double, M::kStateDim, 1>>;
  { M::meas_boxminus(y, y) } -> std::same_as<Eigen::Matrix<double, M::kMeasDim, 1>>;
};

}  // namespace vid::massid
