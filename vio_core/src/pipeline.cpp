/// @file pipeline.cpp
/// @brief Measurement scheduling, initialization, propagation, updates and marginalization.
#include "vio_core/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "geometry/so3.h"
#include "vio_core/chi2.h"
#include "vio_core/ekf_update.h"
#include "vio_core/fixed_lag.h"  // complete type for lagged_
#include "vio_core/msckf/clone_poses.h"
#include "vio_core/msckf/feature_database.h"
#include "vio_core/msckf/visual_update.h"
#include "vio_core/propagation.h"
#include "vio_core/thrust.h"
#include "vio_core/force_output.h"

namespace vid {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
constexpr TimeNs kMaxSubstepNs = 10'000'000;  // 10 ms sub-steps over IMU gaps
constexpr TimeNs kGtInitToleranceNs = 20'000'000;
// Longest half window of the gyro fit in the time-offset clone Jacobian (rate_fit.h). 0.1 and 0.15 s
// left t_d inconsistent on the gentle flights (NEES of single runs up to 81 and 51), with 0.25 s
// the estimate still lagged more at 10 s than with 0.4 s (README "Camera-IMU time offset").
// Frames wait this long for the later gyro samples while t_d is estimated.
constexpr TimeNs kTdRateHalfWindowNs = 400'000'000;
// The shortest window rate_for_clone falls back to near an impact: 21 samples at 400 Hz.
constexpr TimeNs kTdRateMinHalfWindowNs = 25'000'000;

}  // namespace

std::string to_string(FilterStatus s) {
  switch (s) {
    case FilterStatus::kWaitingForInit: return "waiting_for_init";
    case FilterStatus::kOk: return "ok";
    case FilterStatus::kDiverged: return "diverged";
  }
  return "unknown";
}

Pipeline::Pipeline(PipelineConfig config)
    : config_(std::move(config)),
      state_(config_.params),
      initializer_(config_.params),
      thrust_(seconds_to_ns(config_.params.rotor_gap_s)),
      features_(std::make_unique<msckf::FeatureDatabase>()),
      jumps_(config_.params),
      phase_(config_.params),
      health_(config_.params),
      accel_noise_(config_.params.accel_noise_density * config_.params.accel_noise_density * config_.params.imu_rate_hz,
                   config_.params.accel_noise_window_s, config_.params.imu_rate_hz) {
  if (config_.params.mode == PropagationMode::kDynamics && !(config_.vehicle.mass_kg > 0.0)) {
    throw std::invalid_argument("dynamics mode needs vehicle mass_kg > 0");
  }
  if (!(config_.params.thrust_delay_s >= 0.0))
    throw std::invalid_argument("thrust_delay_s must be >= 0, got " + std::to_string(config_.params.thrust_delay_s));
  thrust_delay_ns_ = seconds_to_ns(config_.params.thrust_delay_s);
  const Eigen::Vector3d& axis = config_.vehicle.thrust_axis_I;
  if (!(std::abs(axis.norm() - 1.0) < 1e-9) || !(axis.z() > 0.0))
    throw std::invalid_argument("vehicle thrust_axis must be a unit vector with a positive z component");
  tilted_thrust_ = axis != Eigen::Vector3d::UnitZ();
  if (config_.params.mode == PropagationMode::kDynamics) state_.set_linear_drag(config_.vehicle.linear_drag);
  if (config_.params.window_size < 2) throw std::invalid_argument("window_size must be >= 2");
  if (config_.params.smoother_lag_s < 0.0 || config_.params.smoother_clone_period_s < 0.0)
    throw std::invalid_argument("smoother_lag_s and smoother_clone_period_s must be >= 0");
  if (config_.params.smoother_lag_s > 0.0 && config_.params.mode == PropagationMode::kDynamics)
    lagged_ = std::make_unique<FixedLagOutput>(config_.params.force_frame);
  std::sort(config_.cameras.begin(), config_.cameras.end(),
            [](const CameraCalib& a, const CameraCalib& b) { return a.cam_id < b.cam_id; });
}

Pipeline::~Pipeline() = default;

