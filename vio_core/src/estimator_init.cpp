/// @file estimator_init.cpp
/// @brief The estimator while it waits for initialization from its own sensors (init_mode
/// static / auto; docs/notes/initialization.md).
#include "vio_core/estimator.h"

namespace vid {

void Estimator::record_init(TimeNs t, const char* how) {
  if (counters_.inits.size() < 10000) counters_.inits.push_back(InitRecord{t, how});
}

void Estimator::init_from_sensors(const ImuInput& in) {
  const EstimatorParams& p = config_.params;
  if (!dynamic_init_ && p.init_mode == InitMode::kAuto && !config_.cameras.empty()) {
    // A stereo pair when the estimator uses one, cam0 alone otherwise (mono_alignment.h).
    std::vector<CameraCalib> cams = config_.cameras;
    if (!p.use_stereo || cams.size() < 2) cams.resize(1);
    dynamic_init_ = std::make_unique<DynamicInitializer>(p, std::move(cams));
  }
  if (dynamic_init_) dynamic_init_->add_imu(in.t, in.gyro, in.accel, in.T_m);
  // Frames up to this sample: the window of the in-flight initializer, not the filter's.
  while (!frame_queue_.empty() && imu_clock(frame_queue_.front().t_ns) <= in.t) {
    FeatureFrame f = std::move(frame_queue_.front());
    frame_queue_.pop_front();
    ++counters_.frames_skipped;
    if (!dynamic_init_) continue;
    f.t_ns = imu_clock(f.t_ns);
    if (std::optional<InitResult> r = dynamic_init_->add_frame(f)) {
      if (on_init_window_) on_init_window_(r->window_poses);
      initialize(r->t_ns, r->x, r->P);
      record_init(r->t_ns, "in_flight");
      // The state is at the frame's time: propagate to this sample (its rates held over the
      // few ms), then the frames after it as usual.
      ImuInput start = in;
      start.t = r->t_ns;
      last_input_ = start;
      process_imu_initialized(in);
      return;
    }
  }
  std::optional<InitResult> r = initializer_.add(in.t, in.gyro, in.accel, in.T_m);
  std::string why;
  if (r && dynamic_init_) {
    // Auto mode: the IMU's still window must also be still for the camera (a constant velocity
    // is still to the IMU: vid17_like started at 30 s took 0.7 m/s for 0).
    const std::optional<double> px = dynamic_init_->parallax_px(in.t - seconds_to_ns(p.init_window_s));
    if (!px || *px > p.zero_velocity_max_parallax_px) {
      why = px ? "still to the IMU, but the camera moves (" + std::to_string(*px) + " px parallax)"
               : "still to the IMU, no camera frames to confirm it";
      r.reset();
    }
  }
  if (r) {
    initialize(r->t_ns, r->x, r->P);
    record_init(r->t_ns, "still");
    last_input_ = in;
    emit(in.t);
    return;
  }
  if (why.empty()) {
    why = "no still or hovering window";
    if (!initializer_.last_rejection().empty()) why += " (the last: " + initializer_.last_rejection() + ")";
  }
  if (dynamic_init_ && !dynamic_init_->last_rejection().empty())
    why += "; in flight: " + dynamic_init_->last_rejection();
  status_message_ = why;
  last_input_ = in;
}

}  // namespace vid
