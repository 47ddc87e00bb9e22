// The estimator system's data flow, top to bottom (system.h):
//
//   ImuSample ------------------------------> frontend (gyro prediction) + estimator
//   RotorSample / ThrustSample -------------> estimator
//   ImageFrame (paths) -> decode -+
//   push_decoded (decoded ahead) -+-> image checks -> frontend (KLT) -> FeatureFrame -> estimator
//   StereoFrame (decoded) --------+
//   FeatureFrame (feat0) -> undistortion ---------------------------------------> estimator
//   GroundTruthSample / ForceSample / MassSample -> metrics' truth series ----> estimator
//
//   estimator -> estimate -> state.csv / force.csv / trajectory_tum.txt, metrics' series, observer
//             -> frame timings -> timing.csv, stage statistics, observer
//             -> status changes -> observer
//
// summary.json's fields are assembled in system_summary.cpp.
#include "vid_system/system.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "frontend/camera_model.h"
#include "frontend/image_decode.h"
#include "vid_system/frontend_stage.h"

namespace vid::system {

using Clock = std::chrono::steady_clock;

namespace {

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

EstimateRow to_row(const EstimateOutput& e) {
  EstimateRow r;
  r.t_ns = e.t_ns;
  r.T_WI = e.x.T_WI;
  r.v_WI = e.x.v_WI;
  r.b_g = e.x.b_g;
  r.b_a = e.x.b_a;
  r.F_ext_I = e.F_ext_I;
  const int n = std::min<int>(18, static_cast<int>(e.sigma.size()));
  r.sigma.head(n) = e.sigma.head(n);
  // The force sigma is reported in the body frame whatever frame the filter's force state uses.
  if (n == 18) r.sigma.tail<3>() = e.cov_F_I.diagonal().cwiseMax(0.0).cwiseSqrt();
  r.thrust_scale = e.x.thrust_scale;
  r.sigma_thrust_scale = e.sigma_thrust_scale;
  r.time_offset_s = e.time_offset_s;
  r.sigma_time_offset_s = e.sigma_time_offset_s;
  return r;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Construction: feat0 undistortion or the KLT frontend, the estimator, the output files.

System::System(SystemParams params) : p_(std::move(params)), cpu_start_s_(process_cpu_s()) {
  if (p_.config.cameras.empty()) throw std::runtime_error("System: no camera calibration");
  if (p_.features == FeatureSource::kFeat0)
    for (const auto& cam : p_.config.cameras) models_.push_back(CameraModel::create(cam));
  build_estimator();
  for (const std::string& line : p_.config.overrides) spdlog::warn("{}", line);
  const EstimatorParams& ep = p_.config.estimator;
  if (dynamics() && ep.thrust_scale_random_walk > 0.0 && ep.force_rate_random_walk > 0.0) {
    spdlog::warn("thrust_scale_random_walk {} with the force-rate state on (force_rate_random_walk {}): a mass "
                 "change and a force along the thrust are not separable, the mass estimate will be arbitrary; "
                 "set force_rate_random_walk: 0 for a vehicle without fast external forces (docs/notes/mass-state.md)",
                 ep.thrust_scale_random_walk, ep.force_rate_random_walk);
  }
  if (p_.out_dir) {
    const bool mass_state = dynamics() && ep.thrust_scale_random_walk > 0.0 && p_.config.vehicle;
    outputs_.emplace(*p_.out_dir, dynamics(), mass_state ? std::optional<double>(p_.config.vehicle->mass_kg) : std::nullopt,
                     ep.init_sigma_time_offset > 0.0);
  }
  image_bits_.fill(p_.config.frontend.image_bit_depth);
  if (p_.write_tracks && p_.out_dir && frontend_) {  // once: a re-initialization keeps the file
    tracks_.emplace(*p_.out_dir / "tracks.csv");
    tracks_->line(tracks_csv_header());
  }
  if (p_.out_dir && smoothing()) smoothed_outputs_.emplace(*p_.out_dir);
}

System::~System() = default;

void System::build_estimator() {
  EstimatorConfig pcfg;
  pcfg.params = p_.config.estimator;
  // After a divergence the vehicle is rarely at rest, and a smooth stretch of flight can pass the
  // IMU's still test (vid17_like did, 0.5 s after its divergence): a restart initializes as
  // `auto`, whose still window must also be still for the camera, in flight otherwise.
  if (restarts_ > 0 && pcfg.params.init_mode == InitMode::kStatic) pcfg.params.init_mode = InitMode::kAuto;
  pcfg.vehicle = p_.config.vehicle.value_or(VehicleParams{});
  pcfg.cameras = p_.config.cameras;
  estimator_ = std::make_unique<Estimator>(pcfg);
  estimator_->set_estimate_callback([this](const EstimateOutput& e) { estimate_out(e); });
  estimator_->set_frame_callback([this](const FrameTimings& ft) { frame_out(ft); });
  estimator_->set_smoothed_callback([this](const EstimateOutput& e) { smoothed_out(e); });
  estimator_->set_init_window_callback([this](const std::vector<TimedPose>& w) { init_window_out(w); });
  if (p_.features != FeatureSource::kFeat0)
    frontend_ = std::make_unique<FrontendStage>(p_.config.frontend, p_.config.cameras);
  last_status_ = estimator_->status();
}

void System::restart() {
  past_counters_.merge(estimator_->counters());
  tracking_ms_.clear();
  ++restarts_;
  mark_next_estimate_ = mark_next_smoothed_ = true;  // the new piece's first estimates
  build_estimator();
}

void System::initialize(TimeNs t_ns, const ImuState& x, const Eigen::MatrixXd& P_imu) {
  estimator_->initialize(t_ns, x, P_imu);
  report_status();
}

// ---------------------------------------------------------------------------------------------
// Input

void System::push(const Measurement& m) {
  std::visit([this](const auto& x) { push(x); }, m);
}

void System::push(const ImuSample& s) {
  if (frontend_) frontend_->add_imu(s);
  to_estimator(s);
}

void System::push(const RotorSample& s) {
  if (!p_.ignore_rotor_speeds) to_estimator(s);
}
void System::push(const ThrustSample& s) { to_estimator(s); }

void System::push(const GroundTruthSample& s) {
  gt_p_.t_ns.push_back(s.t_ns);
  gt_p_.v.push_back(s.T_WI.p);
  gt_R_WI_.push_back(s.T_WI.q.toRotationMatrix());
  to_estimator(s);
}

void System::push(const ForceSample& s) {
  gt_f_W_.t_ns.push_back(s.t_ns);
  gt_f_W_.v.push_back(s.f_W_N);  // divided by the mass in summary()
  to_estimator(s);
}

void System::push(const MassSample& s) {
  mass_t_.push_back(s.t_ns);
  mass_kg_.push_back(s.mass_kg);
  to_estimator(s);
}

void System::push(const FeatureFrame& frame) {
  ++feature_frames_;
  FeatureFrame f = frame;
  for (auto& o : f.observations) {
    if (o.has_norm || o.cam_id < 0 || o.cam_id >= static_cast<int>(models_.size())) continue;
    o.has_norm = models_[static_cast<std::size_t>(o.cam_id)]->undistort(o.uv, &o.uv_norm);
  }
  to_estimator(std::move(f));
}

void System::push(const ImageFrame& frame) {
  const auto t_decode = Clock::now();
  const double cpu_decode = thread_cpu_ms();
  std::vector<std::pair<int, cv::Mat>> images;
  for (const auto& ref : frame.images)
    if (ref.cam_id <= 1) {
      int& bits = image_bits_[ref.cam_id == 1 ? 1 : 0];
      if (bits == 0) bits = detect_bit_depth({ref.path}).bits;  // the first image fixes the stream's scale
      images.emplace_back(ref.cam_id, decode_gray8(ref.path, nullptr, bits));
    }
  push_decoded(frame, images, ms_since(t_decode), thread_cpu_ms() - cpu_decode);
}

void System::push_decoded(const ImageFrame& frame, const std::vector<std::pair<int, cv::Mat>>& images,
                          double decode_ms, double decode_cpu_ms) {
  ++frames_;
  decode_ms_.add(decode_ms);
  decode_cpu_ms_ += decode_cpu_ms;
  const auto& cameras = p_.config.cameras;
  cv::Mat left, right;
  bool ok = true;
  std::size_t k = 0;
  for (const auto& ref : frame.images) {
    if (ref.cam_id > 1) continue;
    if (k >= images.size() || images[k].first != ref.cam_id)
      throw std::logic_error(ref.path + ": decoded images do not match the frame's image list");
    const cv::Mat& g = images[k++].second;
    const CameraCalib& cam = cameras.at(std::min<std::size_t>(ref.cam_id, cameras.size() - 1));
    if (!check_frame_image(g, ref.path, cam.width, cam.height, faults_)) ok = false;
    (ref.cam_id == 0 ? left : right) = g;
  }
  if (ok && !left.empty()) track(frame.t_ns, left, right);
}

void System::add_unused_decode_cpu_ms(double ms) { decode_cpu_ms_ += ms; }

void System::push(const StereoFrame& frame) {
  ++frames_;
  const auto& cameras = p_.config.cameras;
  bool ok = true;
  for (int cam_id = 0; cam_id < 2; ++cam_id) {
    const cv::Mat& g = cam_id == 0 ? frame.left : frame.right;
    if (g.empty()) continue;
    const CameraCalib& cam = cameras.at(std::min<std::size_t>(cam_id, cameras.size() - 1));
    if (g.type() != CV_8UC1) {
      faults_.skip(FrameFault::kUnreadable,
                   fmt::format("camera {} image at {} ns: unreadable image (not 8-bit mono)", cam_id, frame.t_ns));
      ok = false;
    } else if (g.cols != cam.width || g.rows != cam.height) {
      faults_.skip(FrameFault::kWrongSize, fmt::format("camera {} image at {} ns: image is {}x{}, calibration says {}x{}",
                                                       cam_id, frame.t_ns, g.cols, g.rows, cam.width, cam.height));
      ok = false;
    }
  }
  if (ok && !frame.left.empty()) track(frame.t_ns, frame.left, frame.right);
}

// Frontend: KLT tracks of a checked frame become the estimator's feature frame.
void System::track(TimeNs t_ns, const cv::Mat& left, const cv::Mat& right) {
  if (!frontend_) return;
  const auto t_track = Clock::now();
  const double cpu_track = thread_cpu_ms();
  FeatureFrame ff = frontend_->track(t_ns, left, right);
  tracking_ms_[t_ns] = ms_since(t_track);
  tracking_cpu_ms_.add(thread_cpu_ms() - cpu_track);
  if (tracks_)
    for (const auto& ob : ff.observations) tracks_->line(tracks_csv_row(ff.t_ns, ob));
  to_estimator(std::move(ff));
}

// Estimator: every measurement enters the estimator here; status changes go to the observer.
void System::to_estimator(Measurement m) {
  estimator_->push(m);
  report_status();
}

void System::finish() {
  estimator_->finish();
  report_status();
}

void System::report_status() {
  const FilterStatus now = estimator_->status();
  if (now == last_status_) return;
  last_status_ = now;
  if (on_status_) on_status_(now, estimator_->status_message());
}

// ---------------------------------------------------------------------------------------------
// Output

void System::estimate_out(const EstimateOutput& e) {
  const EstimateRow row = to_row(e);
  if (mark_next_estimate_) start_piece(row.t_ns);
  last_estimate_t_ = row.t_ns;
  if (outputs_) outputs_->write_estimate(row);
  ++estimates_;
  if (dynamics()) force_mag_.add(e.F_ext_I);
  // Kept for the summary's ATE / force RMSE only when there is ground truth to score against
  // (vid_run on a simulated sequence; ground truth comes first in time order): a live run
  // would otherwise hold every estimate, ~40 kB/s at 400 Hz.
  if (!gt_p_.t_ns.empty() || !gt_f_W_.t_ns.empty()) {
    est_p_.t_ns.push_back(row.t_ns);
    est_p_.v.push_back(row.T_WI.p);
    if (dynamics()) {
      est_f_W_.t_ns.push_back(row.t_ns);
      est_f_W_.v.push_back(e.F_ext_W);
      est_f_I_.t_ns.push_back(row.t_ns);
      est_f_I_.v.push_back(e.F_ext_I);
    }
  }
  if (on_estimate_) on_estimate_(e);
}

void System::start_piece(TimeNs t_ns) {
  mark_next_estimate_ = false;
  piece_starts_.push_back(t_ns);
  if (outputs_) outputs_->mark_reinitialization(t_ns);
}

// After a re-initialization in flight the trajectory goes on over the initializer's window (a
// first initialization starts where the filter does, as with a still window).
void System::init_window_out(const std::vector<TimedPose>& poses) {
  std::vector<TimedPose> after;  // the trajectory stays in time order
  for (const TimedPose& x : poses)
    if (x.t_ns > last_estimate_t_) after.push_back(x);
  if (!mark_next_estimate_ || after.empty()) return;
  start_piece(after.front().t_ns);
  for (const TimedPose& x : after) {
    if (outputs_) outputs_->write_pose(x);
    if (!gt_p_.t_ns.empty()) {  // scored with the piece, as estimate_out's
      est_p_.t_ns.push_back(x.t_ns);
      est_p_.v.push_back(x.T.p);
    }
  }
}

void System::smoothed_out(const EstimateOutput& e) {
  const EstimateRow row = to_row(e);
  if (smoothed_outputs_ && mark_next_smoothed_) smoothed_outputs_->mark_reinitialization(row.t_ns);
  mark_next_smoothed_ = false;
  if (smoothed_outputs_) smoothed_outputs_->write_estimate(row);
  if (!gt_p_.t_ns.empty() || !gt_f_W_.t_ns.empty()) {  // as estimate_out
    est_p_smoothed_.t_ns.push_back(row.t_ns);
    est_p_smoothed_.v.push_back(row.T_WI.p);
    est_f_W_smoothed_.t_ns.push_back(row.t_ns);
    est_f_W_smoothed_.v.push_back(e.F_ext_W);
    est_f_I_smoothed_.t_ns.push_back(row.t_ns);
    est_f_I_smoothed_.v.push_back(e.F_ext_I);
  }
  if (on_smoothed_) on_smoothed_(e);
}

void System::frame_out(const FrameTimings& ft) {
  const bool starving = estimator_->starving();
  if (starving && !was_starving_ && ++starvation_warnings_ <= 10)
    spdlog::warn("feature starvation at {} ns: no feature track reached an update for {} s, the IMU alone carries the estimate{}",
                 ft.t_ns, p_.config.estimator.health_starvation_s,
                 starvation_warnings_ == 10 ? " (further episodes are only counted: summary.json health)" : "");
  was_starving_ = starving;
  TimingRow row;
  row.t_ns = ft.t_ns;
  if (auto it = tracking_ms_.find(ft.t_ns); it != tracking_ms_.end()) {
    row.tracking_ms = it->second;
    tracking_ms_.erase(tracking_ms_.begin(), std::next(it));
  }
  row.propagation_ms = ft.propagation_ms;
  row.accel_update_ms = ft.accel_update_ms;
  row.msckf_update_ms = ft.msckf_update_ms;
  row.marginalization_ms = ft.marginalization_ms;
  row.total_ms =
      row.tracking_ms + row.propagation_ms + row.accel_update_ms + row.msckf_update_ms + row.marginalization_ms;
  if (outputs_) outputs_->write_timing(row);
  stage_times_.add(row);
  if (on_frame_) on_frame_(ft);
}

void System::close_outputs() {
  faults_.report_rest();
  if (outputs_) outputs_->close();
  if (tracks_) tracks_->close();
  if (smoothed_outputs_) smoothed_outputs_->close();
}

FilterStatus System::status() const { return estimator_->status(); }
const std::string& System::status_message() const { return estimator_->status_message(); }
FlightPhase System::flight_phase() const { return estimator_->flight_phase(); }
bool System::starving() const { return estimator_->starving(); }
int System::tracked_cameras() const { return frontend_ ? frontend_->cameras() : 0; }

}  // namespace vid::system
