#include "runner/runner.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <fstream>
#include <map>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "app/progress.h"
#include "frontend/camera_model.h"
#include "frontend/klt_tracker.h"
#include "io/dataset_reader.h"
#include "runner/run_config.h"
#include "runner/run_metrics.h"
#include "runner/run_outputs.h"
#include "runner/run_summary.h"
#include "vio_core/pipeline.h"

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

/// Decode one image as 8-bit gray; empty Mat when unreadable.
cv::Mat decode_gray8(const std::string& path) {
  cv::Mat img = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (img.empty()) return img;
  if (img.depth() == CV_16U) img.convertTo(img, CV_8U, 1.0 / 256.0);
  if (img.depth() != CV_8U) return {};
  if (img.channels() == 3) cv::cvtColor(img, img, cv::COLOR_BGR2GRAY);
  if (img.channels() == 4) cv::cvtColor(img, img, cv::COLOR_BGRA2GRAY);
  return img;
}

EstimateRow to_row(const EstimateOutput& e) {
  EstimateRow r;
  r.t_ns = e.t_ns;
  r.q_WI = e.x.q_WI;
  r.p_WI = e.x.p_WI;
  r.v_WI = e.x.v_WI;
  r.b_g = e.x.b_g;
  r.b_a = e.x.b_a;
  r.F_ext_I = e.x.F_ext_I;
  const int n = std::min<int>(18, static_cast<int>(e.sigma.size()));
  r.sigma.head(n) = e.sigma.head(n);
  return r;
}

/// Rate-limited warnings: the first few verbatim, then only counted.
class Warner {
 public:
  void warn(const std::string& msg) {
    if (++count_ <= 10) spdlog::warn("{}", msg);
    if (count_ == 10) spdlog::warn("further warnings of this kind are only counted (see summary.json)");
  }

 private:
  int count_ = 0;
};

}  // namespace

