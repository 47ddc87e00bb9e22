/// @file generate_cmd.cpp
/// @brief `vid_massid generate`: settings from YAML + flags -> study dataset folder.
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <memory>
#include <sstream>

#include "commands.h"
#include "massid/gen/dataset_generator.h"
#include "massid/gen/study_config.h"
#include "vid_system/progress.h"

namespace vid::massid_app {
namespace {

struct GenerateOptions {
  std::string config;
  std::string out;
  int runs = 0;
  std::vector<std::string> trajectories;
  std::vector<std::string> profiles;
  std::int64_t seed = -1;
  int threads = 0;
  bool quiet = false;
  bool truth = false;
};

int run_generate(const GenerateOptions& o) {
  massid::gen::GeneratorSettings settings;
  if (!o.config.empty()) settings = massid::gen::load_generator_settings(o.config);
  if (o.runs > 0) settings.runs = o.runs;
  if (!o.trajectories.empty()) settings.trajectories = o.trajectories;
  if (!o.profiles.empty()) settings.profiles = o.profiles;
  if (o.seed >= 0) settings.seed = static_cast<std::uint64_t>(o.seed);
  try {
    massid::gen::validate(settings);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("settings: ") + e.what());
  }
  // Logs on stderr; stdout carries only the tracking table.
  spdlog::logger log("vid_massid", std::make_shared<spdlog::sinks::stderr_sink_st>());
  const int total = static_cast<int>(settings.trajectories.size() * settings.profiles.size()) *
                    settings.runs;
  log.info("generating {} runs ({} trajectories x {} profiles x {}) into {}", total,
               settings.trajectories.size(), settings.profiles.size(), settings.runs, o.out);
  const auto t0 = std::chrono::steady_clock::now();
  system::ProgressBar bar("generate", total);
  const auto result = massid::gen::generate_dataset(
      settings, o.out, o.threads,
      [&](int done, int n) { bar.update(done, std::to_string(done) + "/" + std::to_string(n) + " runs"); },
      o.truth);
  bar.finish();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!o.quiet) {
    std::ostringstream table;
    table << "trajectory   profile          runs  pos_rmse_mean[m]  pos_rmse_max[m]  saturated\n";
    for (const auto& g : result.groups) {
      char line[160];
      std::snprintf(line, sizeof(line), "%-12s %-16s %4d  %16.4f  %15.4f  %8.1f%%\n",
                    g.trajectory.c_str(), g.profile.c_str(), g.runs, g.position_rmse_mean_m,
                    g.position_rmse_max_m, 100.0 * g.saturated_fraction_mean);
      table << line;
    }
    std::fputs(table.str().c_str(), stdout);
  }
  log.info("wrote {} runs in {:.1f} s", total, seconds);
  return 0;
}

}  // namespace

void add_generate_command(CLI::App& cli, int* exit_code) {
  auto opts = std::make_shared<GenerateOptions>();
  CLI::App* cmd = cli.add_subcommand(
      "generate", "Simulate the study's runs (trajectories x mass profiles x runs) as run CSVs "
                  "plus manifest.yaml");
  cmd->add_option("--config", opts->config, "Settings YAML (e.g. config/massid/study.yaml)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", opts->out, "Output folder")->required();
  cmd->add_option("--runs", opts->runs, "Runs per trajectory x profile (overrides the config)")
      ->check(CLI::Range(1, 999));
  cmd->add_option("--trajectories", opts->trajectories,
                  "Comma-separated subset of random,loop,lemniscate,zigzag,square")
      ->delimiter(',');
  cmd->add_option("--profiles", opts->profiles,
                  "Comma-separated subset of constant,linear_decrease,step_drop,step_pickup,up_down")
      ->delimiter(',');
  cmd->add_option("--seed", opts->seed, "Base seed (overrides the config)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--threads", opts->threads, "Worker threads (0 = all cores)")->check(CLI::NonNegativeNumber);
  cmd->add_flag("--quiet", opts->quiet, "Do not print the per-group tracking table");
  cmd->add_flag("--truth", opts->truth,
                "Also write run_NNN_truth.csv (true state, reference, MPC acceleration, saturation)");
  cmd->callback([opts, exit_code]() { *exit_code = run_generate(*opts); });
}

}  // namespace vid::massid_app
