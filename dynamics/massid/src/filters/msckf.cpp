/// @file msckf.cpp
/// @brief Window MSCKF of the mass study (docs/model.md eqs. (27), (51), (17)).
#include "massid/filters/msckf.h"

#include <stdexcept>

#include "vio_core/covariance.h"
#include "vio_core/kalman.h"

namespace vid::massid {

WindowMsckf::WindowMsckf(Model model, int window) : model_(model), window_(window) {
  if (window < 1) throw std::invalid_argument("WindowMsckf: window must be >= 1");
  P_ = Eigen::MatrixXd::Zero(10 + kCloneDim * window, 10 + kCloneDim * window);
  clones_.reserve(window);
  meas_.reserve(window);
}

void WindowMsckf::init(const QuadMassState& x0, const Model::StateMat& P0) {
  x_ = x0;
  P_.setZero();
  P_.topLeftCorner<10, 10>() = P0;
  clones_.clear();
  meas_.clear();
}

void WindowMsckf::predict(const QuadMassInput& u, double dt, const Model::StateMat& Q) {
  const Model::StateMat F = model_.state_jacobian(x_, u, dt);
  x_ = model_.propagate(x_, u, dt);
  // Clones are static: only the current-state rows (and mirrored columns) change.
  covariance::propagate_leading(P_, 10 + kCloneDim * clone_count(), F, Q);
}

bool WindowMsckf::update(const QuadMassMeas& y, const Eigen::Matrix<double, 9, 9>& R) {
  // Augment (eqs. 9-10): the clone is [theta, p, v] of the current state, J = [I_9 0].
  covariance::clone_into(P_, 10 + kCloneDim * clone_count(), 0, kCloneDim);
  clones_.push_back(model_.measure(x_));
  meas_.push_back(y);
  if (clone_count() < window_) return false;
  const bool ok = stacked_update(R);
  clones_.clear();
  meas_.clear();
  return ok;
}

bool WindowMsckf::stacked_update(const Eigen::Matrix<double, 9, 9>& R) {
  const int c = clone_count();
  const int nc = kCloneDim * c;
  // Eqs. 11-14 with H = [0 | I]: S = P_cc + blockdiag(R), P_xy = P_xc; the clones are dropped
  // after the update, so only the current state's block is corrected.
  Eigen::MatrixXd S = P_.block(10, 10, nc, nc);
  Eigen::VectorXd r(nc);
  for (int j = 0; j < c; ++j) {
    S.block<9, 9>(9 * j, 9 * j) += R;
    r.segment<9>(9 * j) = Model::meas_boxminus(meas_[j], clones_[j]);
  }
  Model::StateMat P_xx = P_.topLeftCorner<10, 10>();
  Model::StateVec dx;
  if (!kalman_correct(P_xx, P_.block(0, 10, 10, nc), S, r, &dx)) return false;
  P_.topLeftCorner<10, 10>() = P_xx;
  x_ = Model::boxplus(x_, dx);
  return true;
}

}  // namespace vid::massid
