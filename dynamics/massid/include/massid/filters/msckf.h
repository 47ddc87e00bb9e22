#pragma once
/// @file msckf.h
/// @brief MSCKF-style mass filter (docs/model.md eqs. (27), (51), (17)): the current state [q, p, v, m] is
/// propagated like the EKF, and at every sample a stochastic clone of [q, p, v] is appended
/// (eq. (27): P_aug = J P J^T). When the window holds W clones, all W measurements
/// y_j = [q, p, v]_j are stacked (eq. (51): H = [0 | I_9W]) and applied in one update
/// (eq. (17)); the clones are then marginalized and a new window starts.
///
/// Because every clone is dropped right after the update, only the current-state rows of the
/// gain are formed: vio_core's kalman_correct with P_xy = P_xc and S = P_cc + R (exactly the
/// current-state block of the full update); cloning and propagation are vio_core's covariance
/// bookkeeping (vio_core/covariance.h) on a P allocated once for the whole window.

#include <Eigen/Core>
#include <vector>

#include "massid/filters/quadrotor_mass_model.h"

namespace vid::massid {

/// @brief Window filter over QuadrotorMassModel with clones of [q, p, v].
class WindowMsckf {
 public:
  using Model = QuadrotorMassModel;
  static constexpr int kCloneDim = 9;

  WindowMsckf(Model model, int window);

  void init(const QuadMassState& x0, const Model::StateMat& P0);
  /// @brief Propagate the current state and its cross-covariance with the clones.
  void predict(const QuadMassInput& u, double dt, const Model::StateMat& Q);
  /// @brief Clone the current [q, p, v] with its measurement; when the window is full, run the
  /// stacked update. @return true when an update was applied.
  bool update(const QuadMassMeas& y, const Eigen::Matrix<double, 9, 9>& R);

  /// @brief Add extra process noise to the current state (e.g. a detected abrupt change).
  void add_covariance(const Model::StateMat& dQ) { P_.topLeftCorner<10, 10>() += dQ; }

  const QuadMassState& state() const { return x_; }
  Model::StateMat covariance() const { return P_.topLeftCorner<10, 10>(); }
  int clone_count() const { return static_cast<int>(clones_.size()); }
  int window() const { return window_; }

 private:
  bool stacked_update(const Eigen::Matrix<double, 9, 9>& R);

  Model model_;
  int window_;
  QuadMassState x_;
  std::vector<QuadMassMeas> clones_;  ///< cloned [q, p, v] means
  std::vector<QuadMassMeas> meas_;    ///< their measurements
  Eigen::MatrixXd P_;                 ///< (10 + 9 W)^2, used part (10 + 9 c)^2
};

}  // namespace vid::massid
