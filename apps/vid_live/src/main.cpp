/// vid_live: estimate pose and external force from LCM sensor streams (docs/design.md §4, issue 9).
#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <optional>

#include <unistd.h>

#include "app/cli.h"
#include "app/run_main.h"
#include "app/view_launch.h"
#include "io/lcm/channels.h"
#include "live/lcm_input.h"
#include "live/lcm_loop.h"
#include "live/live_engine.h"
#include "live/sensor_files.h"

namespace {
std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop.store(true); }

/// A file removed when the run ends, however it ends.
struct TempFile {
  std::filesystem::path path;
  explicit TempFile(std::filesystem::path p) : path(std::move(p)) {}
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  ~TempFile() {
    std::error_code ec;
    std::filesystem::remove(path, ec);
  }
};
}  // namespace

int main(int argc, char** argv) {
  spdlog::set_default_logger(spdlog::stderr_color_mt("vid_live"));
  spdlog::set_pattern("%^vid_live: %l:%$ %v");
  return vid::app::run_main("vid_live", [&]() -> int {
    CLI::App app{"vid_live: estimate pose and external force from LCM sensor streams (IMU, cameras, rotor speeds)"};
    std::string url, publish_url, config, sensors, channels, out, mode, init, overload = "auto";
    double window_ms = 30.0, stall_s = 0.5, idle_s = 0.0, no_camera_s = 3.0;
    std::size_t max_frames = 4;
    bool thrust = false, quiet = false;
    app.add_option("--lcm-url", url, "LCM URL to read sensors from (memq://, udpm://..., file://LOG?speed=1)")
        ->required();
    app.add_option("--publish-url", publish_url,
                   "LCM URL to publish VID_STATE/VID_FORCE/VID_STATUS (and *_LAGGED) on (default: --lcm-url; for a file:// input: "
                   "none; file://OUT.log?mode=w writes an event log)");
    app.add_option("--sensors", sensors,
                   "sensor files laid out as a dataset folder (camN/sensor.yaml, imu0/, rotor0/, vehicle.yaml), "
                   "e.g. the replayed dataset");
    app.add_option("--config", config, "preset folder or its estimator.yaml (as vid_run --config)");
    app.add_option("--channels", channels, "YAML file of channel names (keys imu, cam0, cam1, rotors, thrust, "
                                           "state, force, status, state_lagged, force_lagged)");
    app.add_option("--out", out, "write vid_run's output files (trajectory_tum.txt, state.csv, ..., summary.json)");
    app.add_option("--mode", mode, "imu | dynamics (default: dynamics when a rotor sensor is configured)")
        ->check(CLI::IsMember({"imu", "dynamics"}));
    app.add_option("--init", init, "static (default: the config's init_mode)")->check(CLI::IsMember({"static"}));
    app.add_flag("--thrust", thrust, "read collective thrust (thrust_t) instead of rotor speeds");
    app.add_option("--reorder-window-ms", window_ms, "data time a message is held for late-comers [ms]")
        ->check(CLI::Range(0.0, 10000.0));
    app.add_option("--max-queued-frames", max_frames, "camera frames waiting for the estimator before the oldest "
                                                      "is dropped")
        ->check(CLI::Range(1, 1000));
    app.add_option("--overload", overload,
                   "auto | drop | block: when the queue is full drop the oldest frame, or make the reader wait "
                   "(auto: block for file:// logs with speed=0, drop otherwise)")
        ->check(CLI::IsMember({"auto", "drop", "block"}));
    app.add_option("--stall-s", stall_s, "no camera frame for this long (data time) counts as a camera stall [s]");
    app.add_option("--no-camera-s", no_camera_s,
                   "no camera frame at all in this much IMU data time [s] is a fault: health no_camera, and a run "
                   "without any frame ends with status no_camera, exit 5")
        ->check(CLI::PositiveNumber);
    app.add_option("--idle-timeout", idle_s, "live transports: stop after this long without messages [s] (0: never)");
    bool tracks = false;
    std::string rerun;
    app.add_flag("--tracks", tracks, "with --out: also write OUT/tracks.csv (the tracked features of every frame)");
    app.add_option("--rerun", rerun,
                   "with --out: at the end, log the run (trajectory, force, tracked features; images when --sensors "
                   "is a dataset folder) to this Rerun .rrd file with `vid-eval view` (implies --tracks); live: "
                   "run `vid-eval view --lcm URL --spawn` beside it")
        ->needs("--out");
    double lag_s = 0.0;
    app.add_option("--lag", lag_s,
                   "also publish the fixed-lag smoothed state and force of this lag [s] on VID_STATE_LAGGED / "
                   "VID_FORCE_LAGGED (dynamics mode; with --out also force_smoothed.csv, trajectory_smoothed_tum.txt)")
        ->check(CLI::PositiveNumber);
    bool strict = false;
    app.add_flag("--strict", strict,
                 "file:// input: bytes in the middle of the log that are not LCM events are an error (default: "
                 "read past them with one warning, counted in summary.json input.lcm_log)");
    app.add_flag("--quiet", quiet, "warnings only");
    if (const auto code = vid::app::parse_cli(app, argc, argv)) return *code;
    if (quiet) spdlog::set_level(spdlog::level::warn);
    vid::live::check_lcm_url(url, "--lcm-url", /*for_input=*/true);
    if (!publish_url.empty()) vid::live::check_lcm_url(publish_url, "--publish-url", /*for_input=*/false);
    // A log is walked before LCM reads it: not a log is an error now, a cut one after its last
    // whole event. Unreadable bytes between events (a damaged block) are skipped by LCM's
    // reader: said in one line, counted, or with --strict an error.
    std::optional<vid::live::LogScan> log_scan;
    std::string read_url = url;  // a damaged log is read through a copy without the damage
    std::optional<TempFile> repaired;
    if (vid::live::is_log_url(url)) {
      log_scan = vid::live::scan_lcm_log(vid::live::log_path(url));
      if (!log_scan->damaged.empty()) {
        const std::string line = vid::live::describe_damage(vid::live::log_path(url), *log_scan, strict);
        if (strict) throw std::runtime_error(line);
        spdlog::warn("{}", line);
        repaired.emplace(std::filesystem::temp_directory_path() /
                         fmt::format("vid_live_{}_undamaged.lcm", static_cast<long>(::getpid())));
        vid::live::write_without_damage(vid::live::log_path(url), *log_scan, repaired->path.string());
        read_url = vid::live::with_log_path(url, repaired->path.string());
      }
    }

    vid::live::LiveOptions opt;
    if (!sensors.empty()) {
      opt.calibration = vid::live::load_sensor_files(sensors);
      opt.imu_yaml = vid::live::sensor_root(sensors) / "imu0" / "sensor.yaml";
    }
    if (!channels.empty()) opt.channels = vid::lcm_io::load_channels(channels);
    if (!config.empty()) opt.session.config = config;
    if (!out.empty()) opt.session.out_dir = out;
    opt.session.write_tracks = tracks || !rerun.empty();
    if (!mode.empty()) opt.session.mode = vid::mode_from_string(mode);
    if (!init.empty()) opt.session.init = vid::init_mode_from_string(init);
    opt.session.has_rotor = !thrust && opt.calibration.rotor.has_value();
    opt.session.has_thrust = thrust;
    opt.session.context = url;
    opt.reorder_window_ns = static_cast<vid::TimeNs>(window_ms * 1e6);
    opt.max_queued_frames = max_frames;
    opt.block_when_full = overload == "block" || (overload == "auto" && vid::live::is_fast_log_url(url));
    opt.stall_s = stall_s;
    opt.no_camera_s = no_camera_s;
    opt.source_url = url;
    opt.lag_s = lag_s;
    if (opt.session.out_dir) std::filesystem::create_directories(*opt.session.out_dir);

    lcm::LCM input(read_url);
    if (!input.good()) throw std::runtime_error(url + ": LCM cannot open this URL");
    if (publish_url.empty() && !vid::live::is_log_url(url)) publish_url = url;
    // The worker publishes while this thread handles input: a separate LCM instance for output
    // (same transport), except memq://, whose queue lives inside one instance.
    std::unique_ptr<lcm::LCM> output;
    lcm::LCM* publisher = nullptr;
    if (publish_url == url && url.rfind("memq://", 0) == 0) {
      publisher = &input;
    } else if (!publish_url.empty()) {
      output = std::make_unique<lcm::LCM>(publish_url);
      if (!output->good()) throw std::runtime_error(publish_url + ": LCM cannot open this URL for publishing");
      publisher = output.get();
    }

    vid::live::LiveEngine engine(opt, publisher);
    if (lag_s > 0.0 && !engine.dynamics())
      throw vid::system::UsageError("--lag: smoothing estimates the force, which needs dynamics mode (rotor speeds or "
                                 "--thrust; not --mode imu)");
    engine.subscribe(input);
    engine.start();
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    spdlog::info("listening on {} ({})", url, fmt::join(engine.input_channels(), ", "));
    const std::string end = vid::live::run_lcm_loop(
        input, url, [&] { return g_stop.load() || engine.failed(); }, idle_s, engine.message_count());
    engine.finish();  // throws (one-line error, exit 1) when the estimator stopped on an error
    const bool cut = end == "eof" && log_scan && log_scan->whole_bytes < log_scan->size;
    nlohmann::json extra = {{"input_end", cut ? "cut" : end}};  // eof | cut | stopped (SIGINT/SIGTERM) | idle
    if (log_scan) extra["input"] = {{"lcm_log", vid::live::log_scan_json(vid::live::log_path(url), *log_scan)}};
    engine.write_summary(extra);
    const auto s = engine.summary();
    if (cut)
      throw std::runtime_error(fmt::format("{}: log cut mid-event at byte {} of {}; read the {} whole events before it",
                                           vid::live::log_path(url), log_scan->whole_bytes, log_scan->size,
                                           log_scan->events));
    for (const auto& w : s["warnings"]) spdlog::warn("{}", w.get<std::string>());  // e.g. external_force_near_2g
    spdlog::info("input ended ({}): {} states published, health {}, {} re-initializations", end,
                 engine.published_states(), s["health"].get<std::string>(), s["reinit_count"].get<int>());
    if (!rerun.empty() && end != "stopped") {
      std::optional<std::filesystem::path> images;  // a recorded dataset as --sensors has the images
      if (!sensors.empty() && std::filesystem::exists(std::filesystem::path(sensors) / "mav0" / "imu0" / "data.csv"))
        images = sensors;
      vid::app::write_rerun_recording(argv[0], out, images, rerun);
    }
    if (end == "stopped") return 130;
    return engine.camera_never_delivered() ? 5 : 0;  // said in one line by the engine
  });
}
