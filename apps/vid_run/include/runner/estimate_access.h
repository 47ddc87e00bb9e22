#pragma once
/// @file estimate_access.h
/// @brief The external force of an EstimateOutput in the body and world frames and its body
/// 1-sigma. Transitional: works both with estimates that carry the force in both frames
/// (F_ext_I, F_ext_W, cov_F_I: force state in a configurable frame) and with the older ones
/// that carry only the body-frame state x.F_ext_I.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vid::runner {

/// @brief Mass-normalized external force in I [m/s^2].
template <class Estimate>
Eigen::Vector3d force_body(const Estimate& e) {
  if constexpr (requires { e.F_ext_I; }) {
    return e.F_ext_I;
  } else {
    return e.x.F_ext_I;
  }
}

/// @brief Mass-normalized external force in W [m/s^2].
template <class Estimate>
Eigen::Vector3d force_world(const Estimate& e) {
  if constexpr (requires { e.F_ext_W; }) {
    return e.F_ext_W;
  } else {
    return e.x.q_WI.normalized() * e.x.F_ext_I;
  }
}

/// @brief 1-sigma of the force in I [m/s^2] (zero in imu mode).
template <class Estimate>
Eigen::Vector3d force_sigma_body(const Estimate& e) {
  if constexpr (requires { e.cov_F_I; }) {
    return e.cov_F_I.diagonal().cwiseMax(0.0).cwiseSqrt();
  } else {
    return e.sigma.size() >= 18 ? Eigen::Vector3d(e.sigma.template segment<3>(15)) : Eigen::Vector3d::Zero();
  }
}

}  // namespace vid::runner
