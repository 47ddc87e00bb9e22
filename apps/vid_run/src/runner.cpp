#include "runner/runner.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <stdexcept>
#include <vector>

#include "app/prefetch.h"
#include "app/progress.h"
#include "frontend/camera_model.h"
#include "frontend/image_decode.h"
#include "frontend/klt_tracker.h"
#include "io/dataset_reader.h"
#include "runner/run_session.h"

namespace vid::runner {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// Timestamp of the last row of a CSV (read from its tail), for the progress bar's total.
std::optional<TimeNs> last_timestamp(const fs::path& csv) {
  std::ifstream f(csv, std::ios::binary | std::ios::ate);
  if (!f) return std::nullopt;
  const std::streamoff size = f.tellg();
  const std::streamoff back = std::min<std::streamoff>(size, 4096);
  f.seekg(size - back);
  std::string tail(static_cast<std::size_t>(back), '\0');
  f.read(tail.data(), back);
  std::size_t end = tail.find_last_not_of("\r\n ");
  if (end == std::string::npos) return std::nullopt;
  const std::size_t start = tail.rfind('\n', end);
  const std::string line = tail.substr(start == std::string::npos ? 0 : start + 1, end + 1);
  try {
    return static_cast<TimeNs>(std::stoll(line.substr(0, line.find(','))));
  } catch (...) {
    return std::nullopt;
  }
}

EstimateRow to_row(const EstimateOutput& e) {
  EstimateRow r;
  r.t_ns = e.t_ns;
  r.q_WI = e.x.q_WI;
  r.p_WI = e.x.p_WI;
  r.v_WI = e.x.v_WI;
  r.b_g = e.x.b_g;
  r.b_a = e.x.b_a;
  r.F_ext_I = e.F_ext_I;
  const int n = std::min<int>(18, static_cast<int>(e.sigma.size()));
  r.sigma.head(n) = e.sigma.head(n);
  // The force sigma is reported in the body frame whatever frame the filter's force state uses.
  if (n == 18) r.sigma.tail<3>() = e.cov_F_I.diagonal().cwiseMax(0.0).cwiseSqrt();
  return r;
}

void add_counters(PipelineCounters& a, const PipelineCounters& b) {
  a.imu_samples += b.imu_samples;
  a.accel_updates += b.accel_updates;
  a.accel_rejected += b.accel_rejected;
  a.accel_used_in_jumps += b.accel_used_in_jumps;
  a.force_jumps += b.force_jumps;
  a.accel_rejected_spans.insert(a.accel_rejected_spans.end(), b.accel_rejected_spans.begin(),
                                b.accel_rejected_spans.end());
  a.force_jump_events.insert(a.force_jump_events.end(), b.force_jump_events.begin(), b.force_jump_events.end());
  a.rotor_gap_samples += b.rotor_gap_samples;
  a.imu_gaps += b.imu_gaps;
  a.frames += b.frames;
  a.frames_skipped += b.frames_skipped;
  a.visual_updates += b.visual_updates;
  a.features_used += b.features_used;
  a.features_rejected += b.features_rejected;
  a.features_rejected_chi2 += b.features_rejected_chi2;
  a.features_too_short += b.features_too_short;
  a.observations_without_norm += b.observations_without_norm;
}

/// @brief What happened to the accelerometer samples: rejected count, fraction and time spans,
/// and the force jumps (summary.json "accel"). Spans and jumps list at most 200 entries each.
nlohmann::json accel_report(const PipelineCounters& c) {
  nlohmann::json j;
  const long seen = c.accel_updates + c.accel_rejected + c.accel_used_in_jumps;
  j["samples"] = seen;
  j["rejected"] = c.accel_rejected;
  j["rejected_fraction"] = seen > 0 ? static_cast<double>(c.accel_rejected) / static_cast<double>(seen) : 0.0;
  j["used_in_jumps"] = c.accel_used_in_jumps;
  j["force_jumps"] = c.force_jumps;
  double span_s = 0.0;
  nlohmann::json spans = nlohmann::json::array();
  for (const TimeSpan& s : c.accel_rejected_spans) {
    span_s += static_cast<double>(s.last_ns - s.first_ns) * 1e-9;
    if (spans.size() < 200) spans.push_back({s.first_ns, s.last_ns});
  }
  j["rejected_spans_ns"] = spans;
  j["rejected_span_count"] = c.accel_rejected_spans.size();
  j["rejected_span_total_s"] = span_s;
  nlohmann::json jumps = nlohmann::json::array();
  for (const ForceJumpRecord& r : c.force_jump_events) {
    if (jumps.size() >= 200) break;
    jumps.push_back({{"t_ns", r.t_ns}, {"window", r.window}, {"size_mps2", r.size_mps2}});
  }
  j["force_jump_events"] = jumps;
  return j;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// RunSession

RunSession::RunSession(const SessionOptions& opt, const io::DatasetCalibration& calibration)
    : opt_(opt), calib_(calibration), cpu_start_s_(process_cpu_s()) {
  cfg_ = resolve_run_config(opt.config, calib_);
  const bool thrust_data = opt.has_rotor || opt.has_thrust;
  // Mode: the flag, else the preset's explicit `mode:`, else dynamics when thrust information exists.
  mode_source_ = "flag --mode";
  if (opt.mode) {
    cfg_.estimator.mode = *opt.mode;
  } else if (cfg_.preset_mode) {
    cfg_.estimator.mode = *cfg_.preset_mode;
    mode_source_ = cfg_.sources.at("estimator");
  } else {
    cfg_.estimator.mode = thrust_data ? PropagationMode::kDynamics : PropagationMode::kImu;
    mode_source_ = thrust_data ? "auto (rotor/thrust data present)" : "auto (no rotor/thrust data)";
  }
  if (opt.init) cfg_.estimator.init_mode = *opt.init;
  if (dynamics() && !thrust_data)
    throw std::runtime_error(opt.context +
                             ": dynamics mode needs rotor speeds (rotor0/) or thrust (thrust0/), and the dataset has "
                             "neither; run with --mode imu");
  if (dynamics() && (!cfg_.vehicle || (opt.has_rotor && cfg_.vehicle->rotor_thrust_coefficients.empty())))
    throw std::runtime_error(opt.context +
                             ": dynamics mode needs vehicle.yaml (mass_kg, rotor_thrust_coefficients) in the dataset or "
                             "the --config preset");
  if (cfg_.cameras.empty())
    throw std::runtime_error(opt.context + ": no camera calibration (camN/sensor.yaml or --config camchain.yaml)");
  if (opt.features == FeatureSource::kFeat0)
    for (const auto& cam : cfg_.cameras) models_.push_back(CameraModel::create(cam));
  build_estimator();
  if (opt.out_dir) outputs_.emplace(*opt.out_dir, dynamics());
}

RunSession::~RunSession() = default;

void RunSession::build_estimator() {
  PipelineConfig pcfg;
  pcfg.params = cfg_.estimator;
  pcfg.vehicle = cfg_.vehicle.value_or(VehicleParams{});
  pcfg.cameras = cfg_.cameras;
  pipeline_ = std::make_unique<Pipeline>(pcfg);
  pipeline_->set_estimate_callback([this](const EstimateOutput& e) { on_estimate(e); });
  pipeline_->set_frame_callback([this](const FrameTimings& ft) { on_frame(ft); });
  if (opt_.features != FeatureSource::kFeat0) {
    std::vector<CameraCalib> tracked(cfg_.cameras.begin(),
                                     cfg_.cameras.begin() + std::min<std::size_t>(2, cfg_.cameras.size()));
    if (!cfg_.frontend.stereo) tracked.resize(1);
    tracker_ = std::make_unique<KltTracker>(cfg_.frontend, tracked);
  }
}

void RunSession::restart() {
  add_counters(past_counters_, pipeline_->counters());
  tracking_ms_.clear();
  build_estimator();
  ++restarts_;
}

int RunSession::tracked_cameras() const {
  if (!tracker_) return 0;
  return (tracker_->params().stereo && cfg_.cameras.size() >= 2) ? 2 : 1;
}

FilterStatus RunSession::status() const { return pipeline_->status(); }
const std::string& RunSession::status_message() const { return pipeline_->status_message(); }

void RunSession::on_estimate(const EstimateOutput& e) {
  const EstimateRow row = to_row(e);
  if (outputs_) outputs_->write_estimate(row);
  ++estimates_;
  est_p_.t_ns.push_back(row.t_ns);
  est_p_.v.push_back(row.p_WI);
  if (dynamics()) {
    est_f_W_.t_ns.push_back(row.t_ns);
    est_f_W_.v.push_back(e.F_ext_W);
    est_f_I_.t_ns.push_back(row.t_ns);
    est_f_I_.v.push_back(e.F_ext_I);
  }
  if (on_estimate_) on_estimate_(e);
}

void RunSession::on_frame(const FrameTimings& ft) {
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

void RunSession::push(const Measurement& m) {
  if (const auto* img = std::get_if<ImageFrame>(&m)) {
    const auto t_decode = Clock::now();
    const double cpu_decode = thread_cpu_ms();
    std::vector<std::pair<int, cv::Mat>> images;
    for (const auto& ref : img->images)
      if (ref.cam_id <= 1) images.emplace_back(ref.cam_id, decode_gray8(ref.path));
    push_decoded(*img, images, ms_since(t_decode), thread_cpu_ms() - cpu_decode);
  } else if (const auto* ff = std::get_if<FeatureFrame>(&m)) {
    ++feature_frames_;
    FeatureFrame f = *ff;
    for (auto& o : f.observations) {
      if (o.has_norm || o.cam_id < 0 || o.cam_id >= static_cast<int>(models_.size())) continue;
      o.has_norm = models_[static_cast<std::size_t>(o.cam_id)]->undistort(o.uv, &o.uv_norm);
    }
    pipeline_->push(Measurement{std::move(f)});
  } else {
    if (const auto* imu = std::get_if<ImuSample>(&m); imu && tracker_) tracker_->add_imu(*imu);
    if (const auto* gt = std::get_if<GroundTruthSample>(&m)) {
      gt_p_.t_ns.push_back(gt->t_ns);
      gt_p_.v.push_back(gt->p_WI);
      gt_R_WI_.push_back(gt->q_WI.toRotationMatrix());
    } else if (const auto* f = std::get_if<ForceSample>(&m)) {
      gt_f_W_.t_ns.push_back(f->t_ns);
      gt_f_W_.v.push_back(f->f_W_N);  // divided by the mass in summary()
    } else if (const auto* ms = std::get_if<MassSample>(&m)) {
      mass_t_.push_back(ms->t_ns);
      mass_kg_.push_back(ms->mass_kg);
    }
    pipeline_->push(m);
  }
}

void RunSession::push_decoded(const ImageFrame& frame, const std::vector<std::pair<int, cv::Mat>>& images,
                              double decode_ms, double decode_cpu_ms) {
  ++frames_;
  decode_ms_.push_back(decode_ms);
  decode_cpu_ms_ += decode_cpu_ms;
  cv::Mat left, right;
  bool ok = true;
  std::size_t k = 0;
  for (const auto& ref : frame.images) {
    if (ref.cam_id > 1) continue;
    if (k >= images.size() || images[k].first != ref.cam_id)
      throw std::logic_error(ref.path + ": decoded images do not match the frame's image list");
    const cv::Mat& g = images[k++].second;
    const CameraCalib& cam = cfg_.cameras.at(std::min<std::size_t>(ref.cam_id, cfg_.cameras.size() - 1));
    if (g.empty()) {
      ++images_unreadable_;
      warn_image(ref.path + ": unreadable image, frame skipped");
      ok = false;
    } else if (g.cols != cam.width || g.rows != cam.height) {
      ++images_wrong_size_;
      warn_image(fmt::format("{}: image is {}x{}, calibration says {}x{}; frame skipped", ref.path, g.cols, g.rows,
                             cam.width, cam.height));
      ok = false;
    }
    (ref.cam_id == 0 ? left : right) = g;
  }
  if (ok && !left.empty()) track(frame.t_ns, left, right);
}

void RunSession::add_unused_decode_cpu_ms(double ms) { decode_cpu_ms_ += ms; }

void RunSession::push_images(TimeNs t_ns, const cv::Mat& left, const cv::Mat& right) {
  ++frames_;
  bool ok = true;
  for (int cam_id = 0; cam_id < 2; ++cam_id) {
    const cv::Mat& g = cam_id == 0 ? left : right;
    if (g.empty()) continue;
    const CameraCalib& cam = cfg_.cameras.at(std::min<std::size_t>(cam_id, cfg_.cameras.size() - 1));
    if (g.type() != CV_8UC1) {
      ++images_unreadable_;
      warn_image(fmt::format("camera {} image at {} ns is not 8-bit mono; frame skipped", cam_id, t_ns));
      ok = false;
    } else if (g.cols != cam.width || g.rows != cam.height) {
      ++images_wrong_size_;
      warn_image(fmt::format("camera {} image at {} ns: image is {}x{}, calibration says {}x{}; frame skipped", cam_id,
                             t_ns, g.cols, g.rows, cam.width, cam.height));
      ok = false;
    }
  }
  if (ok && !left.empty()) track(t_ns, left, right);
}

void RunSession::warn_image(const std::string& msg) {
  if (++image_warnings_ <= 10) spdlog::warn("{}", msg);
  if (image_warnings_ == 10) spdlog::warn("further warnings of this kind are only counted (see summary.json)");
}

void RunSession::track(TimeNs t_ns, const cv::Mat& left, cv::Mat right) {
  if (!tracker_) return;
  if (tracker_->params().stereo == false || cfg_.cameras.size() < 2) right = cv::Mat();
  const auto t_track = Clock::now();
  const double cpu_track = thread_cpu_ms();
  FeatureFrame ff = tracker_->process(t_ns, left, right);
  tracking_ms_[t_ns] = ms_since(t_track);
  tracking_cpu_ms_.push_back(thread_cpu_ms() - cpu_track);
  pipeline_->push(Measurement{std::move(ff)});
}

void RunSession::finish() { pipeline_->finish(); }

void RunSession::close_outputs() {
  if (outputs_) outputs_->close();
}

nlohmann::json RunSession::summary() const {
  nlohmann::json s;
  s["mode"] = to_string(cfg_.estimator.mode);
  s["mode_source"] = mode_source_;
  s["init"] = to_string(cfg_.estimator.init_mode);
  s["features"] = opt_.features == FeatureSource::kFeat0 ? "feat0" : "images";
  s["status"] = to_string(pipeline_->status());
  s["status_message"] = pipeline_->status_message();
  PipelineCounters c = past_counters_;
  add_counters(c, pipeline_->counters());
  s["counts"] = {{"estimates", estimates_},
                 {"camera_frames", frames_},
                 {"feature_frames", feature_frames_},
                 {"images_unreadable", images_unreadable_},
                 {"images_wrong_size", images_wrong_size_},
                 {"frames_skipped_bad_image", images_unreadable_ + images_wrong_size_},
                 {"imu_samples", c.imu_samples},
                 {"accel_updates", c.accel_updates},
                 {"accel_rejected", c.accel_rejected},
                 {"accel_used_in_jumps", c.accel_used_in_jumps},
                 {"force_jumps", c.force_jumps},
                 {"rotor_gap_samples", c.rotor_gap_samples},
                 {"imu_gaps", c.imu_gaps},
                 {"frames_processed", c.frames},
                 {"frames_skipped_by_filter", c.frames_skipped},
                 {"visual_updates", c.visual_updates},
                 {"features_used", c.features_used},
                 {"features_rejected", c.features_rejected}};
  if (restarts_ > 0) s["counts"]["estimator_restarts"] = restarts_;
  s["accel"] = accel_report(c);
  s["timing"] = stage_times_.to_json();  // frontend + estimator stages; excludes image decoding
  s["timing"]["image_decoding"] = stage_stats(decode_ms_);
  s["peak_memory_mib"] = peak_memory_mib();
  // CPU-time view (robust to other processes on a shared machine); the caller adds the
  // CPU real-time factor, which needs the data duration.
  const double cpu_s = process_cpu_s() - cpu_start_s_;
  s["cpu"]["process_cpu_s"] = cpu_s;
  s["cpu"]["image_decoding_cpu_s"] = decode_cpu_ms_ * 1e-3;
  s["cpu"]["tracking_cpu"] = stage_stats(tracking_cpu_ms_);
  s["cpu"]["mean_cpu_ms_per_frame_excluding_decoding"] =
      c.frames > 0 ? (cpu_s * 1e3 - decode_cpu_ms_) / static_cast<double>(c.frames) : 0.0;
  s["config"] = describe(cfg_);
  s["config_sources"] = cfg_.sources;

  // Metrics against ground truth, with the association and alignment of vid_eval.
  std::optional<AteResult> ate;
  if (!gt_p_.t_ns.empty()) ate = ate_posyaw(est_p_, gt_p_);
  if (ate) {
    s["ate_posyaw_m"] = ate->rmse_m;
    s["ate_pairs"] = ate->pairs;
  }
  const auto& truth_vehicle = calib_.vehicle;
  if (dynamics() && !gt_f_W_.t_ns.empty() && (!mass_t_.empty() || truth_vehicle)) {
    Vec3Series gt_f = gt_f_W_;
    for (std::size_t i = 0; i < gt_f.t_ns.size(); ++i) {
      const double m = mass_t_.empty() ? truth_vehicle->mass_kg : mass_at(mass_t_, mass_kg_, gt_f.t_ns[i]);
      gt_f.v[i] /= m;
    }
    // The estimator's world has its own heading (yaw is unobservable): the world-frame figure
    // is taken after rotating the estimate by the ATE's alignment, never without one.
    std::size_t pairs = 0;
    if (!ate) {
      s["force_rmse_world_note"] = "no ground-truth poses to align the estimator's world frame: world-frame force not scored";
    } else if (auto rmse = force_rmse(rotate_about_z(est_f_W_, ate->yaw_rad), gt_f, &pairs)) {
      s["force_rmse_world_mps2"] = *rmse;
      s["force_pairs"] = pairs;
      s["force_alignment"] = {{"mode", "posyaw"}, {"yaw_deg", ate->yaw_rad * 180.0 / M_PI}};
    }
    if (!gt_R_WI_.empty()) {
      if (auto rmse = force_rmse(est_f_I_, world_to_body(gt_f, gt_p_.t_ns, gt_R_WI_)))
        s["force_rmse_body_mps2"] = *rmse;
    }
  }
  return s;
}

// ---------------------------------------------------------------------------------------------
// vid_run over a dataset folder

RunResult run(const RunOptions& opt, const std::atomic<bool>& stop) {
  const auto wall_start = Clock::now();
  fs::create_directories(opt.out_dir);

  // Probe which streams exist, then open the reader with exactly the streams needed.
  SessionOptions so;
  bool has_images = false, has_feat = false;
  {
    io::DatasetReader probe(opt.dataset);
    has_images = probe.has_stream("cam0");
    has_feat = probe.has_stream("feat0");
    so.has_rotor = probe.has_stream("rotor0");
    so.has_thrust = probe.has_stream("thrust0");
  }
  FeatureSource source = opt.features;
  if (source == FeatureSource::kAuto) source = has_images ? FeatureSource::kImages : FeatureSource::kFeat0;
  if (source == FeatureSource::kImages && !has_images)
    throw std::runtime_error(opt.dataset.string() + ": --features images, but the dataset has no cam0/data.csv");
  if (source == FeatureSource::kFeat0 && !has_feat)
    throw std::runtime_error(opt.dataset.string() + ": the dataset has neither cam0/data.csv images nor feat0/data.csv");

  io::ReaderOptions ro;
  ro.skip_missing_images = true;  // a missing image skips its frame (counted), as an unreadable one does
  ro.read_images = source == FeatureSource::kImages;
  ro.read_features = source == FeatureSource::kFeat0;
  io::DatasetReader reader(opt.dataset, ro);
  so.out_dir = opt.out_dir;
  so.config = opt.config;
  so.mode = opt.mode;
  so.init = opt.init;
  so.features = source;
  so.context = opt.dataset.string();
  RunSession session(so, reader.calibration());

  // Decode-ahead: a reader thread and opt.decode_threads decoders fill a queue a few camera
  // frames ahead while this thread runs frontend + estimator; the session gets the same
  // measurements in the same order as with inline decoding. Started after the session so that
  // all decoding falls inside the session's CPU-time window.
  app::PrefetchOptions po;
  po.start_s = opt.start_s;
  po.end_s = opt.end_s;
  po.decode_threads = std::max(0, opt.decode_threads);
  po.max_frames = static_cast<std::size_t>(std::max(4, 2 * po.decode_threads));
  po.capacity = 1024;  // IMU / rotor / truth rows between the frames ahead
  po.background_nice = 5;  // short of cores, frontend + estimator run first (per-frame times)
  app::Prefetcher prefetch(reader, po);

  // Progress over data time.
  std::optional<TimeNs> t_last_data = last_timestamp(reader.mav0() / "imu0" / "data.csv");
  std::optional<TimeNs> t0;
  TimeNs t_first_used = 0, t_last_used = 0;
  std::unique_ptr<app::ProgressBar> bar;
  bool interrupted = false, diverged = false;
  double decode_cpu_pushed_ms = 0.0;

  while (auto p = prefetch.next()) {
    if (stop.load()) {
      interrupted = true;
      break;
    }
    const TimeNs t = stamp_of(p->m);
    if (!t0) {
      t0 = p->t0;
      const TimeNs t_start = *t0 + static_cast<TimeNs>(opt.start_s * 1e9);
      const TimeNs t_end = opt.end_s >= 0.0 ? *t0 + static_cast<TimeNs>(opt.end_s * 1e9) : INT64_MAX;
      const double total_s = t_last_data ? ns_to_s(std::min(*t_last_data, t_end) - t_start) : 1.0;
      if (opt.progress) bar = std::make_unique<app::ProgressBar>("vid_run", total_s);
      t_first_used = t_start;
    }
    t_last_used = t;
    if (const auto* img = std::get_if<ImageFrame>(&p->m)) {
      session.push_decoded(*img, p->images, p->decode_ms, p->decode_cpu_ms);
      decode_cpu_pushed_ms += p->decode_cpu_ms;
    } else {
      session.push(p->m);
    }
    if (session.status() == FilterStatus::kDiverged) {
      diverged = true;
      spdlog::error("estimator diverged at t = {:.3f} s: {}", ns_to_s(t - *t0), session.status_message());
      break;
    }
    if (bar) {
      const double elapsed = std::chrono::duration<double>(Clock::now() - wall_start).count();
      const double data_s = ns_to_s(t - t_first_used);
      const long frames = session.camera_frames() + session.feature_frames();
      bar->update(data_s, fmt::format("{:.0f} frames/s, {:.1f}x real time", frames / std::max(elapsed, 1e-3),
                                      data_s / std::max(elapsed, 1e-3)));
    }
  }
  // Stop and join the decoders before the CPU totals are read; frames decoded ahead but never
  // used (interrupted run) still count as decoding, not as frontend + estimator time.
  prefetch.stop();
  const app::PrefetchStats prefetch_stats = prefetch.stats();
  session.add_unused_decode_cpu_ms(std::max(0.0, prefetch_stats.decode_cpu_ms - decode_cpu_pushed_ms));
  if (!interrupted && !diverged) session.finish();
  if (session.status() == FilterStatus::kDiverged) diverged = true;
  session.close_outputs();
  if (bar) bar->finish();

  const double wall_s = std::chrono::duration<double>(Clock::now() - wall_start).count();
  const double data_s = ns_to_s(t_last_used - t_first_used);
  nlohmann::json s = session.summary();
  s["dataset"] = fs::absolute(opt.dataset).string();
  if (interrupted) s["status"] = "interrupted";
  else if (diverged) s["status"] = "diverged";
  std::size_t images_missing = 0;
  for (const auto& st : reader.stats())
    if (st.name.rfind("cam", 0) == 0) images_missing += st.dropped;
  s["counts"]["images_missing"] = images_missing;
  s["decode_ahead"] = {{"decode_threads", po.decode_threads},
                       {"frames_ahead", po.decode_threads > 0 ? po.max_frames : 0},
                       {"frames_decoded", prefetch_stats.frames_decoded},
                       {"main_thread_wait_s", prefetch_stats.consumer_wait_ms * 1e-3}};
  s["data_duration_s"] = data_s;
  s["wall_time_s"] = wall_s;
  s["real_time_factor"] = wall_s > 0.0 ? data_s / wall_s : 0.0;
  const double cpu_s = s["cpu"]["process_cpu_s"].get<double>();
  s["cpu"]["real_time_factor_cpu"] = cpu_s > 0.0 ? data_s / cpu_s : 0.0;
  write_summary(opt.out_dir, s);

  const long frames = session.camera_frames() + session.feature_frames();
  spdlog::info("{}: {} estimates, {} frames, {:.1f} s of data in {:.1f} s ({:.1f}x real time), status {}",
               opt.out_dir.string(), session.estimates(), frames, data_s, wall_s, wall_s > 0 ? data_s / wall_s : 0.0,
               s["status"].get<std::string>());
  if (session.status() == FilterStatus::kWaitingForInit)
    spdlog::warn("the estimator never initialized ({}); for a hovering start with a noisy IMU raise init_accel_std_max "
                 "(see config/sim/estimator.yaml) or use --init groundtruth",
                 session.status_message());
  if (s.contains("ate_posyaw_m")) spdlog::info("ATE (posyaw) {:.4f} m", s["ate_posyaw_m"].get<double>());
  if (s.contains("force_rmse_world_mps2"))
    spdlog::info("force RMSE (world, posyaw-aligned: yaw {:.1f} deg) {:.4f} m/s^2",
                 s["force_alignment"]["yaw_deg"].get<double>(), s["force_rmse_world_mps2"].get<double>());
  if (s.contains("force_rmse_body_mps2"))
    spdlog::info("force RMSE (body) {:.4f} m/s^2", s["force_rmse_body_mps2"].get<double>());
  if (interrupted) return RunResult::kInterrupted;
  if (diverged) return RunResult::kDiverged;
  return RunResult::kOk;
}

}  // namespace vid::runner
