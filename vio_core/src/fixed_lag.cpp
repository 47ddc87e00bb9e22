/// @file fixed_lag.cpp
/// @brief Anchors from released force clones and the smoothed IMU-rate outputs between them.
#include "vio_core/fixed_lag.h"

#include <algorithm>

#include "geometry/so3.h"

namespace vid {

void FixedLagOutput::clone_taken(TimeNs t_ns, const Eigen::Vector3d& F_ext_fc, const Eigen::Matrix3d& P_F,
                                 const Pose& T_WI) {
  pending_.push_back(Pending{t_ns, F_ext_fc, P_F, T_WI, std::nullopt});
}

void FixedLagOutput::pose_leaving(TimeNs t_ns, const Pose& T_WI) {
  for (Pending& p : pending_)
    if (p.t_ns == t_ns) p.T_WI_last = T_WI;
}

void FixedLagOutput::clone_released(TimeNs t_ns, const Eigen::Vector3d& F_ext_fc, const Eigen::Matrix3d& P_F,
                                    const std::optional<Pose>& T_WI) {
  // Clones leave oldest first; a clone taken without clone_taken (none in the estimator) is skipped.
  while (!pending_.empty() && pending_.front().t_ns < t_ns) pending_.pop_front();
  if (pending_.empty() || pending_.front().t_ns != t_ns) return;
  const Pending& c = pending_.front();
  LagAnchor a;
  a.t_ns = t_ns;
  a.dF = F_ext_fc - c.F_ext_fc;
  a.dP_F = c.P_F - P_F;
  const std::optional<Pose> pose = T_WI ? T_WI : c.T_WI_last;
  if (pose) {
    a.dtheta = so3::boxminus(pose->q, c.T_WI.q);
    a.dp_WI = pose->p - c.T_WI.p;
  }
  anchors_.push_back(a);
  pending_.pop_front();
}

LagAnchor interpolate_anchor(const LagAnchor& a, const LagAnchor& b, TimeNs t) {
  if (t >= b.t_ns) return b;
  if (t <= a.t_ns) return a;
  const double w = static_cast<double>(t - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  LagAnchor r;
  r.t_ns = t;
  r.dF = (1.0 - w) * a.dF + w * b.dF;
  r.dP_F = (1.0 - w) * a.dP_F + w * b.dP_F;
  r.dtheta = (1.0 - w) * a.dtheta + w * b.dtheta;
  r.dp_WI = (1.0 - w) * a.dp_WI + w * b.dp_WI;
  return r;
}

EstimateOutput apply_lag_anchor(const EstimateOutput& e, const LagAnchor& a, ForceFrame frame) {
  EstimateOutput s = e;
  s.x.T_WI.q = so3::boxplus(e.x.T_WI.q, a.dtheta);
  s.x.T_WI.p = e.x.T_WI.p + a.dp_WI;
  s.x.F_ext = e.x.F_ext + a.dF;
  if (e.F_ext_I.isZero() && e.F_ext_W.isZero() && e.cov_F_I.isZero()) return s;  // imu mode: no force
  // The reported force is the state's plus the model's body drag (force_output.h); the smoother
  // corrects the state's part, the drag of the causal estimate is kept.
  const Eigen::Vector3d drag_I = e.F_ext_I - force_in_body(e.x, frame);
  s.F_ext_I = force_in_body(s.x, frame);
  s.F_ext_W = force_in_world(s.x, frame);
  if (!drag_I.isZero(0.0)) {
    s.F_ext_I += drag_I;
    s.F_ext_W = s.x.T_WI.q * s.F_ext_I;
  }
  // The covariance reduction is the clone's, in the force frame (docs/model.md eq. (40)); the other frame's
  // reduction is mapped through the smoothed R_WI.
  const Eigen::Matrix3d R = s.x.T_WI.q.toRotationMatrix();
  if (frame == ForceFrame::kWorld) {
    s.cov_F_W = e.cov_F_W - a.dP_F;
    s.cov_F_I = e.cov_F_I - R.transpose() * a.dP_F * R;
  } else {
    s.cov_F_I = e.cov_F_I - a.dP_F;
    s.cov_F_W = e.cov_F_W - R * a.dP_F * R.transpose();
  }
  return s;
}

EstimateOutput FixedLagOutput::smoothed(const EstimateOutput& e) const {
  // anchors_[0] <= e.t_ns < anchors_[1] when two are known; one anchor is held.
  const LagAnchor a = anchors_.size() >= 2 ? interpolate_anchor(anchors_[0], anchors_[1], e.t_ns) : anchors_.front();
  return apply_lag_anchor(e, a, frame_);
}

void FixedLagOutput::release(const std::function<void(const EstimateOutput&)>& out, bool all) {
  if (anchors_.empty()) {
    if (all) {
      // No clone ever left (a run shorter than one period): the causal estimates as they are.
      for (const EstimateOutput& e : causal_)
        if (out) out(e);
      causal_.clear();
    }
    return;
  }
  while (!causal_.empty()) {
    const TimeNs t = causal_.front().t_ns;
    while (anchors_.size() >= 2 && anchors_[1].t_ns <= t) anchors_.pop_front();
    // Past the newest anchor the next one is still to come (unless the stream ended).
    if (!all && t > anchors_.back().t_ns) break;
    if (out) out(smoothed(causal_.front()));
    causal_.pop_front();
  }
}

}  // namespace vid
