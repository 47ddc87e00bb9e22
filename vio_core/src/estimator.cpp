/// @file estimator.cpp
/// @brief Measurement scheduling, initialization and propagation; the accelerometer step is in
/// estimator_accel.cpp, the camera frame's in estimator_frame.cpp.
#include "vio_core/estimator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "estimator_detail.h"
#include "vio_core/fixed_lag.h"  // complete type for lagged_
#include "vio_core/msckf/feature_database.h"
#include "vio_core/propagation.h"
#include "vio_core/thrust.h"
#include "vio_core/visual_updater.h"

namespace vid {
using namespace estimator_detail;

Estimator::Estimator(EstimatorConfig config)
    : config_(std::move(config)),
      state_(config_.params),
      initializer_(config_.params),
      thrust_(seconds_to_ns(config_.params.rotor_gap_s)),
      features_(std::make_unique<msckf::FeatureDatabase>()),
      visual_(std::make_unique<VisualUpdater>(config_.params, config_.cameras)),
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

Estimator::~Estimator() = default;

void Estimator::push(const Measurement& m) {
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

void Estimator::finish() {
  drain(true);
  smoother_frame_end(false, true);
  // Samples still in the jump detector's window: no jump used a gated one.
  for (int i = jumps_.size() - 1; i >= 0; --i)
    if (jumps_.recent(i).gated) record_past_gate(jumps_.recent(i).t_ns);
  jumps_.clear();
}

void Estimator::drain(bool force) {
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

void Estimator::initialize(TimeNs t_ns, const ImuState& x, const Eigen::MatrixXd& P_imu) {
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

Estimator::ImuInput Estimator::interpolate(const ImuInput& a, const ImuInput& b, TimeNs t) const {
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

std::optional<GroundTruthSample> Estimator::groundtruth_at(TimeNs t) const {
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

void Estimator::process_imu(const ImuInput& in) {
  ++counters_.imu_samples;
  const EstimatorParams& p = config_.params;
  if (p.init_sigma_time_offset > 0.0) {
    gyro_history_.push_back({in.t, in.gyro});
    while (in.t - gyro_history_.front().t_ns > kTdRateHalfWindowNs) gyro_history_.pop_front();
  }
  if (status_ == FilterStatus::kWaitingForInit && p.init_mode != InitMode::kGroundTruth) {
    init_from_sensors(in);  // estimator_init.cpp
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

void Estimator::process_imu_initialized(const ImuInput& in) {
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

void Estimator::integrate_to(const ImuInput& a, const ImuInput& b, TimeNs t_end, double noise_scale,
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

}  // namespace vid
