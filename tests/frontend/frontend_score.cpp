// Developer tool (not a test): score the KLT frontend on a rendered sequence with a given
// frontend config, printing the same report as test_frontend_scoring plus stage timings.
//   frontend_score DATASET SCENARIO.yaml [--config FILE] [--mono] [--min-rate R]
//                  [--seed N] [--duration S] [--initial-heading DEG|random]   (as given to vid_sim)
#include <CLI/CLI.hpp>

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>

#include "frontend/frontend_params_yaml.h"
#include "sim/scenario.h"
#include "sim/simulator.h"
#include "track_scoring.h"

int main(int argc, char** argv) {
  CLI::App cli{"score the KLT frontend on a rendered simulator sequence"};
  std::string dataset, scenario, config;
  bool mono = false;
  double min_rate = 0.0;
  cli.add_option("dataset", dataset, "rendered dataset folder")->required();
  cli.add_option("scenario", scenario, "scenario YAML it was rendered from")->required();
  cli.add_option("--config", config, "frontend settings YAML");
  cli.add_flag("--mono", mono, "left camera only");
  cli.add_option("--min-rate", min_rate, "count frame-to-frame survival only above this rate");
  std::optional<std::uint64_t> seed;
  std::optional<double> duration;
  std::string heading;
  cli.add_option("--seed", seed, "vid_sim's --seed (the ground-truth world's heading may depend on it)");
  cli.add_option("--duration", duration, "vid_sim's --duration");
  cli.add_option("--initial-heading", heading, "vid_sim's --initial-heading");
  CLI11_PARSE(cli, argc, argv);
  try {
    vid::FrontendParams p;
    if (!config.empty()) p = vid::load_frontend_params(config);
    const vid::sim::Scene scene = vid::sim::scene_from_scenario_file(scenario);
    vid::sim::Scenario sc = vid::sim::load_scenario(scenario);
    vid::sim::apply_run_options(sc, seed, duration, heading);
    const Eigen::Matrix3d R_GS = vid::sim::Simulator(sc).R_GS();  // ground truth -> scene world
    const auto s = vid::test::score_sequence(dataset, p, scene, !mono, min_rate, R_GS);
    vid::test::print_score(dataset.c_str(), s);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "frontend_score: %s\n", e.what());
    return 1;
  }
  return 0;
}
