/// @file estimator_output.cpp
/// @brief The estimator's outputs: the IMU-rate estimate (state, covariances, the force in both
/// frames, time offset, status) handed to the callback and the smoother (estimator_outputs.h).
#include <algorithm>
#include <cmath>

#include "vio_core/estimator.h"
#include "vio_core/fixed_lag.h"  // complete type for lagged_
#include "vio_core/force_output.h"

namespace vid {

std::string to_string(FilterStatus s) {
  switch (s) {
    case FilterStatus::kWaitingForInit: return "waiting_for_init";
    case FilterStatus::kOk: return "ok";
    case FilterStatus::kDiverged: return "diverged";
  }
  return "unknown";
}

void Estimator::emit(TimeNs t) {
  if (!on_estimate_ && !lagged_) return;
  EstimateOutput o;
  o.t_ns = t;
  o.x = state_.imu();
  o.phase = phase_.phase();
  const int d = state_.imu_dim();
  o.sigma = state_.P().topLeftCorner(d, d).diagonal().cwiseSqrt();
  o.cov_theta = state_.P().block<3, 3>(imu_idx::kTheta, imu_idx::kTheta);
  o.cov_p = state_.P().block<3, 3>(imu_idx::kP, imu_idx::kP);
  o.F_ext_I.setZero();
  o.F_ext_W.setZero();
  o.cov_F_I.setZero();
  o.cov_F_W.setZero();
  if (state_.with_force()) {
    const ForceEstimate f = force_output(state_);
    o.F_ext_I = f.F_I;
    o.F_ext_W = f.F_W;
    o.cov_F_I = f.cov_F_I;
    o.cov_F_W = f.cov_F_W;
  }
  if (state_.with_thrust_scale()) {
    const int is = state_.layout().thrust_scale_index();
    o.sigma_thrust_scale = std::sqrt(std::max(0.0, state_.P()(is, is)));
  }
  o.time_offset_s = time_offset_s();
  o.sigma_time_offset_s = state_.time_offset_sigma();
  o.status = status_;
  if (lagged_) lagged_->add_causal(o);
  if (on_estimate_) on_estimate_(o);
}

}  // namespace vid
