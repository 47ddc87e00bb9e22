/// @file main.cpp
/// @brief vid_track: run the KLT frontend alone on a dataset folder (docs/formats.md §1) and write the
/// tracks as CSV (#timestamp [ns],cam_id,feature_id,u [px],v [px]), optionally with pictures.
#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <string>

#include "app/cli.h"
#include "app/run_main.h"
#include "frontend/frontend_params_yaml.h"
#include "track_session.h"

int main(int argc, char** argv) {
  // Logs (warnings, the closing line) go to stderr, prefixed like every program's.
  spdlog::set_default_logger(spdlog::stderr_color_mt("vid_track"));
  spdlog::set_pattern("%^vid_track: %l:%$ %v");
  return vid::app::run_main("vid_track", [&]() -> int {
    CLI::App cli{"KLT frontend alone on a dataset folder: tracks CSV and optional drawn images."};
    std::string dataset, config, out, draw;
    std::size_t draw_every = 1;
    bool no_gyro = false;
    cli.add_option("--dataset", dataset, "dataset folder (SEQ or SEQ/mav0)")->required();
    cli.add_option("--config", config, "frontend settings YAML (config/frontend/default.yaml)");
    cli.add_option("--out", out, "output tracks CSV")->required();
    cli.add_option("--draw", draw, "write PNGs with track trails and stereo matches here");
    cli.add_option("--draw-every", draw_every, "draw every n-th frame")->check(CLI::PositiveNumber);
    cli.add_flag("--no-gyro", no_gyro, "disable gyro-aided prediction");
    bool strict = false, quiet = false;
    cli.add_flag("--strict", strict,
                 "a missing, unreadable or wrong-size image is an error (exit 1, tracks so far kept) instead of a "
                 "skipped frame (one warning, counted)");
    cli.add_flag("--quiet", quiet, "warnings only");
    if (const auto code = vid::app::parse_cli(cli, argc, argv)) return *code;
    vid::app::TrackOptions o;
    o.dataset = dataset;
    o.out_csv = out;
    if (!draw.empty()) o.draw_dir = draw;
    o.draw_every = draw_every;
    o.strict = strict;
    if (quiet) spdlog::set_level(spdlog::level::warn);
    if (!config.empty()) o.params = vid::load_frontend_params(config);
    if (no_gyro) o.params.gyro_prediction = false;
    const auto s = vid::app::run_tracking(o);
    spdlog::info("vid_track: {} frames ({} skipped for bad images), {:.1f} tracks/frame, {:.1f} stereo/frame, "
                 "{:.2f} ms/frame, {} observations -> {}",
                 s.frames, s.frames_skipped, s.mean_features, s.mean_stereo, s.mean_ms, s.observations, out);
    return 0;
  });
}
