/// @file estimator_frame.cpp
/// @brief The estimator's camera frame: its place on the IMU clock (time offset, hold, the gyro
/// rate of its clone), the MSCKF update, zero-velocity, marginalization, health and divergence.
#include <algorithm>
#include <cmath>

#include "estimator_detail.h"
#include "geometry/so3.h"
#include "vio_core/chi2.h"
#include "vio_core/ekf_update.h"
#include "vio_core/estimator.h"
#include "vio_core/fixed_lag.h"  // complete type for lagged_
#include "vio_core/msckf/clone_poses.h"
#include "vio_core/msckf/feature_database.h"
#include "vio_core/rate_fit.h"
#include "vio_core/visual_updater.h"

namespace vid {
using namespace estimator_detail;

TimeNs Estimator::frame_hold_ns() const {
  // A frame stamped t_cam belongs at t_cam + t_d on the IMU clock: with t_d < 0 it arrives after
  // the IMU samples it precedes. Hold IMU samples until the stamps of the other streams are
  // -t_d ahead (plus 3 sigma while t_d is estimated), at most 0.2 s; while t_d is estimated, also
  // for the gyro fit after each frame (rate_for_clone).
  const double hold_s = -time_offset_s() + 3.0 * state_.time_offset_sigma();
  const TimeNs fit_ns = config_.params.init_sigma_time_offset > 0.0 ? kTdRateHalfWindowNs : 0;
  return static_cast<TimeNs>(std::llround(std::clamp(hold_s, 0.0, 0.2) * 1e9)) + fit_ns;
}

Eigen::Vector3d Estimator::rate_for_clone(TimeNs t, const Eigen::Vector3d& fallback) const {
  if (!state_.time_offset()) return fallback;
  std::vector<GyroSample> window(gyro_history_.begin(), gyro_history_.end());
  for (const ImuSample& s : imu_queue_) {  // held by frame_hold_ns: the samples after t
    if (s.t_ns - t > kTdRateHalfWindowNs) break;
    window.push_back({s.t_ns, s.gyro_I});
  }
  const std::optional<AdaptiveRate> fit = fit_rate_adaptive(window, t, kTdRateHalfWindowNs, kTdRateMinHalfWindowNs);
  return fit ? fit->rate_I : fallback;
}

double Estimator::time_offset_s() const {
  return state_.time_offset_or(config_.cameras.empty() ? 0.0 : config_.cameras.front().timeshift_cam_imu_s);
}

TimeNs Estimator::imu_clock(TimeNs t_cam) const {
  return t_cam + static_cast<TimeNs>(std::llround(time_offset_s() * 1e9));
}

void Estimator::process_frame(const FeatureFrame& f, TimeNs stamp, const Eigen::Vector3d& w_I) {
  ++counters_.frames;
  const EstimatorParams& p = config_.params;
  const auto t_frame = Clock::now();
  FrameTimings& tm = pending_timings_;
  tm.t_ns = stamp;

  // The clone's time-offset Jacobian [w_I; v]: the rate fitted to the gyro, and no velocity.
  // The position path carries next to no information on t_d here (the rotation path alone
  // predicts the filter's sigma, docs/notes/time-offset.md), while the filter's velocity, corrected at every frame,
  // put frame-to-frame noise into it that read as information (t_d NEES per run up to 180 with
  // it, 0.2-5 without). The pose is still taken at t_cam + t_d_hat; only the coupling is left out.
  state_.augment_clone({w_I, Eigen::Vector3d::Zero(), p.camera_time_jitter});
  const bool force_cloned = smoother_frame_start();
  FeatureFrame usable;
  usable.t_ns = f.t_ns;
  usable.observations.reserve(f.observations.size());
  for (const FeatureObservation& o : f.observations) {
    if (!o.has_norm) {
      ++counters_.observations_without_norm;
      continue;
    }
    if (o.cam_id < 0 || o.cam_id >= static_cast<int>(config_.cameras.size())) continue;
    if (!p.use_stereo && o.cam_id != 0) continue;
    usable.observations.push_back(o);
  }
  features_->add(usable);

  const std::vector<msckf::ClonePose> clones = msckf::clone_poses(state_);
  const bool window_full = static_cast<int>(clones.size()) > p.window_size;
  if (p.zero_velocity_max_parallax_px > 0.0 && !config_.cameras.empty()) {
    parallax_.add(usable);
    // Landed: standing on the ground (any camera count); otherwise only one camera needs it.
    const bool landed = phase_.phase() == FlightPhase::kLanded && p.landed_zero_velocity_sigma > 0.0;
    if (landed || !p.use_stereo)
      zero_velocity_if_still(clones.front(), clones.back(),
                             landed ? p.landed_zero_velocity_sigma : p.zero_velocity_sigma, landed);
  }
  std::vector<msckf::FeatureTrack> tracks = features_->select_for_update(clones, f.t_ns, window_full);
  if (p.max_features_per_update > 0 && static_cast<int>(tracks.size()) > p.max_features_per_update) {
    // keep the longest tracks (most constraints); ties by id for determinism
    std::stable_sort(tracks.begin(), tracks.end(), [](const auto& a, const auto& b) {
      if (a.obs.size() != b.obs.size()) return a.obs.size() > b.obs.size();
      return a.feature_id < b.feature_id;
    });
    tracks.resize(static_cast<std::size_t>(p.max_features_per_update));
  }
  if (p.visual_update && !tracks.empty() && !config_.cameras.empty()) {
    bool applied = false;
    const msckf::VisualLinearSystem sys = visual_->update(state_, tracks, clones, &applied);
    tm.features_used += sys.features_used;
    tm.features_rejected += sys.features_rejected_chi2 + sys.features_rejected_triangulation;
    tm.features_rejected_chi2 += sys.features_rejected_chi2;
    counters_.features_used += sys.features_used;
    counters_.features_rejected += sys.features_rejected_chi2 + sys.features_rejected_triangulation;
    counters_.features_rejected_chi2 += sys.features_rejected_chi2;
    counters_.visual_chi2_sum += sys.chi2_sum;
    counters_.visual_dof_sum += sys.dof_sum;
    counters_.features_too_short += sys.features_too_short;
    if (applied) ++counters_.visual_updates;
  }
  tm.msckf_update_ms = ms_since(t_frame);
  check_health(f.t_ns, tm.features_used, tm.features_rejected_chi2, tm.features_rejected - tm.features_rejected_chi2);

  const auto t_marg = Clock::now();
  if (window_full) {
    features_->remove_observations_at(state_.clones().front().t_ns);
    if (lagged_) lagged_->pose_leaving(state_.clones().front().t_ns, state_.clones().front().T_WI);
    state_.marginalize_oldest_clone();
    parallax_.drop_before(state_.clones().front().t_ns);
  }
  smoother_frame_end(force_cloned);
  tm.marginalization_ms = ms_since(t_marg);
  tm.clones = static_cast<int>(state_.clones().size());
  check_divergence(true);
  if (on_frame_) on_frame_(tm);
  pending_timings_ = FrameTimings{};
}

void Estimator::zero_velocity_if_still(const msckf::ClonePose& oldest, const msckf::ClonePose& newest,
                                      double sigma_mps, bool landed) {
  // A median over fewer features is not a statement about the scene; over less than 0.25 s
  // (5 frames at 20 Hz) slow motion has not yet shown above the pixel noise.
  constexpr int kMinFeatures = 20;
  constexpr TimeNs kMinSpanNs = 250'000'000;
  if (newest.t_ns - oldest.t_ns < kMinSpanNs) return;
  const CameraCalib& cam = config_.cameras.front();
  const Eigen::Matrix3d R_IC = cam.T_IC.linear();
  const Eigen::Matrix3d R_new_old = R_IC.transpose() * newest.R_WI.transpose() * oldest.R_WI * R_IC;
  const WindowParallax px = rotation_compensated_parallax(parallax_.matches(oldest.t_ns), R_new_old,
                                                          0.5 * (cam.intrinsics[0] + cam.intrinsics[1]));
  if (px.features < kMinFeatures || !(px.median_px < config_.params.zero_velocity_max_parallax_px)) return;
  if (!zero_velocity_update(state_, sigma_mps)) return;
  ++counters_.zero_velocity_updates;
  if (landed) ++counters_.zero_velocity_updates_landed;
}

void Estimator::check_health(TimeNs t, int used, int rejected_chi2, int untriangulated) {
  const HealthVerdict v = health_.on_frame(t, used + rejected_chi2, rejected_chi2, untriangulated);
  counters_.starvation_episodes = health_.starvation_episodes();
  counters_.starved_s = health_.starved_s();
  counters_.max_chi2_rejected_fraction = health_.max_rejected_fraction();
  if (v.out_of_band && status_ == FilterStatus::kOk) {
    status_ = FilterStatus::kDiverged;
    status_message_ = v.message + " at t=" + std::to_string(t) + " ns";
  }
}

void Estimator::check_divergence(bool full) {
  const ImuState& x = state_.imu();
  const EstimatorParams& p = config_.params;
  std::string why;
  const bool mean_finite = x.T_WI.q.coeffs().allFinite() && x.T_WI.p.allFinite() &&
                           x.v_WI.allFinite() && x.b_g.allFinite() && x.b_a.allFinite() &&
                           x.F_ext.allFinite() && std::isfinite(x.thrust_scale);
  const Eigen::VectorXd diag = state_.P().diagonal();
  if (!mean_finite) {
    why = "state mean is not finite";
  } else if (!(x.thrust_scale > 0.0)) {
    why = "thrust scale " + std::to_string(x.thrust_scale) + " is not positive";
  } else if (x.v_WI.norm() > p.max_velocity) {
    why = "velocity " + std::to_string(x.v_WI.norm()) + " m/s exceeds max_velocity";
  } else if (!diag.allFinite() || diag.minCoeff() <= 0.0) {
    why = "covariance diagonal not positive/finite";
  } else if (std::sqrt(diag.segment<3>(imu_idx::kP).maxCoeff()) > p.max_position_sigma) {
    why = "position sigma exceeds max_position_sigma";
  } else if (full) {
    const CovarianceHealth h = state_.check_and_symmetrize();
    if (!h.finite || !h.positive_definite) why = "covariance not positive definite";
  }
  if (!why.empty()) {
    status_ = FilterStatus::kDiverged;
    status_message_ = why + " at t=" + std::to_string(state_.time()) + " ns";
  }
}

}  // namespace vid
