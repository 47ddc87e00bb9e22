#pragma once
/// @file ukf.h
/// @brief Unscented Kalman filter with sigma points on the manifold (docs/model.md eqs. (52)-(54)):
/// chi_0 = x, chi_{i, i+n} = x ⊞ (± sqrt((n + lambda) P))_i (eq. (52)); the predicted mean is
/// the weighted manifold mean of f(chi) (fixed-point iteration in the tangent of the current
/// mean; the covariance uses the deviations centred on the mean shift, exact in R^n), P^- = sum w_c (chi ⊟ x^-)(.)^T + Q (eq. (53)); the update redraws sigma points around
/// (x^-, P^-), forms Pyy = sum w_c dy dy^T + R and Pxy = sum w_c dx dy^T with dy taken in the
/// tangent of h(x^-), K = Pxy Pyy^-1 (eq. (54)).

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <utility>

#include "massid/filters/system_model.h"
#include "vio_core/kalman.h"

namespace vid::massid {

/// @brief Scaled unscented transform parameters: lambda = alpha^2 (n + kappa) - n.
struct UkfParams {
  double alpha = 1.0;
  double beta = 0.0;
  double kappa = 0.0;
  int mean_iterations = 1;  ///< manifold mean fixed-point iterations (1 is exact in R^n)
};

/// @brief UKF over any ManifoldSystem.
template <ManifoldSystem Model>
class ManifoldUkf {
 public:
  static constexpr int N = Model::kStateDim;
  static constexpr int M = Model::kMeasDim;
  static constexpr int S = 2 * N + 1;
  using State = typename Model::State;
  using StateVec = Eigen::Matrix<double, N, 1>;
  using StateCov = Eigen::Matrix<double, N, N>;
  using MeasVec = Eigen::Matrix<double, M, 1>;
  using MeasCov = Eigen::Matrix<double, M, M>;

  explicit ManifoldUkf(Model model = Model(), UkfParams params = {})
      : model_(std::move(model)), params_(params) {
    const double n = N;
    lambda_ = params.alpha * params.alpha * (n + params.kappa) - n;
    wm0_ = lambda_ / (n + lambda_);
    wc0_ = wm0_ + (1.0 - params.alpha * params.alpha + params.beta);
    wi_ = 0.5 / (n + lambda_);
    wm_.setConstant(wi_);
    wc_.setConstant(wi_);
    wm_(0) = wm0_;
    wc_(0) = wc0_;
  }

  void init(const State& x0, const StateCov& P0) {
    x_ = x0;
    P_ = P0;
  }

  /// @brief Eqs. 15-16. @return false if P is not positive definite (state unchanged).
  bool predict(const typename Model::Input& u, double dt, const StateCov& Q) {
    std::array<State, S> chi;
    if (!draw(&chi)) return false;
    for (State& c : chi) c = model_.propagate(c, u, dt);
    State mean = chi[0];
    Eigen::Matrix<double, N, S> D;  // deviations chi_i ⊟ mean, one per column
    StateVec d_mean = StateVec::Zero();
    for (int it = 0; it < std::max(1, params_.mean_iterations); ++it) {
      for (int i = 0; i < S; ++i) D.col(i) = Model::boxminus(chi[i], mean);
      d_mean = D.lazyProduct(wm_);
      mean = Model::boxplus(mean, d_mean);
    }
    // Deviations from the new mean, to first order (exact in R^n): chi_i ⊟ mean ≈ D_i - d_mean.
    D.colwise() -= d_mean;
    // Small fixed sizes: coefficient-based (lazy) products, unrolled at compile time, instead of
    // Eigen's blocked GEMM path (packing dominated the update time at 10 x 21 x 10).
    const Eigen::Matrix<double, N, S> DW = D * wc_.asDiagonal();
    StateCov P = Q;
    P.noalias() += DW.lazyProduct(D.transpose());
    x_ = mean;
    P_ = 0.5 * (P + P.transpose());
    return true;
  }

  /// @brief Eq. 17. @return false if P or Pyy is not positive definite.
  bool update(const typename Model::Meas& y, const MeasCov& R) {
    std::array<State, S> chi;
    if (!draw(&chi)) return false;
    const typename Model::Meas y_ref = model_.measure(x_);
    Eigen::Matrix<double, M, S> E;  // measurement deviations, one per column
    for (int i = 0; i < S; ++i) E.col(i) = Model::meas_boxminus(model_.measure(chi[i]), y_ref);
    const MeasVec dy_mean = E.lazyProduct(wm_);
    E.colwise() -= dy_mean;
    const Eigen::Matrix<double, M, S> EW = E * wc_.asDiagonal();
    MeasCov Pyy = R;
    Pyy.noalias() += EW.lazyProduct(E.transpose());
    // The drawn points' state deviations are 0, +L, -L, so sum_i dx_i (w_c dy_i)^T
    // = L (EW_+ - EW_-)^T: half the products of forming [0, L, -L] explicitly.
    Eigen::Matrix<double, M, N> EWd = EW.template middleCols<N>(1);
    EWd -= EW.template rightCols<N>();
    Eigen::Matrix<double, N, M> Pxy;
    Pxy.noalias() = L_.lazyProduct(EWd.transpose());
    const MeasVec r = Model::meas_boxminus(y, y_ref) - dy_mean;
    StateVec dx;
    if (!kalman_correct(P_, Pxy, Pyy, r, &dx)) return false;
    x_ = Model::boxplus(x_, dx);
    return true;
  }

  /// @brief Add extra process noise now (e.g. a detected abrupt change).
  void add_covariance(const StateCov& dQ) { P_ += dQ; }

  const State& state() const { return x_; }
  const StateCov& covariance() const { return P_; }

 private:
  bool draw(std::array<State, S>* chi) {
    Eigen::LLT<StateCov> llt((N + lambda_) * P_);
    if (llt.info() != Eigen::Success) return false;
    L_ = llt.matrixL();
    (*chi)[0] = x_;
    for (int i = 0; i < N; ++i) {
      const StateVec l = L_.col(i);
      if constexpr (requires(State* s) { Model::boxplus_pm(x_, l, s, s); }) {
        // x ⊞ l and x ⊞ -l together (the model shares the work, e.g. Exp(-a) = Exp(a)^T).
        Model::boxplus_pm(x_, l, &(*chi)[1 + i], &(*chi)[1 + N + i]);
      } else {
        (*chi)[1 + i] = Model::boxplus(x_, l);
        (*chi)[1 + N + i] = Model::boxplus(x_, StateVec(-l));
      }
    }
    return true;
  }

  Model model_;
  UkfParams params_;
  double lambda_ = 0.0, wm0_ = 0.0, wc0_ = 0.0, wi_ = 0.0;
  Eigen::Matrix<double, S, 1> wm_, wc_;  ///< mean / covariance weights
  State x_{};
  StateCov P_ = StateCov::Identity();
  StateCov L_ = StateCov::Zero();
};

}  // namespace vid::massid
