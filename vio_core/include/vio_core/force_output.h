#pragma once
/// @file force_output.h
/// @brief The external force an estimate reports, in I and in W with covariances: the force
/// state mapped to the other frame, plus the model's body drag when the state has one, so the
/// output keeps one meaning (everything but thrust and gravity, docs/formats.md §2 force.csv).

#include <Eigen/Core>

#include "vio_core/state.h"

namespace vid {

/// @brief Reported external force [m/s^2] and covariances.
struct ForceEstimate {
  Eigen::Vector3d F_I = Eigen::Vector3d::Zero();  ///< everything but thrust and gravity, in I
  Eigen::Vector3d F_W = Eigen::Vector3d::Zero();  ///< the same in W
  Eigen::Matrix3d cov_F_I = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d cov_F_W = Eigen::Matrix3d::Zero();
  Eigen::Vector3d F_drag_I = Eigen::Vector3d::Zero();  ///< of F_I, the model's body drag (0 without)
};

/// @brief The force of @p state (needs the force state). The block in the state's force frame is
/// the state's own covariance; the other frame takes the orientation error along
/// (R = R_hat Exp(dtheta)); with drag, the velocity and orientation errors of -D R^T v too.
ForceEstimate force_output(const FilterState& state);

}  // namespace vid
