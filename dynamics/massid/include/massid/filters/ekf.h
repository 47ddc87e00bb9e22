#pragma once
/// @file ekf.h
/// @brief On-manifold EKF over any ManifoldSystem (docs/model.md eq. (50)): predict
/// x^- = f(x, u), P^- = F P F^T + Q; update r = y ⊟ h(x^-), K = P H^T S^-1,
/// x = x^- ⊞ K r, P = (I - K H) P^-, the correction being vio_core's one
/// kalman_correct (vio_core/kalman.h).

#include <Eigen/Core>

#include "massid/filters/system_model.h"
#include "vio_core/kalman.h"

namespace vid::massid {

/// @brief Extended Kalman filter with error state in the model's tangent space.
template <ManifoldSystem Model>
class ManifoldEkf {
 public:
  static constexpr int N = Model::kStateDim;
  static constexpr int M = Model::kMeasDim;
  using State = typename Model::State;
  using StateCov = Eigen::Matrix<double, N, N>;
  using MeasCov = Eigen::Matrix<double, M, M>;

  explicit ManifoldEkf(Model model = Model()) : model_(std::move(model)) {}

  /// @brief Start from mean x0 and covariance P0 (tangent at x0).
  void init(const State& x0, const StateCov& P0) {
    x_ = x0;
    P_ = P0;
  }
  /// @brief Prediction of eq. (50) with additive discrete process noise Q (eq. (49)'s n_x).
  void predict(const typename Model::Input& u, double dt, const StateCov& Q) {
    const StateCov F = model_.state_jacobian(x_, u, dt);
    x_ = model_.propagate(x_, u, dt);
    P_ = F * P_ * F.transpose() + Q;
  }
  /// @brief Update of eq. (50) with measurement noise R (eq. (49)'s n_y). @return false if S is singular.
  bool update(const typename Model::Meas& y, const MeasCov& R) {
    const Eigen::Matrix<double, M, N> H = model_.measurement_jacobian(x_);
    const Eigen::Matrix<double, M, 1> r = Model::meas_boxminus(y, model_.measure(x_));
    const Eigen::Matrix<double, N, M> PHt = P_ * H.transpose();
    MeasCov S = H * PHt + R;
    S = 0.5 * (S + S.transpose()).eval();
    Eigen::Matrix<double, N, 1> dx;
    if (!kalman_correct(P_, PHt, S, r, &dx)) return false;
    x_ = Model::boxplus(x_, dx);
    return true;
  }

  /// @brief Add extra process noise now (e.g. a detected abrupt change).
  void add_covariance(const StateCov& dQ) { P_ += dQ; }

  const State& state() const { return x_; }
  const StateCov& covariance() const { return P_; }
  const Model& model() const { return model_; }

 private:
  Model model_;
  State x_{};
  StateCov P_ = StateCov::Identity();
};

}  // namespace vid::massid