void Pipeline::push(const Measurement& m) {
  stream_time_ = std::max(stream_time_, stamp_of(m));
  if (const auto* imu = std::get_if<ImuSample>(&m)) {
    imu_queue_.push_back(*imu);
  } else if (const auto* rotor = std::get_if<RotorSample>(&m)) {
    if (config_.params.mode == PropagationMode::kDynamics) {
      thrust_.add(rotor->t_ns - thrust_delay_ns_, collective_thrust(*rotor, config_.vehicle) / config_.vehicle.mass_kg);
    }
  } else if (const auto* thrust = std::get_if<ThrustSample>(&m)) {
    if (config_.params.mode == PropagationMode::kDynamics) {
      thrust_.add(thrust->t_ns - thrust_delay_ns_, thrust->thrust_N / config_.vehicle.mass_kg);
    }
  } else if (const auto* frame = std::get_if<FeatureFrame>(&m)) {
    frame_queue_.push_back(*frame);
  } else if (const auto* gt = std::get_if<GroundTruthSample>(&m)) {
    if (config_.params.init_mode == InitMode::kGroundTruth && status_ == FilterStatus::kWaitingForInit) {
      init_gt_.push_back(*gt);
      while (gt->t_ns - init_gt_.front().t_ns > 1'000'000'000) init_gt_.pop_front();
    }
  } else if (const auto* force = std::get_if<ForceSample>(&m)) {
    if (config_.params.init_mode == InitMode::kGroundTruth) last_force_W_ = force->f_W_N;
  }
  drain(false);
}

void Pipeline::finish() {
  drain(true);
  smoother_frame_end(false, true);
  // Samples still in the jump detector's window: no jump used a gated one.
  for (int i = jumps_.size() - 1; i >= 0; --i)
    if (jumps_.recent(i).gated) record_past_gate(jumps_.recent(i).t_ns);
  jumps_.clear();
}

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

void Pipeline::record_rejected(TimeNs t) {
  ++counters_.accel_rejected;
  add_to_spans(counters_.accel_rejected_spans, t);
}

void Pipeline::record_downweighted(TimeNs t) {
  ++counters_.accel_downweighted;
  add_to_spans(counters_.accel_downweighted_spans, t);
}

void Pipeline::record_past_gate(TimeNs t) {
  if (config_.params.accel_gate_downweight) {
    record_downweighted(t);
  } else {
    record_rejected(t);
  }
}

void Pipeline::add_noise_fit(const AccelInnovation& info) {
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

double Pipeline::nominal_accel_var() const {
  const EstimatorParams& p = config_.params;
  return p.accel_noise_density * p.accel_noise_density * p.imu_rate_hz;
}

void Pipeline::accel_step(const ImuInput& in) {
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

void Pipeline::update_flight_phase(TimeNs t) {
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

void Pipeline::drain(bool force) {
  const bool dyn = config_.params.mode == PropagationMode::kDynamics;
  const TimeNs gap_ns = seconds_to_ns(config_.params.rotor_gap_s);
  const TimeNs hold_ns = frame_hold_ns();
  while (!imu_queue_.empty()) {
    const ImuSample& s = imu_queue_.front();
    if (!force && stream_time_ - s.t_ns < hold_ns) break;  // a frame that precedes it may still come
    ImuInput in{s.t_ns, s.gyro_I, s.accel_I, Eigen::Vector3d::Zero(), false};
    if (dyn) {
      const bool ready = thrust_.covers(s.t_ns) || force || stream_time_ - s.t_ns > gap_ns + thrust_delay_ns_;
      if (!ready) break;
      const ThrustQuery q = thrust_.at(s.t_ns);
      in.T_m = tilted_thrust_ ? Eigen::Vector3d(config_.vehicle.thrust_axis_I * q.T_m.z()) : q.T_m;
      in.thrust_held = q.held || !q.valid;
      thrust_.prune_before(s.t_ns);
    }
    imu_queue_.pop_front();
    process_imu(in);
  }
  if (force) {
    // frames newer than the last IMU sample cannot be processed
    counters_.frames_skipped += static_cast<long>(frame_queue_.size());
    frame_queue_.clear();
  }
}

void Pipeline::initialize(TimeNs t_ns, const ImuState& x, const Eigen::MatrixXd& P_imu) {
  if (lagged_) {  // a re-initialization: what the old state smoothed goes out first
    smoother_frame_end(false, true);
    lagged_ = std::make_unique<FixedLagOutput>(config_.params.force_frame);
  }
  state_.initialize(t_ns, x, P_imu);
  if (config_.params.init_sigma_time_offset > 0.0 && !config_.cameras.empty()) {
    state_.add_time_offset(config_.cameras.front().timeshift_cam_imu_s, config_.params.init_sigma_time_offset);
  }
  jumps_.clear();
  accel_noise_.reset();
  phase_.reset();
  last_input_.reset();
  features_ = std::make_unique<msckf::FeatureDatabase>();
  parallax_ = ParallaxWindow();
  status_ = FilterStatus::kOk;
  status_message_ = "ok";
}

Pipeline::ImuInput Pipeline::interpolate(const ImuInput& a, const ImuInput& b, TimeNs t) const {
  if (b.t == a.t) return b;
  const double w = static_cast<double>(t - a.t) / static_cast<double>(b.t - a.t);
  ImuInput r;
  r.t = t;
  r.gyro = (1.0 - w) * a.gyro + w * b.gyro;
  r.accel = (1.0 - w) * a.accel + w * b.accel;
  r.T_m = (1.0 - w) * a.T_m + w * b.T_m;
  r.thrust_held = b.thrust_held;
  return r;
}

std::optional<GroundTruthSample> Pipeline::groundtruth_at(TimeNs t) const {
  // The IMU sample is processed after the ground truth that follows it has arrived (the frame
  // hold), so the newest row is often past t: interpolate between the two that bracket t.
  for (std::size_t i = 1; i < init_gt_.size(); ++i) {
    const GroundTruthSample& a = init_gt_[i - 1];
    const GroundTruthSample& b = init_gt_[i];
    if (!(a.t_ns <= t && t <= b.t_ns)) continue;
    if (b.t_ns - a.t_ns > kGtInitToleranceNs) break;  // a gap in the ground truth
    const double w = b.t_ns == a.t_ns ? 1.0 : static_cast<double>(t - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
    GroundTruthSample g = b;
    g.t_ns = t;
    g.T_WI.p = (1.0 - w) * a.T_WI.p + w * b.T_WI.p;
    g.T_WI.q = a.T_WI.q.slerp(w, b.T_WI.q);
    g.v_WI = (1.0 - w) * a.v_WI + w * b.v_WI;
    g.b_g = (1.0 - w) * a.b_g + w * b.b_g;
    g.b_a = (1.0 - w) * a.b_a + w * b.b_a;
    return g;
  }
  // No bracket (the row of t's own time is read after the IMU sample): the newest earlier row
  // within the tolerance, at its own time; the caller propagates it to t with the IMU.
  if (!init_gt_.empty() && init_gt_.back().t_ns <= t && t - init_gt_.back().t_ns <= kGtInitToleranceNs)
    return init_gt_.back();
  return std::nullopt;
}

void Pipeline::process_imu(const ImuInput& in) {
  ++counters_.imu_samples;
  const EstimatorParams& p = config_.params;
  if (p.init_sigma_time_offset > 0.0) {
    gyro_history_.push_back({in.t, in.gyro});
    while (in.t - gyro_history_.front().t_ns > kTdRateHalfWindowNs) gyro_history_.pop_front();
  }
  if (status_ == FilterStatus::kWaitingForInit && p.init_mode != InitMode::kGroundTruth) {
    init_from_sensors(in);  // pipeline_init.cpp
    return;
  }
  if (status_ == FilterStatus::kWaitingForInit) {
    while (!frame_queue_.empty() && imu_clock(frame_queue_.front().t_ns) <= in.t) {
      frame_queue_.pop_front();
      ++counters_.frames_skipped;
    }
    if (p.init_mode == InitMode::kGroundTruth) {
      if (const std::optional<GroundTruthSample> gt = groundtruth_at(in.t)) {
        ImuState x = state_from_groundtruth(*gt);
        if (last_force_W_ && config_.vehicle.mass_kg > 0.0) {
          set_force_from_body(x, p.force_frame, x.T_WI.q.conjugate() * (*last_force_W_ / config_.vehicle.mass_kg));
        }
        initialize(gt->t_ns, x, initial_covariance(p, x.T_WI.q));
        record_init(gt->t_ns, "groundtruth");
        if (gt->t_ns < in.t) {
          // Start at the row's own time and propagate to this sample (its rates held back over
          // the few ms): taking the row as the state at t would be one IMU period late.
          ImuInput start = in;
          start.t = gt->t_ns;
          last_input_ = start;
          process_imu_initialized(in);
          return;
        }
      }
    }
    last_input_ = in;
    if (status_ == FilterStatus::kOk) emit(in.t);
    return;
  }
  process_imu_initialized(in);
}

void Pipeline::process_imu_initialized(const ImuInput& in) {
  const EstimatorParams& p = config_.params;
  if (status_ == FilterStatus::kDiverged) return;
  if (!last_input_) {  // initialized explicitly: this sample starts the propagation
    last_input_ = in;
    if (in.t > state_.time()) state_.set_time(in.t);
    emit(in.t);
    return;
  }
  if (in.t <= state_.time()) return;  // duplicate / out-of-order sample

  ImuInput a = *last_input_;
  const bool imu_gap = in.t - a.t > seconds_to_ns(p.imu_gap_s);
  if (imu_gap) ++counters_.imu_gaps;
  const double noise_scale = imu_gap ? p.imu_gap_noise_scale : 1.0;
  const double thrust_scale = in.thrust_held ? p.rotor_gap_noise_scale : 1.0;
  if (p.mode == PropagationMode::kDynamics && in.thrust_held) ++counters_.rotor_gap_samples;

  while (!frame_queue_.empty() && imu_clock(frame_queue_.front().t_ns) <= in.t) {
    FeatureFrame f = std::move(frame_queue_.front());
    frame_queue_.pop_front();
    const TimeNs stamp = f.t_ns;
    f.t_ns = imu_clock(stamp);  // from here on every frame time is on the IMU clock
    if (f.t_ns < state_.time()) {
      ++counters_.frames_skipped;
      continue;
    }
    integrate_to(a, in, f.t_ns, noise_scale, thrust_scale);
    a = interpolate(a, in, f.t_ns);
    process_frame(f, stamp, rate_for_clone(f.t_ns, a.gyro));
    if (status_ == FilterStatus::kDiverged) return;
  }
  integrate_to(a, in, in.t, noise_scale, thrust_scale);
  last_input_ = in;

  if (p.mode == PropagationMode::kDynamics && p.accel_update) {
    const auto t0 = Clock::now();
    accel_step(in);
    pending_timings_.accel_update_ms += ms_since(t0);
  }
  if (state_.with_force()) update_flight_phase(in.t);
  check_divergence(false);
  if (status_ == FilterStatus::kOk) emit(in.t);
}

void Pipeline::integrate_to(const ImuInput& a, const ImuInput& b, TimeNs t_end, double noise_scale,
                            double thrust_scale) {
  const TimeNs t0 = state_.time();
  if (t_end <= t0) return;
  const auto c0 = Clock::now();
  const int steps = static_cast<int>((t_end - t0 + kMaxSubstepNs - 1) / kMaxSubstepNs);
  ImuInput prev = interpolate(a, b, t0);
  for (int i = 1; i <= steps; ++i) {
    const TimeNs t = (i == steps) ? t_end : t0 + (t_end - t0) * i / steps;
    const ImuInput next = interpolate(a, b, t);
    ImuInterval u;
    u.dt = static_cast<double>(t - prev.t) * 1e-9;
    u.gyro0 = prev.gyro;
    u.gyro1 = next.gyro;
    const bool dyn = config_.params.mode == PropagationMode::kDynamics;
    u.drive0 = dyn ? prev.T_m : prev.accel;
    u.drive1 = dyn ? next.T_m : next.accel;
    propagate(state_, u, config_.params, noise_scale, thrust_scale);
    state_.set_time(t);
    prev = next;
  }
  pending_timings_.propagation_ms += ms_since(c0);
}

TimeNs Pipeline::frame_hold_ns() const {
  // A frame stamped t_cam belongs at t_cam + t_d on the IMU clock: with t_d < 0 it arrives after
  // the IMU samples it precedes. Hold IMU samples until the stamps of the other streams are
  // -t_d ahead (plus 3 sigma while t_d is estimated), at most 0.2 s; while t_d is estimated, also
  // for the gyro fit after each frame (rate_for_clone).
  const double hold_s = -time_offset_s() + 3.0 * state_.time_offset_sigma();
  const TimeNs fit_ns = config_.params.init_sigma_time_offset > 0.0 ? kTdRateHalfWindowNs : 0;
  return static_cast<TimeNs>(std::llround(std::clamp(hold_s, 0.0, 0.2) * 1e9)) + fit_ns;
}

Eigen::Vector3d Pipeline::rate_for_clone(TimeNs t, const Eigen::Vector3d& fallback) const {
  if (!state_.time_offset()) return fallback;
  std::vector<GyroSample> window(gyro_history_.begin(), gyro_history_.end());
  for (const ImuSample& s : imu_queue_) {  // held by frame_hold_ns: the samples after t
    if (s.t_ns - t > kTdRateHalfWindowNs) break;
    window.push_back({s.t_ns, s.gyro_I});
  }
  const std::optional<AdaptiveRate> fit = fit_rate_adaptive(window, t, kTdRateHalfWindowNs, kTdRateMinHalfWindowNs);
  return fit ? fit->rate_I : fallback;
}

double Pipeline::time_offset_s() const {
  return state_.time_offset_or(config_.cameras.empty() ? 0.0 : config_.cameras.front().timeshift_cam_imu_s);
}

TimeNs Pipeline::imu_clock(TimeNs t_cam) const {
  return t_cam + static_cast<TimeNs>(std::llround(time_offset_s() * 1e9));
}

void Pipeline::process_frame(const FeatureFrame& f, TimeNs stamp, const Eigen::Vector3d& w_I) {
  ++counters_.frames;
  const EstimatorParams& p = config_.params;
  const auto t_frame = Clock::now();
  FrameTimings& tm = pending_timings_;
  tm.t_ns = stamp;

  // The clone's time-offset Jacobian [w_I; v]: the rate fitted to the gyro, and no velocity.
  // The position path carries next to no information on t_d here (the rotation path alone
  // predicts the filter's sigma, README), while the filter's velocity, corrected at every frame,
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
    std::vector<msckf::CameraExtrinsic> extrinsics;
    for (const CameraCalib& c : config_.cameras) {
      msckf::CameraExtrinsic e;
      e.T_IC = c.T_IC;
      extrinsics.push_back(e);
    }
    const CameraCalib& c0 = config_.cameras.front();
    msckf::VisualUpdateParams vp;
    vp.sigma_norm = p.pixel_noise_px / (0.5 * (c0.intrinsics[0] + c0.intrinsics[1]));
    vp.chi2_multiplier = p.chi2_multiplier;
    vp.min_observations = p.min_track_length;
    vp.compression = p.msckf_normal_equations ? msckf::Compression::kNormalEquations : msckf::Compression::kQr;
    vp.triangulation.max_condition = p.triangulation_max_condition;
    const msckf::VisualLinearSystem sys =
        msckf::build_visual_update(tracks, clones, extrinsics, state_.P(), vp);
    tm.features_used += sys.features_used;
    tm.features_rejected += sys.features_rejected_chi2 + sys.features_rejected_triangulation;
    tm.features_rejected_chi2 += sys.features_rejected_chi2;
    counters_.features_used += sys.features_used;
    counters_.features_rejected += sys.features_rejected_chi2 + sys.features_rejected_triangulation;
    counters_.features_rejected_chi2 += sys.features_rejected_chi2;
    counters_.visual_chi2_sum += sys.chi2_sum;
    counters_.visual_dof_sum += sys.dof_sum;
    counters_.features_too_short += sys.features_too_short;
    if (sys.H.rows() > 0) {
      const Eigen::MatrixXd R =
          Eigen::MatrixXd::Identity(sys.H.rows(), sys.H.rows()) * sys.noise_var;
      if (ekf_update(state_, sys.H, sys.r, R).applied) ++counters_.visual_updates;
    }
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

void Pipeline::zero_velocity_if_still(const msckf::ClonePose& oldest, const msckf::ClonePose& newest,
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

void Pipeline::check_health(TimeNs t, int used, int rejected_chi2, int untriangulated) {
  const HealthVerdict v = health_.on_frame(t, used + rejected_chi2, rejected_chi2, untriangulated);
  counters_.starvation_episodes = health_.starvation_episodes();
  counters_.starved_s = health_.starved_s();
  counters_.max_chi2_rejected_fraction = health_.max_rejected_fraction();
  if (v.out_of_band && status_ == FilterStatus::kOk) {
    status_ = FilterStatus::kDiverged;
    status_message_ = v.message + " at t=" + std::to_string(t) + " ns";
  }
}

void Pipeline::check_divergence(bool full) {
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

void Pipeline::emit(TimeNs t) {
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
