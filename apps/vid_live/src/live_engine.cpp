#include "live/live_engine.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "vid_system/summary.h"

namespace vid::live {

namespace {

double ms_between(SteadyClock::time_point a, SteadyClock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

}  // namespace

LiveEngine::LiveEngine(LiveOptions options, lcm::LCM* publisher)
    : opt_(std::move(options)), pub_(publisher), window_(opt_.reorder_window_ns), camera_watch_(opt_.no_camera_s),
      wall_start_(SteadyClock::now()) {
  opt_.session.features = system::FeatureSource::kImages;
  use_rotor_ = opt_.session.has_rotor;
  use_thrust_ = opt_.session.has_thrust && !use_rotor_;
  if (opt_.calibration.rotor) {
    rotor_count_ = opt_.calibration.rotor->count;
    rotor_unit_ = opt_.calibration.rotor->unit;
  }
  system::SystemParams sp = system::make_system_params(opt_.session, opt_.calibration);
  if (opt_.lag_s > 0.0) sp.config.estimator.smoother_lag_s = opt_.lag_s;
  system::check_imu_extrinsic(sp.config, opt_.imu_yaml);
  session_ = std::make_unique<system::System>(std::move(sp));
  tracked_cameras_ = session_->tracked_cameras();
  imu_rate_.emplace(opt_.imu_yaml, "channel " + opt_.channels.imu);
  session_->on_estimate([this](const EstimateOutput& e) { publish_estimate(*session_, e); });
  session_->on_smoothed([this](const EstimateOutput& e) { publish_lagged(*session_, e); });
  session_->on_frame([this](const FrameTimings& ft) {
    auto it = frame_arrival_.find(ft.t_ns);
    if (it != frame_arrival_.end()) processed_arrivals_.push_back(it->second);
    frame_arrival_.erase(frame_arrival_.begin(), it == frame_arrival_.end() ? it : std::next(it));
  });
}

void LiveEngine::start() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (started_) return;
  started_ = true;
  worker_ = std::thread([this] { worker_loop(); });
}

LiveEngine::~LiveEngine() {
  try {
    finish();
  } catch (const std::exception&) {
    // already reported by the caller's finish(), or nobody asked
  }
}

std::vector<std::string> LiveEngine::input_channels() const {
  std::vector<std::string> ch{opt_.channels.imu, opt_.channels.cam0};
  if (tracked_cameras_ > 1) ch.push_back(opt_.channels.cam1);
  if (use_rotor_) ch.push_back(opt_.channels.rotors);
  if (use_thrust_) ch.push_back(opt_.channels.thrust);
  return ch;
}

void LiveEngine::subscribe(lcm::LCM& lcm) {
  // LCM queues at most 30 messages per subscription by default and drops the rest without a
  // word: 75 ms of IMU at 400 Hz. The one-hour soak lost ~1300 IMU messages that way whenever
  // the reader waited for a far-behind worker (the kernel's socket dropped 1). Sensor channels
  // may queue 5 s of IMU (2000 messages), cameras 2 s at 30 Hz (60: ~36 MB of 640x480 stereo).
  for (const auto& ch : input_channels()) {
    const bool camera = ch == opt_.channels.cam0 || ch == opt_.channels.cam1;
    lcm.subscribe(ch, &LiveEngine::on_raw, this)->setQueueCapacity(camera ? 60 : 2000);
  }
}

void LiveEngine::on_raw(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
  on_message(channel, rbuf->data, rbuf->data_size);
}

void LiveEngine::on_message(const std::string& channel, const void* data, std::size_t size) {
  LiveItem item;
  item.arrival = SteadyClock::now();
  const auto& c = opt_.channels;
  Stream stream = Stream::kImu;
  try {
    if (channel == c.imu) {
      stream = Stream::kImu;
      item.data = lcm_io::from_lcm(lcm_io::decode<imu_t>(data, size, channel), channel);
    } else if (channel == c.cam0 || channel == c.cam1) {
      stream = channel == c.cam0 ? Stream::kCam0 : Stream::kCam1;
      const image_t m = lcm_io::decode<image_t>(data, size, channel);
      lcm_io::validate_image(m, channel, 2);
      if (m.camera_id != (stream == Stream::kCam0 ? 0 : 1))
        throw lcm_io::DecodeError(channel + ": image_t camera_id " + std::to_string(m.camera_id) + " on this channel");
      cv::Mat img(m.height, m.width, CV_8UC1);
      std::copy(m.data.begin(), m.data.end(), img.data);
      item.data = CameraImage{m.timestamp, m.camera_id, img};
    } else if (channel == c.rotors) {
      stream = Stream::kRotor;
      item.data = lcm_io::from_lcm(lcm_io::decode<rotor_speeds_t>(data, size, channel), channel, rotor_count_, rotor_unit_);
    } else if (channel == c.thrust) {
      stream = Stream::kThrust;
      item.data = lcm_io::from_lcm(lcm_io::decode<thrust_t>(data, size, channel), channel);
    } else {
      return;  // not ours
    }
    ++messages_;
  } catch (const std::exception& e) {  // DecodeError, or an allocation failure on absurd sizes
    ++messages_;
    std::lock_guard<std::mutex> lock(mutex_);
    window_.count_malformed(stream);
    if (++malformed_warnings_ <= 5) spdlog::warn("{} (counted; further ones only counted after 5)", e.what());
    return;
  }
  item.stream = stream;
  item.t_ns = std::visit([](const auto& x) { return x.t_ns; }, item.data);
  std::unique_lock<std::mutex> lock(mutex_);
  if (input_done_ || failed_) return;
  window_.insert(std::move(item));
  deliver(window_.pop_ready(), lock);
}

void LiveEngine::deliver(std::vector<LiveItem> items, std::unique_lock<std::mutex>& lock) {
  // Images of one timestamp (released consecutively: cameras sort after the sensors) form a frame.
  std::optional<CameraFrame> frame;
  auto close_frame = [&] {
    if (!frame) return;
    if (frame->left.empty()) {
      ++frames_without_left_;  // cam0 missing: the frontend needs the left image
    } else {
      push_work(std::move(*frame), lock);
    }
    frame.reset();
  };
  for (auto& it : items) {
    if (auto* img = std::get_if<CameraImage>(&it.data)) {
      if (frame && frame->t_ns != img->t_ns) close_frame();
      if (!frame) frame = CameraFrame{img->t_ns, {}, {}, it.arrival};
      (img->cam_id == 0 ? frame->left : frame->right) = img->image;
      frame->arrival = std::max(frame->arrival, it.arrival);
      continue;
    }
    close_frame();
    if (auto* s = std::get_if<ImuSample>(&it.data)) push_work(*s, lock);
    else if (auto* r = std::get_if<RotorSample>(&it.data)) push_work(std::move(*r), lock);
    else if (auto* t = std::get_if<ThrustSample>(&it.data)) push_work(*t, lock);
  }
  close_frame();
}

void LiveEngine::push_work(WorkItem w, std::unique_lock<std::mutex>& lock) {
  const bool is_frame = std::holds_alternative<CameraFrame>(w);
  const bool running = started_;  // before start() nothing drains the queue: never wait
  if (!is_frame && running && queue_.size() - queued_frames_ >= opt_.max_queued_samples) {
    // Sensor samples are never dropped; far behind (not a normal overload), the reader waits.
    cv_space_.wait(lock, [&] { return queue_.size() - queued_frames_ < opt_.max_queued_samples || failed_; });
    if (failed_) return;
  }
  if (is_frame && queued_frames_ >= opt_.max_queued_frames) {
    if (opt_.block_when_full && running) {
      cv_space_.wait(lock, [&] { return queued_frames_ < opt_.max_queued_frames || failed_; });
      if (failed_) return;
    } else {
      // Overload: the oldest queued frame goes (IMU and thrust are never dropped).
      auto old = std::find_if(queue_.begin(), queue_.end(),
                              [](const WorkItem& q) { return std::holds_alternative<CameraFrame>(q); });
      if (old != queue_.end()) {
        queue_.erase(old);
        --queued_frames_;
        ++frames_dropped_overload_;
      }
    }
  }
  if (is_frame) ++queued_frames_;
  queue_.push_back(std::move(w));
  cv_work_.notify_one();
}

void LiveEngine::finish() {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!input_done_) {
      deliver(window_.flush(), lock);
      input_done_ = true;
      cv_work_.notify_all();
    }
  }
  start();  // the worker runs whatever is queued, then finishes the session
  if (worker_.joinable()) worker_.join();
  if (failed_) throw std::runtime_error(error_);
}

