/// @file main.cpp
/// @brief vid_sim: scenario YAML -> simulated dataset folder (docs/formats.md §1); with
/// --camera-along only the camera streams along a recorded trajectory (sim/camera_along.h).

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>

#include "app/cli.h"
#include "app/run_main.h"
#include "sim/camera_along.h"
#include "sim/dataset_sink.h"
#include "sim/scenario.h"
#include "sim/simulator.h"
#include "vid_system/progress.h"

int main(int argc, char** argv) {
  return vid::app::run_main("vid_sim", [&]() -> int {
    CLI::App cli{"vid_sim: write a simulated VID-Dataset-like sequence (scenario YAML -> dataset folder), or with "
                  "--camera-along only the camera streams along a recorded trajectory"};
    std::string scenario_file, out_dir;
    std::optional<std::uint64_t> seed;
    std::optional<double> duration;
    std::string heading, along_file;
    bool features_only = false, no_noise = false, quiet = false, overwrite = false;
    cli.add_option("--scenario", scenario_file, "scenario YAML (see config/sim/README.md)")->required();
    cli.add_option("--out", out_dir, "output folder (DIR/mav0/...)")->required();
    cli.add_option("--seed", seed, "random seed (default: the scenario's seed)");
    cli.add_option("--duration", duration, "simulated duration [s] (default: the scenario's)")
        ->check(CLI::PositiveNumber);
    cli.add_option("--initial-heading", heading,
                   "heading at t = 0 in the written ground-truth world: degrees, or 'random' (drawn "
                   "from the seed); default: the scenario's groundtruth.initial_heading_deg");
    cli.add_flag("--features-only", features_only, "write feat0 + landmarks.csv, no images");
    cli.add_flag("--no-noise", no_noise, "turn every sensor noise and random walk off");
    cli.add_flag("--quiet", quiet, "no log output");
    cli.add_option("--camera-along", along_file,
                   "TUM file 't[s] x y z qx qy qz qw' of T_WI (e.g. motion capture): write ONLY the camera "
                   "streams (camN, feat0, landmarks.csv) at the scenario's camera rate along it into OUT/mav0; "
                   "the scenario's cameras, scene, render, features, seed and noise are used, its trajectory, "
                   "vehicle, IMU, rotor sensor, forces and ground truth ignored; other files in OUT stay untouched");
    cli.add_flag("--overwrite", overwrite, "with --camera-along: replace existing camera streams in OUT");
    if (const auto code = vid::app::parse_cli(cli, argc, argv)) return *code;
    if (quiet) spdlog::set_level(spdlog::level::warn);
    if (along_file.empty() && overwrite) throw vid::system::UsageError("--overwrite: only with --camera-along");
    if (!along_file.empty() && (duration || !heading.empty()))
      throw vid::system::UsageError("--camera-along: --duration and --initial-heading do not apply (the recording sets both)");

    vid::sim::Scenario sc = vid::sim::load_scenario(scenario_file);
    try {
      vid::sim::apply_run_options(sc, seed, duration, heading);
    } catch (const std::invalid_argument& e) {
      throw vid::system::UsageError(e.what());
    }
    if (no_noise) sc.noise = false;
    if (features_only) {
      sc.cameras.images = false;
      sc.cameras.features = true;
    }
    if (!along_file.empty()) {
      const vid::sim::PoseTrack track = vid::sim::PoseTrack::read_tum(along_file);
      const double span_s = static_cast<double>(track.end_ns() - track.start_ns()) * 1e-9;
      spdlog::info("vid_sim: cameras of '{}' ({}), seed {}, along {} ({} poses, {:.1f} s){}", sc.name, scenario_file,
                   sc.seed, along_file, track.size(), span_s, sc.cameras.images ? " with images" : "");
      vid::system::ProgressBar bar("vid_sim", span_s);
      const std::uint64_t frames = vid::sim::write_camera_along(
          sc, track, out_dir, overwrite, [&](std::uint64_t k, std::uint64_t n) {
            bar.update(span_s * static_cast<double>(k) / static_cast<double>(n), std::to_string(k) + " frames");
          });
      bar.finish();
      spdlog::info("vid_sim: wrote {} camera frames into {}/mav0", frames, out_dir);
      return 0;
    }
    spdlog::info("vid_sim: scenario '{}' ({}), seed {}, {:.1f} s, {} camera(s){}", sc.name, scenario_file, sc.seed,
                 sc.duration_s, sc.cameras.cameras.size(), sc.cameras.images ? " with images" : "");
    const auto wall0 = std::chrono::steady_clock::now();
    vid::sim::Simulator sim(sc);
    spdlog::info("vid_sim: initial heading {:.1f} deg in the ground-truth world", sim.initial_heading_deg());
    vid::sim::DatasetSink sink(out_dir, sc, vid::sim::make_visual_output(sc), sim.R_GS());
    vid::system::ProgressBar bar("vid_sim", sc.duration_s);
    sim.run(sink, [&](double done, double) { bar.update(done, std::to_string(sink.camera_frames()) + " frames"); });
    sink.finish();
    bar.finish();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    spdlog::info("vid_sim: wrote {} ({} camera frames) in {:.1f} s", out_dir, sink.camera_frames(), wall);
    return 0;
  });
}
