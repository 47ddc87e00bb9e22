/// @file estimator_accel.cpp
/// @brief The estimator's accelerometer step (dynamics mode): the gated update, the
/// vibration-aware noise, force jumps, rejected / down-weighted spans, the flight phase.
#include <algorithm>

#include "vio_core/chi2.h"
#include "vio_core/ekf_update.h"
#include "vio_core/estimator.h"
#include "vio_core/force_output.h"

namespace vid {

namespace {
// Samples less than 50 ms apart share a span; a span never runs backwards (first <= last) even
// if a caller reports an older sample after a newer one.
void add_to_spans(std::vector<TimeSpan>& spans, TimeNs t) {
  constexpr TimeNs kJoinNs = 50'000'000;
  if (!spans.empty() && t - spans.back().last_ns <= kJoinNs && spans.back().first_ns - t <= kJoinNs) {
    spans.back().first_ns = std::min(spans.back().first_ns, t);
    spans.back().last_ns = std::max(spans.back().last_ns, t);
  } else {
    spans.push_back(TimeSpan{t, t});
  }
}
}  // namespace

void Estimator::record_rejected(TimeNs t) {
  ++counters_.accel_rejected;
  add_to_spans(counters_.accel_rejected_spans, t);
}

void Estimator::record_downweighted(TimeNs t) {
  ++counters_.accel_downweighted;
  add_to_spans(counters_.accel_downweighted_spans, t);
}

void Estimator::record_past_gate(TimeNs t) {
  if (config_.params.accel_gate_downweight) {
    record_downweighted(t);
  } else {
    record_rejected(t);
  }
}

void Estimator::add_noise_fit(const AccelInnovation& info) {
  // info holds the innovation in the force frame; the fit is per IMU axis.
  const bool world = state_.force_frame() == ForceFrame::kWorld;
  const Eigen::Vector3d r_I = world ? Eigen::Vector3d(info.R_WI.transpose() * info.w) : info.w;
  const Eigen::Matrix3d S_I = world ? Eigen::Matrix3d(info.R_WI.transpose() * info.S * info.R_WI) : info.S;
  if (!(S_I.diagonal().minCoeff() > 0.0)) return;
  const bool was_inflated = accel_noise_.noise_var() != Eigen::Vector3d::Constant(nominal_accel_var());
  accel_noise_.add(r_I, S_I.diagonal());
  if (was_inflated) ++counters_.accel_noise_inflated;
  // Against the nominal noise (imu0/sensor.yaml): the fit tells whether that setting is right,
  // whatever the adaptation made of it.
  counters_.accel_nis_sum += r_I.cwiseAbs2().cwiseQuotient(accel_noise_.nominal_innovation_var());
  ++counters_.accel_nis_count;
}

double Estimator::nominal_accel_var() const {
  const EstimatorParams& p = config_.params;
  return p.accel_noise_density * p.accel_noise_density * p.imu_rate_hz;
}

void Estimator::accel_step(const ImuInput& in) {
  const EstimatorParams& p = config_.params;
  const Eigen::Vector3d noise_var = accel_noise_.noise_var();
  const double thr = p.accel_chi2_gating ? p.accel_chi2_multiplier * chi2_quantile(0.99, 3) : 0.0;
  const bool down = p.accel_gate_downweight;
  AccelInnovation info;
  if (!p.force_jump_detection) {
    const UpdateResult u = accel_update(state_, in.accel, in.T_m, noise_var, thr, &info, down);
    add_noise_fit(info);
    if (u.applied && !u.downweighted) {
      ++counters_.accel_updates;
    } else {
      record_past_gate(in.t);
    }
    return;
  }
  const UpdateResult u = accel_update(state_, in.accel, in.T_m, noise_var, thr, &info, down);
  add_noise_fit(info);
  if (u.applied && !u.downweighted) ++counters_.accel_updates;
  // The noise the adapter added for vibration, in the force frame: coloured (force_jump.h).
  const Eigen::Vector3d vib = accel_noise_.excess_var();
  if (!vib.isZero(0.0)) {
    const bool world = state_.force_frame() == ForceFrame::kWorld;
    info.S_vib = world ? Eigen::Matrix3d(info.R_WI * vib.asDiagonal() * info.R_WI.transpose())
                       : Eigen::Matrix3d(vib.asDiagonal());
  }
  // A sample past the gate (rejected or down-weighted) stays in the detector's window: if a
  // jump uses it, its correction is undone and it counts at full weight in the jump's estimate;
  // otherwise it counts as rejected / down-weighted once it leaves the window.
  if (auto old = jumps_.push(info); old && old->gated) record_past_gate(old->t_ns);
  const std::optional<ForceJump> jump = jumps_.test();
  if (!jump) return;
  std::vector<AccelInnovation> window;
  for (int i = 0; i < jump->n; ++i) {
    window.push_back(jumps_.recent(i));
    if (window.back().gated) ++counters_.accel_used_in_jumps;
  }
  // Older than the jump's window: oldest first (recent(0) is the newest), so spans grow forward.
  for (int i = jumps_.size() - 1; i >= jump->n; --i)
    if (jumps_.recent(i).gated) record_past_gate(jumps_.recent(i).t_ns);
  jumps_.clear();
  apply_force_jump(state_, window, *jump, noise_var.maxCoeff(), p.init_sigma_force_rate);
  ++counters_.force_jumps;
  if (counters_.force_jump_events.size() < 10000)
    counters_.force_jump_events.push_back(ForceJumpRecord{jump->t_ns, jump->n, jump->delta.norm()});
}

void Estimator::update_flight_phase(TimeNs t) {
  const FlightPhase before = phase_.phase();
  const FlightPhase now = phase_.update(t, force_in_world(state_.imu(), state_.force_frame()));
  if (before != FlightPhase::kUnknown) {
    const double dt = ns_to_s(t - phase_time_);
    (before == FlightPhase::kLanded ? counters_.landed_s : counters_.airborne_s) += dt;
  }
  phase_time_ = t;
  if (before != FlightPhase::kUnknown && now != before && counters_.flight_phase_events.size() < 10000)
    counters_.flight_phase_events.push_back(FlightPhaseRecord{t, now});
}

}  // namespace vid