void LiveEngine::worker_loop() {
  for (;;) {
    WorkItem w;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      cv_work_.wait(lock, [&] { return !queue_.empty() || input_done_; });
      if (queue_.empty()) break;
      w = std::move(queue_.front());
      queue_.pop_front();
      if (std::holds_alternative<CameraFrame>(w)) --queued_frames_;
      cv_space_.notify_all();
    }
    try {
      process(w);
    } catch (const std::exception& e) {
      // e.g. an output file that cannot be written: stop estimating, report it from finish().
      std::lock_guard<std::mutex> lock(mutex_);
      error_ = e.what();
      failed_ = true;
      queue_.clear();
      queued_frames_ = 0;
      cv_space_.notify_all();
      return;
    }
  }
  session_->finish();
  std::lock_guard<std::mutex> lock(mutex_);
  finished_ = true;
  if (session_->status() == FilterStatus::kDiverged) health_ = Health::kDiverged;
  if (camera_watch_.on_end())  // an input shorter than --no-camera-s, without a frame
    spdlog::error("channel {}: no camera frame in the whole input ({:.1f} s of IMU data): status no_camera (exit 5)",
                  opt_.channels.cam0, camera_watch_.imu_span_s());
  if (camera_watch_.fault()) health_ = Health::kNoCamera;
  session_->close_outputs();
  publish_status_locked(last_t_.value_or(0));
}

