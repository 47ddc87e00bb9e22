#pragma once
// The IMU block's error-state retraction, written out here (not the filter's own) so that
// numeric Jacobians in the tests are an independent reference (docs/design.md §2: dtheta on
// the right of R_WI, the rest additive).
#include <Eigen/Core>

#include "geometry/so3.h"
#include "vio_core/state.h"

namespace vid::test {

/// @brief x boxplus dx over the IMU block of layout l.
inline ImuState perturb(const ImuState& x, const Eigen::VectorXd& dx, const ImuLayout& l) {
  ImuState y = x;
  y.T_WI.q = so3::boxplus(x.T_WI.q, dx.segment<3>(imu_idx::kTheta));
  y.T_WI.p += dx.segment<3>(imu_idx::kP);
  y.v_WI += dx.segment<3>(imu_idx::kV);
  y.b_g += dx.segment<3>(imu_idx::kBg);
  y.b_a += dx.segment<3>(imu_idx::kBa);
  if (l.force) y.F_ext += dx.segment<3>(imu_idx::kF);
  if (l.force_rate) y.F_dot += dx.segment<3>(imu_idx::kFdot);
  if (l.thrust_scale) y.thrust_scale += dx(l.thrust_scale_index());
  return y;
}

}  // namespace vid::test
