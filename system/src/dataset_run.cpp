#include "vid_system/dataset_run.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <exception>
#include <memory>
#include <stdexcept>
#include <vector>

#include "io/dataset_reader.h"
#include "vid_system/data_window.h"
#include "vid_system/image_depth.h"
#include "vid_system/input_checks.h"
#include "vid_system/prefetch.h"
#include "vid_system/progress.h"
#include "vid_system/system.h"
#include "vid_system/usage_error.h"

namespace vid::system {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {
// A divergence within this long after a re-initialization is the same fault: the run stops.
constexpr double kPersistentFaultS = 10.0;

// A run that never initialized, or that used no camera frame, has no estimate worth an exit 0
// (its summary.json may still show a perfect-looking ATE over a few IMU-only estimates).
RunResult honest_end(const System& session, const nlohmann::json& s) {
  if (session.status() == FilterStatus::kWaitingForInit) {
    spdlog::error("the estimator never initialized: {} (README \"Initialization\")", session.status_message());
    return RunResult::kNotInitialized;
  }
  const auto& c = s["counts"];
  const long frames = c["camera_frames"].get<long>() + c["feature_frames"].get<long>();
  if (frames > 0 && c["frames_processed"].get<long>() == 0) {
    spdlog::error("the estimator used none of the {} camera frames ({} skipped by the filter: before its "
                  "initialization or behind its state's time)",
                  frames, c["frames_skipped_by_filter"].get<long>());
    return RunResult::kNoFrameUsed;
  }
  return RunResult::kOk;
}
}  // namespace

RunResult run_dataset(const RunOptions& opt, const std::atomic<bool>& stop) {
  const auto wall_start = Clock::now();
  fs::create_directories(opt.out_dir);

  // Probe which streams exist, then open the reader with exactly the streams needed.
  SystemOptions so;
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
  ro.list_missing_images = true;  // the session skips a frame with a missing image, as with an unreadable one
  ro.read_images = source == FeatureSource::kImages;
  ro.read_features = source == FeatureSource::kFeat0;
  ro.max_gap_periods = opt.max_gap_periods;
  ro.gaps_as_warnings = opt.allow_gaps;
  ro.warn = [](const std::string& w) { spdlog::warn("{}", w); };
  check_dataset_window(opt.dataset, ro, opt.start_s, opt.end_s);
  io::DatasetReader reader(opt.dataset, ro);
  so.out_dir = opt.out_dir;
  so.config = opt.config;
  so.mode = opt.mode;
  so.init = opt.init;
  so.features = source;
  so.context = opt.dataset.string();
  so.write_tracks = opt.write_tracks;
  SystemParams sp = make_system_params(so, reader.calibration());
  // The estimator discretizes the IMU noise at its configured rate: a wrong rate is an error.
  const fs::path imu_csv = reader.mav0() / "imu0" / "data.csv";
  check_imu_extrinsic(sp.config, reader.mav0() / "imu0" / "sensor.yaml");
  if (const auto hz = median_rate_hz(imu_csv))
    check_imu_rate(sp.config, *hz, reader.mav0() / "imu0" / "sensor.yaml", imu_csv.string());
  if (opt.smooth_lag_s) sp.config.estimator.smoother_lag_s = *opt.smooth_lag_s;
  System session(std::move(sp));
  if (opt.smooth_lag_s && !session.dynamics())
    throw UsageError("--smooth: smoothing estimates the force, which needs dynamics mode (rotor0/ or thrust0/; "
                     "not --mode imu)");
  session.frame_faults().set_strict(opt.strict);

  // Decode-ahead: a reader thread and opt.decode_threads decoders fill a queue a few camera
  // frames ahead while this thread runs frontend + estimator; the session gets the same
  // measurements in the same order as with inline decoding. Started after the session so that
  // all decoding falls inside the session's CPU-time window.
  PrefetchOptions po;
  po.start_s = opt.start_s;
  po.end_s = opt.end_s.value_or(-1.0);
  po.decode_threads = std::max(0, opt.decode_threads);
  po.max_frames = static_cast<std::size_t>(std::max(4, 2 * po.decode_threads));
  po.capacity = 1024;  // IMU / rotor / truth rows between the frames ahead
  po.background_nice = 5;  // short of cores, frontend + estimator run first (per-frame times)
  // 16-bit images: one scale per camera for the whole run, from samples of the stream.
  const CameraDepths depths = source == FeatureSource::kImages
                                  ? camera_bit_depths(reader.mav0(), session.params().config.frontend.image_bit_depth)
                                  : CameraDepths{};
  po.image_bits = {depths.bits(0), depths.bits(1)};
  Prefetcher prefetch(reader, po);

  // Progress over data time.
  std::optional<TimeNs> t_last_data = last_timestamp(reader.mav0() / "imu0" / "data.csv");
  std::optional<TimeNs> t0;
  TimeNs t_first_used = 0, t_last_used = 0;
  std::unique_ptr<ProgressBar> bar;
  bool interrupted = false, diverged = false;
  nlohmann::json divergences = nlohmann::json::array();  // each, recovered or not
  std::optional<TimeNs> last_restart;
  double decode_cpu_pushed_ms = 0.0;

  // A data error mid-run (a CSV row, a bad frame under --strict) still closes the outputs and
  // writes summary.json (status "error") before it ends the program.
  std::exception_ptr error;
  std::string error_message;
  try {
    while (auto p = prefetch.next()) {
      if (stop.load()) {
        interrupted = true;
        break;
      }
      const TimeNs t = stamp_of(p->m);
      if (!t0) {
        t0 = p->t0;
        const TimeNs t_start = *t0 + static_cast<TimeNs>(opt.start_s * 1e9);
        const TimeNs t_end = opt.end_s ? *t0 + static_cast<TimeNs>(*opt.end_s * 1e9) : INT64_MAX;
        const double total_s = t_last_data ? ns_to_s(std::min(*t_last_data, t_end) - t_start) : 1.0;
        if (opt.progress) bar = std::make_unique<ProgressBar>("vid_run", total_s);
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
        divergences.push_back({{"t_ns", t}, {"message", session.status_message()}});
        // A fault that outlives a re-initialization (a wrong calibration, a sensor that stays
        // broken) diverges again soon: then the run stops as without --on-divergence reinit.
        const bool again = last_restart && t - *last_restart < seconds_to_ns(kPersistentFaultS);
        if (!opt.reinit_on_divergence || again) {
          diverged = true;
          spdlog::error("estimator diverged at t = {:.3f} s: {}{}", ns_to_s(t - *t0), session.status_message(),
                        again ? fmt::format(" (again, {:.1f} s after re-initializing: the fault persists)",
                                            ns_to_s(t - *last_restart))
                              : "");
          break;
        }
        spdlog::warn("estimator diverged at t = {:.3f} s: {}; re-initializing from the data (--on-divergence reinit)",
                     ns_to_s(t - *t0), session.status_message());
        session.restart();
        last_restart = t;
      }
      if (bar) {
        const double elapsed = std::chrono::duration<double>(Clock::now() - wall_start).count();
        const double data_s = ns_to_s(t - t_first_used);
        const long frames = session.camera_frames() + session.feature_frames();
        bar->update(data_s, fmt::format("{:.0f} frames/s, {:.1f}x real time", frames / std::max(elapsed, 1e-3),
                                        data_s / std::max(elapsed, 1e-3)));
      }
    }
  } catch (const std::exception& e) {
    error = std::current_exception();
    error_message = e.what();
  }
  // Stop and join the decoders before the CPU totals are read; frames decoded ahead but never
  // used (interrupted run) still count as decoding, not as frontend + estimator time.
  prefetch.stop();
  const PrefetchStats prefetch_stats = prefetch.stats();
  session.add_unused_decode_cpu_ms(std::max(0.0, prefetch_stats.decode_cpu_ms - decode_cpu_pushed_ms));
  if (!interrupted && !diverged && !error) session.finish();
  if (session.status() == FilterStatus::kDiverged) diverged = true;
  session.close_outputs();
  if (bar) bar->finish();

  const double wall_s = std::chrono::duration<double>(Clock::now() - wall_start).count();
  const double data_s = ns_to_s(t_last_used - t_first_used);
  nlohmann::json s = session.summary();
  s["dataset"] = fs::absolute(opt.dataset).string();
  if (source == FeatureSource::kImages)
    for (int cam = 0; cam < 2; ++cam)
      s["image_bit_depth"]["cam" + std::to_string(cam)] = {{"bits", depths.cams[cam].bits}, {"how", depths.cams[cam].how}};
  if (error) {
    s["status"] = "error";
    s["status_message"] = error_message;
  } else if (interrupted) {
    s["status"] = "interrupted";
  } else if (diverged) {
    s["status"] = "diverged";
  }
  if (!divergences.empty()) s["divergences"] = divergences;
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
  for (const auto& w : s["noise_fit"]["warnings"]) spdlog::warn("noise fit: {}", w.get<std::string>());
  for (const auto& w : s["warnings"]) spdlog::warn("{}", w.get<std::string>());
  if (error) std::rethrow_exception(error);

  const long frames = session.camera_frames() + session.feature_frames();
  spdlog::info("{}: {} estimates, {} frames, {:.1f} s of data in {:.1f} s ({:.1f}x real time), status {}",
               opt.out_dir.string(), session.estimates(), frames, data_s, wall_s, wall_s > 0 ? data_s / wall_s : 0.0,
               s["status"].get<std::string>());
  if (s.contains("ate_posyaw_m")) spdlog::info("ATE (posyaw) {:.4f} m", s["ate_posyaw_m"].get<double>());
  if (s.contains("force_rmse_world_mps2"))
    spdlog::info("force RMSE (world, posyaw-aligned: yaw {:.1f} deg) {:.4f} m/s^2",
                 s["force_alignment"]["yaw_deg"].get<double>(), s["force_rmse_world_mps2"].get<double>());
  if (s.contains("force_rmse_body_mps2"))
    spdlog::info("force RMSE (body) {:.4f} m/s^2", s["force_rmse_body_mps2"].get<double>());
  if (interrupted) return RunResult::kInterrupted;
  if (diverged) return RunResult::kDiverged;
  return honest_end(session, s);
}

}  // namespace vid::system