void LiveEngine::process(WorkItem& w) {
  TimeNs t = 0;
  if (auto* f = std::get_if<CameraFrame>(&w)) {
    t = f->t_ns;
    frame_arrival_[t] = f->arrival;
    session_->push(system::StereoFrame{t, f->left, f->right});
  } else {
    Measurement m = std::visit(
        [](auto& x) -> Measurement {
          if constexpr (std::is_same_v<std::decay_t<decltype(x)>, CameraFrame>) return ImuSample{};
          else return x;
        },
        w);
    t = stamp_of(m);
    if (std::holds_alternative<ImuSample>(m)) imu_rate_->add(t, session_->config());
    session_->push(m);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  if (!first_t_) first_t_ = t;
  last_t_ = std::max(last_t_.value_or(t), t);
  bool camera_fault_now = false;  // the no-camera fault starts: said once, published at once
  if (std::holds_alternative<CameraFrame>(w)) {
    if (camera_watch_.on_frame(t))
      spdlog::info("channel {}: first camera frame after {:.1f} s of IMU data; health no longer no_camera",
                   opt_.channels.cam0, camera_watch_.first_frame_after_s().value_or(0.0));
    last_frame_t_ = t;
    stalled_ = false;
  } else if (std::holds_alternative<ImuSample>(w) && camera_watch_.on_imu(t)) {
    camera_fault_now = true;
    spdlog::error("channel {}: no camera frame in {:.1f} s of IMU data: health no_camera; a run without any camera "
                  "frame ends with status no_camera, exit 5 (--no-camera-s)",
                  opt_.channels.cam0, camera_watch_.imu_span_s());
  } else if (last_frame_t_ && !stalled_ && ns_to_s(t - *last_frame_t_) > opt_.stall_s) {
    stalled_ = true;  // the cameras went quiet while the IMU goes on
    ++camera_stalls_;
  }
  if (session_->status() == FilterStatus::kDiverged) {
    spdlog::error("estimator diverged at {} ns ({}); re-initializing", t, session_->status_message());
    health_ = Health::kDiverged;
    publish_status_locked(t);
    divergences_.push_back({{"t_ns", t}, {"message", session_->status_message()}});
    session_->restart();
    ++reinit_count_;
    frame_arrival_.clear();
    processed_arrivals_.clear();
  }
  health_ = health_locked();
  if (camera_fault_now || !last_status_t_ || t - *last_status_t_ >= 1'000'000'000) publish_status_locked(t);
}

Health LiveEngine::health_locked() const {
  const FilterStatus st = session_->status();
  if (st == FilterStatus::kDiverged) return Health::kDiverged;
  if (camera_watch_.fault()) return Health::kNoCamera;
  if (st == FilterStatus::kWaitingForInit) return Health::kInitializing;
  return stalled_ || session_->starving() ? Health::kDegraded : Health::kTracking;  // cameras quiet or no feature usable
}

namespace {

/// @brief state_t of one estimate (cov_diag: the error state's variances, then the body force's).
state_t state_message(const EstimateOutput& e, Health health, int reinit_count) {
  state_t st;
  st.timestamp = e.t_ns;
  const Eigen::Quaterniond q = e.x.T_WI.q.normalized();
  const Eigen::Vector3d sigma_F = e.cov_F_I.diagonal().cwiseMax(0.0).cwiseSqrt();  // body, as force.csv
  for (int i = 0; i < 3; ++i) {
    st.p[i] = e.x.T_WI.p[i];
    st.v[i] = e.x.v_WI[i];
    st.b_g[i] = e.x.b_g[i];
    st.b_a[i] = e.x.b_a[i];
    st.f_ext_body[i] = e.F_ext_I[i];
    st.f_ext_world[i] = e.F_ext_W[i];
  }
  st.q[0] = q.w(), st.q[1] = q.x(), st.q[2] = q.y(), st.q[3] = q.z();
  for (int i = 0; i < 15; ++i) st.cov_diag[i] = i < e.sigma.size() ? e.sigma[i] * e.sigma[i] : 0.0;
  for (int i = 0; i < 3; ++i) st.cov_diag[15 + i] = sigma_F[i] * sigma_F[i];  // body frame, as force.csv
  st.status = static_cast<int8_t>(health);
  st.reinit_count = reinit_count;
  return st;
}

/// @brief force_t of one estimate (dynamics mode).
force_t force_message(const system::System& s, const EstimateOutput& e) {
  force_t f;
  f.timestamp = e.t_ns;
  f.mass_kg = s.config().vehicle ? s.config().vehicle->mass_kg : 0.0;
  const Eigen::Vector3d sigma_F = e.cov_F_I.diagonal().cwiseMax(0.0).cwiseSqrt();
  for (int i = 0; i < 3; ++i) {
    f.f_body[i] = e.F_ext_I[i];
    f.f_world[i] = e.F_ext_W[i];
    f.sigma_body[i] = sigma_F[i];
    f.f_world_newton[i] = e.F_ext_W[i] * f.mass_kg;
  }
  return f;
}

}  // namespace

state_t LiveEngine::state_now(const EstimateOutput& e) {
  std::lock_guard<std::mutex> lock(mutex_);
  return state_message(e, health_, reinit_count_);
}

void LiveEngine::publish_estimate(const system::System& s, const EstimateOutput& e) {
  // Worker thread, inside session_->push(); the mutex is not held.
  const state_t st = state_now(e);
  if (pub_) pub_->publish(opt_.channels.state, &st);
  if (pub_ && s.dynamics()) {
    const force_t f = force_message(s, e);
    pub_->publish(opt_.channels.force, &f);
  }
  const auto now = SteadyClock::now();
  std::lock_guard<std::mutex> lock(mutex_);
  ++published_;
  for (const auto& arrival : processed_arrivals_) latency_ms_.add(ms_between(arrival, now));
  processed_arrivals_.clear();
}

void LiveEngine::publish_lagged(const system::System& s, const EstimateOutput& e) {
  // Worker thread (or finish(), which releases the last clones). The health is today's, not
  // that of the estimate's time: a lagged state says how the filter is doing now.
  const state_t st = state_now(e);
  const force_t f = force_message(s, e);
  if (pub_) {
    pub_->publish(opt_.channels.state_lagged, &st);
    pub_->publish(opt_.channels.force_lagged, &f);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  ++published_lagged_;
}

std::vector<std::pair<std::string, std::int64_t>> LiveEngine::counters() const {
  std::vector<std::pair<std::string, std::int64_t>> out;
  for (int i = 0; i < kNumStreams; ++i) {
    const Stream s = static_cast<Stream>(i);
    const StreamCounters& c = window_.counters(s);
    const std::string n = stream_name(s);
    out.emplace_back(n + ".received", c.received);
    out.emplace_back(n + ".malformed", c.malformed);
    out.emplace_back(n + ".duplicate", c.duplicate);
    out.emplace_back(n + ".reordered", c.reordered);
    out.emplace_back(n + ".late", c.late);
    out.emplace_back(n + ".missing", c.missing);
  }
  out.emplace_back("frames_dropped_overload", frames_dropped_overload_);
  out.emplace_back("frames_without_left_image", frames_without_left_);
  out.emplace_back("camera_stalls", camera_stalls_);
  out.emplace_back("reinit_count", reinit_count_);
  out.emplace_back("states_published", published_);
  if (session_->smoothing()) out.emplace_back("lagged_states_published", published_lagged_);
  return out;
}

void LiveEngine::publish_status_locked(TimeNs t) {
  last_status_t_ = t;
  if (!pub_) return;
  status_t m;
  m.timestamp = t;
  m.status = static_cast<int8_t>(health_);
  m.status_text = lcm_io::to_string(health_);
  m.message = session_->status_message();
  m.flight_phase = to_string(session_->flight_phase());
  m.reinit_count = reinit_count_;
  for (const auto& [name, value] : counters()) {
    m.counter_names.push_back(name);
    m.counter_values.push_back(value);
  }
  m.num_counters = static_cast<int32_t>(m.counter_names.size());
  pub_->publish(opt_.channels.status, &m);
}

Health LiveEngine::health() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return health_;
}

bool LiveEngine::camera_never_delivered() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return camera_watch_.never_delivered();
}

long LiveEngine::published_states() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return published_;
}

