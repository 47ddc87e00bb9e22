/// vid_replay: publish a dataset folder on LCM (docs/design.md §4, issue 9).
#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <csignal>
#include <fstream>

#include "app/cli.h"
#include "app/run_main.h"
#include "live/lcm_input.h"
#include "replay/replay.h"

namespace {
std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop.store(true); }
}  // namespace

int main(int argc, char** argv) {
  spdlog::set_default_logger(spdlog::stderr_color_mt("vid_replay"));
  spdlog::set_pattern("%^vid_replay: %l:%$ %v");
  return vid::app::run_main("vid_replay", [&]() -> int {
    CLI::App app{"vid_replay: publish a dataset folder (EuRoC/ASL + extensions) on LCM"};
    vid::replay::ReplayOptions opt;
    std::string dataset, log, channels, report;
    app.add_option("--dataset", dataset, "dataset folder (SEQ or SEQ/mav0)")->required();
    app.add_option("--lcm-url", opt.lcm_url, "LCM URL to publish on (e.g. udpm://239.255.76.67:7667?ttl=0, memq://)")
        ->required();
    auto* rate = app.add_option("--rate", opt.rate, "real-time factor (default 1)")->check(CLI::PositiveNumber);
    app.add_flag("--fast", opt.fast, "publish as fast as possible")->excludes(rate);
    app.add_option("--log", log, "also write an LCM event log (lcm-logplayer / lcm.EventLog format)");
    app.add_option("--channels", channels, "YAML file of channel names (keys imu, cam0, cam1, rotors, thrust)");
    app.add_option("--start", opt.start_s, "start [s] after the first measurement");
    app.add_option("--end", opt.end_s, "end [s] after the first measurement (default: to the end)");
    app.add_option("--loop", opt.loops, "replay the window N times, each pass shifted to follow the last (soak tests)")
        ->check(CLI::Range(1, 1000000));
    auto& f = opt.faults;
    app.add_option("--drop-images", f.drop_images, "fault: probability of not publishing an image")
        ->check(CLI::Range(0.0, 1.0));
    app.add_option("--duplicate-imu", f.duplicate_imu, "fault: probability of publishing an IMU message twice")
        ->check(CLI::Range(0.0, 1.0));
    app.add_option("--reorder", f.reorder, "fault: probability of delaying a message (any stream)")
        ->check(CLI::Range(0.0, 1.0));
    app.add_option("--reorder-max-ms", f.reorder_max_ms, "fault: largest delay of a reordered message [ms]")
        ->check(CLI::Range(0.0, 10000.0));
    app.add_option("--malformed", f.malformed, "fault: number of undecodable/invalid messages")
        ->check(CLI::Range(0, 1000000));
    app.add_option("--late", f.late, "fault: probability of publishing a message --late-ms after its time")
        ->check(CLI::Range(0.0, 1.0));
    app.add_option("--late-ms", f.late_ms, "fault: delay of a late message [ms] (default 100)")
        ->check(CLI::Range(0.0, 100000.0));
    std::vector<double> stall;
    app.add_option("--camera-stall", stall, "fault: START DURATION [s]: no images in that span")->expected(2);
    app.add_option("--fault-seed", f.seed, "seed of the fault injection");
    app.add_option("--image-bit-depth", opt.image_bit_depth,
                   "significant bits of 16-bit images, e.g. 12 (default 0: found per camera from sample images)")
        ->check(CLI::IsMember({0, 9, 10, 11, 12, 13, 14, 15, 16}));
    app.add_flag("--no-camera", opt.no_camera,
                 "publish IMU and rotors/thrust without the camera (one warning line); needed for a folder without "
                 "cam0/ images, e.g. feature-level feat0/ data, which has no LCM message");
    app.add_option("--report", report, "write what was published and every injected fault as JSON");
    bool quiet = false;
    app.add_flag("--quiet", quiet, "no progress bar, warnings only");
    if (const auto code = vid::app::parse_cli(app, argc, argv)) return *code;
    vid::live::check_lcm_url(opt.lcm_url, "--lcm-url", /*for_input=*/false);  // LCM's own lines otherwise
    opt.dataset = dataset;
    if (stall.size() == 2) {
      if (stall[0] < 0.0 || stall[1] <= 0.0) throw vid::system::UsageError("--camera-stall: START >= 0 and DURATION > 0 expected");
      f.stall_start_s = stall[0];
      f.stall_s = stall[1];
    }
    if (!log.empty()) opt.log = log;
    if (!channels.empty()) opt.channels = vid::lcm_io::load_channels(channels);
    opt.progress = !quiet;
    if (quiet) spdlog::set_level(spdlog::level::warn);
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    const nlohmann::json r = vid::replay::replay(opt, g_stop);
    if (!report.empty()) {
      std::ofstream out(report);
      out << r.dump(2) << "\n";
      if (!out) throw std::runtime_error(report + ": cannot write the report");
    }
    long total = 0;
    for (const auto& [channel, n] : r["published"].items()) total += n.get<long>();
    spdlog::info("{} messages published in {:.1f} s", total, r["wall_time_s"].get<double>());
    return g_stop.load() ? 130 : 0;
  });
}
