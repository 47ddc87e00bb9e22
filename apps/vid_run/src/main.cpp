/// vid_run: offline estimation on a dataset folder (docs/formats.md §2, docs/design.md §4).
#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <csignal>

#include "app/cli.h"
#include "app/run_main.h"
#include "app/view_launch.h"
#include "vid_system/dataset_run.h"

namespace {
std::atomic<bool> g_stop{false};
extern "C" void on_sigint(int) { g_stop.store(true); }
}  // namespace

int main(int argc, char** argv) {
  // Logs (progress info, warnings) go to stderr: stdout stays free for piping.
  spdlog::set_default_logger(spdlog::stderr_color_mt("vid_run"));
  spdlog::set_pattern("%^vid_run: %l:%$ %v");
  return vid::app::run_main("vid_run", [&]() -> int {
    CLI::App app{"vid_run: estimate pose and external force on a dataset folder (EuRoC/ASL + extensions)"};
    vid::system::RunOptions opt;
    std::string config, mode, init, features = "auto";
    app.add_option("--dataset", opt.dataset, "dataset folder (SEQ or SEQ/mav0)")->required();
    app.add_option("--out", opt.out_dir, "output folder (created)")->required();
    app.add_option("--config", config, "preset folder or its estimator.yaml (default: the dataset's own files)");
    app.add_option("--mode", mode, "imu | dynamics (default: dynamics when rotor0/ or thrust0/ exist)")
        ->check(CLI::IsMember({"imu", "dynamics"}));
    app.add_option("--init", init, "auto | static | groundtruth (default: the config's init_mode)")
        ->check(CLI::IsMember({"auto", "static", "groundtruth"}));
    app.add_option("--features", features, "images | feat0 | auto (default: images when cam0/data.csv exists)")
        ->check(CLI::IsMember({"auto", "images", "feat0"}));
    app.add_option("--smooth", opt.smooth_lag_s,
                   "fixed-lag smoothing with this lag [s] (dynamics mode): also writes force_smoothed.csv and "
                   "trajectory_smoothed_tum.txt; the causal outputs stay as they are")
        ->check(CLI::PositiveNumber);
    app.add_option("--start", opt.start_s, "start [s] after the first measurement");
    app.add_option("--end", opt.end_s, "end [s] after the first measurement (default: to the end)");
    app.add_option("--decode-threads", opt.decode_threads,
                   "threads decoding images ahead of the frontend; 0: decode inline (default 1)")
        ->check(CLI::Range(0, 8));
    app.add_flag("--strict", opt.strict,
                 "a missing, unreadable or wrong-size camera image is an error (exit 1, outputs so far kept) "
                 "instead of a skipped frame (one warning, counted in summary.json)");
    app.add_option("--max-gap-periods", opt.max_gap_periods,
                   "a time gap in imu0, rotor0, thrust0, camN or feat0 longer than this many sample periods is an "
                   "error naming file and line (default 100; 0: no check)")
        ->check(CLI::NonNegativeNumber);
    app.add_flag("--allow-gaps", opt.allow_gaps, "such a gap is a warning instead of an error");
    app.add_flag("--tracks", opt.write_tracks,
                 "also write OUT/tracks.csv: the tracked features of every frame (vid_track's format)");
    std::string rerun;
    app.add_option("--rerun", rerun,
                   "after the run, log it (trajectory, force, tracked features, images) to this Rerun .rrd file "
                   "with `vid-eval view` (implies --tracks)");
    std::string on_divergence = "reinit";
    app.add_option("--on-divergence", on_divergence,
                   "reinit: start the estimator again from the data (in flight with init_mode auto) and go on, "
                   "each divergence one warning line and listed in summary.json; stop: end the run, exit 3 "
                   "(default reinit)")
        ->check(CLI::IsMember({"reinit", "stop"}));
    bool quiet = false;
    app.add_flag("--quiet", quiet, "no progress bar, warnings only");
    if (const auto code = vid::app::parse_cli(app, argc, argv)) return *code;
    if (!config.empty()) opt.config = config;
    if (!mode.empty()) opt.mode = vid::mode_from_string(mode);
    if (!init.empty()) opt.init = vid::init_mode_from_string(init);
    opt.features = features == "images"  ? vid::system::FeatureSource::kImages
                   : features == "feat0" ? vid::system::FeatureSource::kFeat0
                                         : vid::system::FeatureSource::kAuto;
    opt.reinit_on_divergence = on_divergence == "reinit";
    opt.progress = !quiet;
    if (quiet) spdlog::set_level(spdlog::level::warn);
    std::signal(SIGINT, on_sigint);
    std::signal(SIGTERM, on_sigint);
    if (!rerun.empty()) opt.write_tracks = true;
    const auto result = vid::system::run_dataset(opt, g_stop);
    if (!rerun.empty() && result != vid::system::RunResult::kInterrupted)
      vid::app::write_rerun_recording(argv[0], opt.out_dir, opt.dataset, rerun);
    if (result == vid::system::RunResult::kDiverged) spdlog::error("the estimator diverged (see summary.json)");
    if (result == vid::system::RunResult::kInterrupted) spdlog::warn("interrupted: outputs and summary.json written");
    return static_cast<int>(result);
  });
}
