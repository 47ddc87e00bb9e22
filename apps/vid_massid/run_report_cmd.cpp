/// @file run_report_cmd.cpp
/// @brief `vid_massid run` (methods over a study dataset -> OUT/runs.csv + per-run estimates)
/// and `vid_massid report` (per-trajectory tables like the seed's figures 7-11 + PNG plots
/// drawn by `vid-eval massid-plots`).
#include <spdlog/spdlog.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "app/view_launch.h"
#include "commands.h"
#include "massid/filters/study_io.h"
#include "massid/filters/study_runner.h"
#include "vid_system/progress.h"

namespace vid::massid_app {
namespace {

namespace fs = std::filesystem;

struct RunOptions {
  std::string data, out, methods = "ekf,ukf,msckf,swls,vio";
  int runs_per_case = 10, threads = 2, train_runs_per_case = 2, hidden_nodes = 500;
  std::uint64_t selection_seed = 1;
};

struct ReportOptions {
  std::string results;
  bool no_plots = false;
};

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

int run_methods(const RunOptions& o) {
  const massid::DatasetIndex index = massid::read_dataset_index(o.data);
  massid::StudyRunOptions so;
  so.methods = split_list(o.methods);
  if (so.methods.empty()) throw std::runtime_error("--methods: empty list");
  if (o.runs_per_case < 1) throw std::runtime_error("--runs-per-case must be >= 1");
  so.runs_per_case = o.runs_per_case;
  so.threads = std::max(1, o.threads);
  so.selection_seed = o.selection_seed;
  so.train_runs_per_case = o.train_runs_per_case;
  so.data_driven.hidden_nodes = o.hidden_nodes;
  fs::create_directories(o.out);
  const fs::path runs_file = fs::path(o.out) / "runs.csv";
  std::ofstream runs(runs_file);
  if (!runs) throw std::runtime_error(runs_file.string() + ": cannot write");
  runs << massid::runs_csv_header() << '\n';
  const int total = static_cast<int>(massid::select_runs(index, so.runs_per_case, so.selection_seed).size());
  spdlog::info("running {} on {} runs of {} with {} threads", o.methods, total, o.data, so.threads);
  system::ProgressBar bar("run", total);
  massid::run_study(index, so, [&](const massid::RunResult& r, int done, int n) {
    for (const std::string& line : massid::runs_csv_lines(r)) runs << line << '\n';
    massid::write_estimates_csv(o.out, r);
    bar.update(done, std::to_string(done) + "/" + std::to_string(n) + " runs");
  });
  bar.finish();
  runs.close();
  if (!runs) throw std::runtime_error(runs_file.string() + ": write failed");
  spdlog::info("wrote {} and {}/estimates/", runs_file.string(), o.out);
  return 0;
}

int run_report(const ReportOptions& o) {
  const fs::path results(o.results);
  const auto rows = massid::read_runs_csv(results / "runs.csv");
  const fs::path report_dir = results / "report";
  std::cout << massid::write_tables(rows, report_dir);
  spdlog::info("tables in {}", report_dir.string());
  if (o.no_plots) return 0;
  app::run_vid_eval("vid_massid",
                     {"massid-plots", "--results", results.string(), "--out", (report_dir / "plots").string()},
                     "vid_massid report: plots (--no-plots for tables only)");
  return 0;
}

}  // namespace

void add_run_report_commands(CLI::App& cli, int* exit_code) {
  auto ro = std::make_shared<RunOptions>();
  CLI::App* run = cli.add_subcommand("run", "Run mass-identification methods over a study dataset; "
                                            "writes OUT/runs.csv and OUT/estimates/.");
  run->add_option("--data", ro->data, "study dataset folder (vid_massid generate)")->required()->check(CLI::ExistingDirectory);
  run->add_option("--out", ro->out, "output folder")->required();
  run->add_option("--methods", ro->methods,
                  "comma-separated methods: ekf,ukf,msckf,swls,vio,elm,relm,oselm")
      ->capture_default_str();
  run->add_option("--runs-per-case", ro->runs_per_case, "evaluated runs per trajectory x profile")->capture_default_str();
  run->add_option("--threads", ro->threads, "worker threads")->capture_default_str();
  run->add_option("--selection-seed", ro->selection_seed, "seed of the run selection")->capture_default_str();
  run->add_option("--train-runs-per-case", ro->train_runs_per_case, "ELM family: training runs per case")->capture_default_str();
  run->add_option("--hidden-nodes", ro->hidden_nodes, "ELM family: hidden nodes")->capture_default_str();
  run->callback([ro, exit_code]() { *exit_code = run_methods(*ro); });

  auto po = std::make_shared<ReportOptions>();
  CLI::App* rep = cli.add_subcommand("report", "Tables (Markdown + CSV) per trajectory and PNG plots of "
                                               "mass estimate vs truth from a `run` output folder.");
  rep->add_option("--results", po->results, "output folder of `vid_massid run`")->required()->check(CLI::ExistingDirectory);
  rep->add_flag("--no-plots", po->no_plots, "tables only");
  rep->callback([po, exit_code]() { *exit_code = run_report(*po); });
}

}  // namespace vid::massid_app
