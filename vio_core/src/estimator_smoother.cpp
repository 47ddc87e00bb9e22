/// @file estimator_smoother.cpp
/// @brief The estimator's fixed-lag smoothing: force clones taken at camera frames, released
/// after smoother_lag_s as anchors of the smoothed outputs (docs/notes/smoothing.md; the
/// bookkeeping is FilterState's, the outputs fixed_lag.h's).
#include <optional>

#include "vio_core/estimator.h"
#include "vio_core/fixed_lag.h"

namespace vid {

bool Estimator::smoother_frame_start() {
  if (!lagged_) return false;
  // Frame times jitter: a clone is due from 1 ms before the period is up.
  constexpr TimeNs kToleranceNs = 1'000'000;
  const auto& fc = state_.force_clones();
  if (!fc.empty() && state_.time() - fc.back().t_ns < seconds_to_ns(config_.params.smoother_clone_period_s) - kToleranceNs)
    return false;
  state_.augment_force_clone();
  return true;
}

void Estimator::smoother_frame_end(bool cloned, bool all) {
  if (!lagged_) return;
  const auto pose_clone_at = [this](TimeNs t) -> std::optional<Pose> {
    for (const CloneState& c : state_.clones())
      if (c.t_ns == t) return c.T_WI;
    return std::nullopt;
  };
  const auto F_block = [this](const ForceClone& c) -> Eigen::Matrix3d {
    return state_.P().block<3, 3>(c.cov_index, c.cov_index);
  };
  if (cloned && !state_.force_clones().empty()) {
    const ForceClone& c = state_.force_clones().back();
    if (const std::optional<Pose> pose = pose_clone_at(c.t_ns)) lagged_->clone_taken(c.t_ns, c.F_ext, F_block(c), *pose);
  }
  constexpr TimeNs kToleranceNs = 1'000'000;
  const TimeNs lag_ns = seconds_to_ns(config_.params.smoother_lag_s);
  while (!state_.force_clones().empty() &&
         (all || state_.time() - state_.force_clones().front().t_ns >= lag_ns - kToleranceNs)) {
    const ForceClone& c = state_.force_clones().front();
    lagged_->clone_released(c.t_ns, c.F_ext, F_block(c), pose_clone_at(c.t_ns));
    state_.marginalize_oldest_force_clone();
  }
  lagged_->release(on_smoothed_, all);
}

}  // namespace vid