RunResult run(const RunOptions& opt, const std::atomic<bool>& stop) {
  const auto wall_start = Clock::now();
  fs::create_directories(opt.out_dir);

  // Probe which streams exist, then open the reader with exactly the streams needed.
  bool has_images = false, has_feat = false, has_rotor = false, has_thrust = false;
  {
    io::DatasetReader probe(opt.dataset);
    has_images = probe.has_stream("cam0");
    has_feat = probe.has_stream("feat0");
    has_rotor = probe.has_stream("rotor0");
    has_thrust = probe.has_stream("thrust0");
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
  RunConfig cfg = resolve_run_config(opt.config, reader.calibration());

  const bool thrust_data = has_rotor || has_thrust;
  // Mode: the flag, else the preset's explicit `mode:`, else dynamics when thrust information exists.
  std::string mode_source = "flag --mode";
  if (opt.mode) {
    cfg.estimator.mode = *opt.mode;
  } else if (cfg.preset_mode) {
    cfg.estimator.mode = *cfg.preset_mode;
    mode_source = cfg.sources.at("estimator");
  } else {
    cfg.estimator.mode = thrust_data ? PropagationMode::kDynamics : PropagationMode::kImu;
    mode_source = thrust_data ? "auto (rotor/thrust data present)" : "auto (no rotor/thrust data)";
  }
  if (opt.init) cfg.estimator.init_mode = *opt.init;
  const bool dynamics = cfg.estimator.mode == PropagationMode::kDynamics;
  if (dynamics && !thrust_data)
    throw std::runtime_error(opt.dataset.string() +
                             ": dynamics mode needs rotor speeds (rotor0/) or thrust (thrust0/), and the dataset has "
                             "neither; run with --mode imu");
  if (dynamics && (!cfg.vehicle || (has_rotor && cfg.vehicle->rotor_thrust_coefficients.empty())))
    throw std::runtime_error(opt.dataset.string() +
                             ": dynamics mode needs vehicle.yaml (mass_kg, rotor_thrust_coefficients) in the dataset or "
                             "the --config preset");
  if (cfg.cameras.empty())
    throw std::runtime_error(opt.dataset.string() + ": no camera calibration (camN/sensor.yaml or --config camchain.yaml)");

  PipelineConfig pcfg;
  pcfg.params = cfg.estimator;
  pcfg.vehicle = cfg.vehicle.value_or(VehicleParams{});
  pcfg.cameras = cfg.cameras;
  Pipeline pipeline(pcfg);

  std::unique_ptr<KltTracker> tracker;
  std::vector<std::unique_ptr<CameraModel>> models;  // feat0: undistortion of the given pixels
  if (source == FeatureSource::kFeat0) {
    for (const auto& cam : cfg.cameras) models.push_back(CameraModel::create(cam));
  } else {
    std::vector<CameraCalib> tracked(cfg.cameras.begin(), cfg.cameras.begin() + std::min<std::size_t>(2, cfg.cameras.size()));
    if (!cfg.frontend.stereo) tracked.resize(1);
    tracker = std::make_unique<KltTracker>(cfg.frontend, tracked);
  }

  RunOutputs outputs(opt.out_dir, dynamics);
  StageTimes stage_times;
  std::map<TimeNs, double> tracking_ms;  // frame time -> tracking time, until the pipeline reports the frame
  Vec3Series est_p, est_f_W, gt_p, gt_f_W;
  std::vector<TimeNs> mass_t;
  std::vector<double> mass_kg;
  long estimates = 0;

  pipeline.set_estimate_callback([&](const EstimateOutput& e) {
    const EstimateRow row = to_row(e);
    outputs.write_estimate(row);
    ++estimates;
    est_p.t_ns.push_back(row.t_ns);
    est_p.v.push_back(row.p_WI);
    if (dynamics) {
      est_f_W.t_ns.push_back(row.t_ns);
      est_f_W.v.push_back(row.q_WI.normalized() * row.F_ext_I);
    }
  });
  pipeline.set_frame_callback([&](const FrameTimings& ft) {
    TimingRow row;
    row.t_ns = ft.t_ns;
    if (auto it = tracking_ms.find(ft.t_ns); it != tracking_ms.end()) {
      row.tracking_ms = it->second;
      tracking_ms.erase(tracking_ms.begin(), std::next(it));
    }
    row.propagation_ms = ft.propagation_ms;
    row.accel_update_ms = ft.accel_update_ms;
    row.msckf_update_ms = ft.msckf_update_ms;
    row.marginalization_ms = ft.marginalization_ms;
    row.total_ms = row.tracking_ms + row.propagation_ms + row.accel_update_ms + row.msckf_update_ms +
                   row.marginalization_ms;
    outputs.write_timing(row);
    stage_times.add(row);
  });

  // Progress over data time.
  std::optional<TimeNs> t_last_data = last_timestamp(reader.mav0() / "imu0" / "data.csv");
  std::optional<TimeNs> t0;
  TimeNs t_start = 0, t_end = INT64_MAX, t_first_used = 0, t_last_used = 0;
  std::unique_ptr<app::ProgressBar> bar;
  long frames = 0, images_unreadable = 0, images_wrong_size = 0, feature_frames = 0;
  Warner image_warnings;
  std::vector<double> decode_ms;  // PNG decoding per camera frame (not part of the stage times)
  std::vector<double> tracking_cpu_ms;  // thread CPU time of the tracker per frame
  double decode_cpu_ms = 0.0;
  const double cpu_start_s = process_cpu_s();
  bool interrupted = false, diverged = false;

  while (auto m = reader.next()) {
    if (stop.load()) {
      interrupted = true;
      break;
    }
    const TimeNs t = stamp_of(*m);
    if (!t0) {
      t0 = t;
      t_start = t + static_cast<TimeNs>(opt.start_s * 1e9);
      if (opt.end_s >= 0.0) t_end = t + static_cast<TimeNs>(opt.end_s * 1e9);
      const double total_s = t_last_data ? ns_to_s(std::min(*t_last_data, t_end) - t_start) : 1.0;
      if (opt.progress) bar = std::make_unique<app::ProgressBar>("vid_run", total_s);
      t_first_used = t_start;
    }
    if (t < t_start) continue;
    if (t > t_end) break;
    t_last_used = t;

    if (const auto* img = std::get_if<ImageFrame>(&*m)) {
      ++frames;
      cv::Mat left, right;
      bool ok = true;
      const auto t_decode = Clock::now();
      const double cpu_decode = thread_cpu_ms();
      for (const auto& ref : img->images) {
        if (ref.cam_id > 1) continue;
        cv::Mat g = decode_gray8(ref.path);
        const CameraCalib& cam = cfg.cameras.at(std::min<std::size_t>(ref.cam_id, cfg.cameras.size() - 1));
        if (g.empty()) {
          ++images_unreadable;
          image_warnings.warn(ref.path + ": unreadable image, frame skipped");
          ok = false;
        } else if (g.cols != cam.width || g.rows != cam.height) {
          ++images_wrong_size;
          image_warnings.warn(fmt::format("{}: image is {}x{}, calibration says {}x{}; frame skipped", ref.path, g.cols,
                                          g.rows, cam.width, cam.height));
          ok = false;
        }
        (ref.cam_id == 0 ? left : right) = g;
      }
      decode_ms.push_back(ms_since(t_decode));
      decode_cpu_ms += thread_cpu_ms() - cpu_decode;
      if (!ok || left.empty()) continue;
      if (tracker->params().stereo == false || cfg.cameras.size() < 2) right = cv::Mat();
      const auto t_track = Clock::now();
      const double cpu_track = thread_cpu_ms();
      FeatureFrame ff = tracker->process(img->t_ns, left, right);
      tracking_ms[img->t_ns] = ms_since(t_track);
      tracking_cpu_ms.push_back(thread_cpu_ms() - cpu_track);
      pipeline.push(Measurement{std::move(ff)});
    } else if (auto* ff = std::get_if<FeatureFrame>(&*m)) {
      ++feature_frames;
      for (auto& o : ff->observations) {
        if (o.has_norm || o.cam_id < 0 || o.cam_id >= static_cast<int>(models.size())) continue;
        o.has_norm = models[static_cast<std::size_t>(o.cam_id)]->undistort(o.uv, &o.uv_norm);
      }
      pipeline.push(*m);
    } else {
      if (const auto* imu = std::get_if<ImuSample>(&*m); imu && tracker) tracker->add_imu(*imu);
      if (const auto* gt = std::get_if<GroundTruthSample>(&*m)) {
        gt_p.t_ns.push_back(gt->t_ns);
        gt_p.v.push_back(gt->p_WI);
      } else if (const auto* f = std::get_if<ForceSample>(&*m)) {
        gt_f_W.t_ns.push_back(f->t_ns);
        gt_f_W.v.push_back(f->f_W_N);  // divided by the mass below
      } else if (const auto* ms = std::get_if<MassSample>(&*m)) {
        mass_t.push_back(ms->t_ns);
        mass_kg.push_back(ms->mass_kg);
      }
      pipeline.push(*m);
    }
    if (pipeline.status() == FilterStatus::kDiverged) {
      diverged = true;
      spdlog::error("estimator diverged at t = {:.3f} s: {}", ns_to_s(t - *t0), pipeline.status_message());
      break;
    }
    if (bar) {
      const double elapsed = std::chrono::duration<double>(Clock::now() - wall_start).count();
      const double data_s = ns_to_s(t - t_start);
      bar->update(data_s, fmt::format("{:.0f} frames/s, {:.1f}x real time", (frames + feature_frames) / std::max(elapsed, 1e-3),
                                      data_s / std::max(elapsed, 1e-3)));
    }
  }
  if (!interrupted && !diverged) pipeline.finish();
  if (pipeline.status() == FilterStatus::kDiverged) diverged = true;
  outputs.close();
  if (bar) bar->finish();

  const double wall_s = std::chrono::duration<double>(Clock::now() - wall_start).count();
  const double data_s = ns_to_s(t_last_used - t_first_used);
  nlohmann::json s;
  s["dataset"] = fs::absolute(opt.dataset).string();
  s["mode"] = to_string(cfg.estimator.mode);
  s["mode_source"] = mode_source;
  s["init"] = to_string(cfg.estimator.init_mode);
  s["features"] = source == FeatureSource::kImages ? "images" : "feat0";
  s["status"] = interrupted ? "interrupted" : (diverged ? "diverged" : to_string(pipeline.status()));
  s["status_message"] = pipeline.status_message();
  const PipelineCounters& c = pipeline.counters();
  s["counts"] = {{"estimates", estimates},
                 {"camera_frames", frames},
                 {"feature_frames", feature_frames},
                 {"images_unreadable", images_unreadable},
                 {"images_wrong_size", images_wrong_size},
                 {"frames_skipped_bad_image", images_unreadable + images_wrong_size},
                 {"imu_samples", c.imu_samples},
                 {"accel_updates", c.accel_updates},
                 {"accel_rejected", c.accel_rejected},
                 {"rotor_gap_samples", c.rotor_gap_samples},
                 {"imu_gaps", c.imu_gaps},
                 {"frames_processed", c.frames},
                 {"frames_skipped_by_filter", c.frames_skipped},
                 {"visual_updates", c.visual_updates},
                 {"features_used", c.features_used},
                 {"features_rejected", c.features_rejected}};
  std::size_t images_missing = 0;
  for (const auto& st : reader.stats())
    if (st.name.rfind("cam", 0) == 0) images_missing += st.dropped;
  s["counts"]["images_missing"] = images_missing;
  s["data_duration_s"] = data_s;
  s["wall_time_s"] = wall_s;
  s["real_time_factor"] = wall_s > 0.0 ? data_s / wall_s : 0.0;
  s["timing"] = stage_times.to_json();  // frontend + estimator stages; excludes image decoding
  s["timing"]["image_decoding"] = stage_stats(decode_ms);
  s["peak_memory_mib"] = peak_memory_mib();
  // CPU-time view of the same run (robust to other processes on a shared machine): the whole
  // run, its real-time factor on CPU time, tracking per frame, and everything but PNG decoding
  // per processed frame (mean; the estimator runs inside the reader loop, one thread).
  const double cpu_s = process_cpu_s() - cpu_start_s;
  s["cpu"]["process_cpu_s"] = cpu_s;
  s["cpu"]["real_time_factor_cpu"] = cpu_s > 0.0 ? data_s / cpu_s : 0.0;
  s["cpu"]["image_decoding_cpu_s"] = decode_cpu_ms * 1e-3;
  s["cpu"]["tracking_cpu"] = stage_stats(tracking_cpu_ms);
  s["cpu"]["mean_cpu_ms_per_frame_excluding_decoding"] =
      c.frames > 0 ? (cpu_s * 1e3 - decode_cpu_ms) / static_cast<double>(c.frames) : 0.0;
  s["config"] = describe(cfg);
  s["config_sources"] = cfg.sources;

  // Metrics against ground truth, with the association and alignment of vid_eval.
  if (!gt_p.t_ns.empty()) {
    if (auto ate = ate_posyaw(est_p, gt_p)) {
      s["ate_posyaw_m"] = ate->rmse_m;
      s["ate_pairs"] = ate->pairs;
    }
  }
  const auto& truth_vehicle = reader.calibration().vehicle;
  if (dynamics && !gt_f_W.t_ns.empty() && (!mass_t.empty() || truth_vehicle)) {
    for (std::size_t i = 0; i < gt_f_W.t_ns.size(); ++i) {
      const double m = mass_t.empty() ? truth_vehicle->mass_kg : mass_at(mass_t, mass_kg, gt_f_W.t_ns[i]);
      gt_f_W.v[i] /= m;
    }
    std::size_t pairs = 0;
    if (auto rmse = force_rmse(est_f_W, gt_f_W, &pairs)) {
      s["force_rmse_world_mps2"] = *rmse;
      s["force_pairs"] = pairs;
    }
  }
  write_summary(opt.out_dir, s);

  spdlog::info("{}: {} estimates, {} frames, {:.1f} s of data in {:.1f} s ({:.1f}x real time), status {}",
               opt.out_dir.string(), estimates, frames + feature_frames, data_s, wall_s,
               wall_s > 0 ? data_s / wall_s : 0.0, s["status"].get<std::string>());
  if (pipeline.status() == FilterStatus::kWaitingForInit)
    spdlog::warn("the estimator never initialized ({}); for a hovering start with a noisy IMU raise init_accel_std_max "
                 "(see config/sim/estimator.yaml) or use --init groundtruth",
                 pipeline.status_message());
  if (s.contains("ate_posyaw_m")) spdlog::info("ATE (posyaw) {:.4f} m", s["ate_posyaw_m"].get<double>());
  if (s.contains("force_rmse_world_mps2"))
    spdlog::info("force RMSE (world) {:.4f} m/s^2", s["force_rmse_world_mps2"].get<double>());
  if (interrupted) return RunResult::kInterrupted;
  if (diverged) return RunResult::kDiverged;
  return RunResult::kOk;
}

}  // namespace vid::runner