nlohmann::json LiveEngine::summary() const {
  std::lock_guard<std::mutex> lock(mutex_);
  nlohmann::json s = session_->summary();
  const double wall_s = std::chrono::duration<double>(SteadyClock::now() - wall_start_).count();
  const double data_s = first_t_ ? ns_to_s(*last_t_ - *first_t_) : 0.0;
  s["source"] = opt_.source_url;
  s["health"] = lcm_io::to_string(health_);
  if (finished_ && health_ != Health::kDiverged && session_->status() != FilterStatus::kDiverged)
    s["status"] = to_string(session_->status());
  if (finished_ && camera_watch_.never_delivered()) {  // the cause, whatever the estimator did without it
    s["status"] = "no_camera";
    s["status_message"] = fmt::format("no camera frame on channel {} in {:.1f} s of IMU data", opt_.channels.cam0,
                                      camera_watch_.imu_span_s());
  }
  const auto first_frame = camera_watch_.first_frame_after_s();
  s["camera_first_frame_after_s"] = first_frame ? nlohmann::json(*first_frame) : nlohmann::json(nullptr);
  s["data_duration_s"] = data_s;
  s["wall_time_s"] = wall_s;
  s["real_time_factor"] = wall_s > 0.0 ? data_s / wall_s : 0.0;
  const double cpu_s = s["cpu"]["process_cpu_s"].get<double>();
  s["cpu"]["real_time_factor_cpu"] = cpu_s > 0.0 ? data_s / cpu_s : 0.0;
  nlohmann::json faults;
  for (const auto& [name, value] : counters()) faults[name] = value;
  s["faults"] = faults;
  s["reinit_count"] = reinit_count_;
  if (!divergences_.empty()) s["divergences"] = divergences_;
  s["latency_image_to_state_ms"] = latency_ms_.to_json();
  s["live"] = {{"reorder_window_ms", static_cast<double>(opt_.reorder_window_ns) * 1e-6},
               {"max_queued_frames", opt_.max_queued_frames},
               {"overload", opt_.block_when_full ? "block" : "drop_oldest_frames"},
               {"stall_s", opt_.stall_s},
               {"no_camera_s", opt_.no_camera_s},
               {"input_channels", input_channels()}};
  return s;
}

void LiveEngine::write_summary(const nlohmann::json& extra) const {
  if (!opt_.session.out_dir) return;
  nlohmann::json s = summary();
  s.update(extra);
  system::write_summary(*opt_.session.out_dir, s);
}

}  // namespace vid::live
