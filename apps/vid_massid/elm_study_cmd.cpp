/// @file elm_study_cmd.cpp
/// @brief `vid_massid elm-study`: the data-driven study of seed section 6.3 — tables 1-3
/// (hidden nodes ELM vs RELM, lambda sweep, number of training datasets), a method table
/// (ELM / RELM / OSELM at the seed's setting) and the series behind figures 13-17 (estimate vs
/// truth per trajectory and mass profile), plotted by `vid-eval elm-plots` (--plots).
#include <spdlog/spdlog.h>

#include <chrono>
#include <filesystem>
#include <memory>

#include "app/view_launch.h"
#include "commands.h"
#include "massid/elm/study.h"
#include "massid/elm/study_tables.h"
#include "vid_system/progress.h"

namespace vid::massid_app {
namespace {

namespace me = massid::elm;

struct StudyOptions {
  std::string dataset;
  std::string out;
  std::vector<std::string> trajectories;
  std::vector<int> hidden{50, 100, 200, 300, 400, 500, 600, 700, 800, 900, 1000};
  std::vector<double> lambdas{1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1.0};
  int max_train = 10;
  int n_train = 5;
  int base_hidden = 500;
  double base_lambda = 1e-5;
  int test_per_profile = 2;
  int test_first = 10;
  int repeats = 1;
  int oselm_chunk = 1;
  std::uint64_t seed = 1;
  std::vector<int> tables{0, 1, 2, 3};
  std::vector<double> windows;
  int stride = 0;
  double weight_scale = 0.0;
  bool plots = false;
};

bool wants(const StudyOptions& o, int t) {
  return std::find(o.tables.begin(), o.tables.end(), t) != o.tables.end();
}

std::vector<std::string> trajectories_of(const massid::DatasetIndex& index) {
  std::vector<std::string> out;
  for (const auto& r : index.runs) {
    if (std::find(out.begin(), out.end(), r.trajectory) == out.end()) out.push_back(r.trajectory);
  }
  return out;
}

int run_study(const StudyOptions& o) {
  const massid::DatasetIndex index = massid::read_dataset_index(o.dataset);
  const std::vector<std::string> trajectories =
      o.trajectories.empty() ? trajectories_of(index) : o.trajectories;
  const std::filesystem::path out(o.out);
  std::filesystem::create_directories(out / "series");
  me::RunCache cache(index);

  massid::DataDrivenOptions base;
  base.hidden_nodes = o.base_hidden;
  base.lambda = o.base_lambda;
  base.seed = o.seed;
  base.oselm_chunk = o.oselm_chunk;
  me::ModelConfig config;
  if (!o.windows.empty()) config.features.windows = o.windows;
  if (o.stride > 0) config.features.train_stride = o.stride;
  config.weight_scale = o.weight_scale;

  std::vector<me::StudyRow> t0_rows, t1_rows, t2_rows, t3_rows;
  const int steps_per_traj = (wants(o, 0) ? 3 : 0) +
                             (wants(o, 1) ? 2 * static_cast<int>(o.hidden.size()) : 0) +
                             (wants(o, 2) ? static_cast<int>(o.lambdas.size()) : 0) +
                             (wants(o, 3) ? o.max_train : 0);
  system::ProgressBar bar("elm-study", steps_per_traj * static_cast<double>(trajectories.size()));
  int done = 0;
  auto tick = [&](const std::string& what) { bar.update(++done, what); };

  for (const std::string& traj : trajectories) {
    const int n_split = std::max(o.n_train, wants(o, 3) ? o.max_train : 0);
    const me::RunSplit full = me::split_by_run(index, traj, n_split, o.test_per_profile, o.test_first);
    const auto test = cache.get_all(full.test);
    const std::vector<massid::RunInfo> base_train_info(full.train.begin(), full.train.begin() + o.n_train);
    const auto train = cache.get_all(base_train_info);
    spdlog::info("{}: {} training runs, {} held-out runs", traj, train.size(), test.size());

    if (wants(o, 0)) {  // methods at the seed's setting + figure series
      std::vector<std::string> names;
      std::vector<std::vector<std::vector<double>>> per_method;  // method -> test run -> series
      for (me::Method m : {me::Method::kElm, me::Method::kRelm, me::Method::kOselm}) {
        std::shared_ptr<const me::MassModel> model;
        me::StudyRow row = me::run_configuration(m, train, test, base, config, o.repeats, &model);
        t0_rows.push_back(row);
        names.push_back(row.method);
        per_method.emplace_back();
        me::score_held_out(*model, test, &per_method.back());
        tick(traj + " " + row.method);
      }
      // First held-out run of each profile -> series CSV for the figure 13-17 analogs.
      for (size_t i = 0; i < test.size(); i += static_cast<size_t>(o.test_per_profile)) {
        std::vector<std::vector<double>> est;
        for (const auto& pm : per_method) est.push_back(pm[i]);
        const auto& info = test[i]->info;
        me::write_series_csv(out / "series" / (traj + "__" + info.mass_profile + ".csv"), *test[i],
                             names, est);
      }
    }
    if (wants(o, 1)) {
      for (int L : o.hidden) {
        massid::DataDrivenOptions opt = base;
        opt.hidden_nodes = L;
        for (me::Method m : {me::Method::kElm, me::Method::kRelm}) {
          t1_rows.push_back(me::run_configuration(m, train, test, opt, config, o.repeats));
          tick(traj + " L=" + std::to_string(L));
        }
      }
    }
    if (wants(o, 2)) {
      for (double lambda : o.lambdas) {
        massid::DataDrivenOptions opt = base;
        opt.lambda = lambda;
        t2_rows.push_back(me::run_configuration(me::Method::kRelm, train, test, opt, config, o.repeats));
        tick(traj + " lambda");
      }
    }
    if (wants(o, 3)) {
      for (int n = 1; n <= o.max_train; ++n) {
        const std::vector<massid::RunInfo> infos(full.train.begin(), full.train.begin() + n);
        for (me::Method m : {me::Method::kRelm}) {
          t3_rows.push_back(me::run_configuration(m, cache.get_all(infos), test, base, config, o.repeats));
        }
        tick(traj + " n=" + std::to_string(n));
      }
    }
  }
  bar.finish();

  const std::string setting = std::to_string(o.base_hidden) + " hidden nodes, lambda " +
                              std::to_string(o.base_lambda) + ", " + std::to_string(o.n_train) +
                              " training datasets";
  if (wants(o, 0))
    me::write_study_table(out, "table_methods", "ELM / RELM / OSELM, " + setting,
                          me::SweepKind::kMethods, t0_rows);
  if (wants(o, 1))
    me::write_study_table(out, "table1_hidden_nodes",
                          "Table 1: hidden nodes, ELM vs RELM (lambda " + std::to_string(o.base_lambda) + ")",
                          me::SweepKind::kHidden, t1_rows);
  if (wants(o, 2))
    me::write_study_table(out, "table2_lambda", "Table 2: RELM lambda sweep (" + setting + ")",
                          me::SweepKind::kLambda, t2_rows);
  if (wants(o, 3))
    me::write_study_table(out, "table3_training_sets",
                          "Table 3: number of training datasets (RELM, " +
                              std::to_string(o.base_hidden) + " hidden nodes)",
                          me::SweepKind::kTrainingSets, t3_rows);
  spdlog::info("tables written to {}", out.string());

  if (o.plots && wants(o, 0)) app::run_vid_eval("vid_massid", {"elm-plots", out.string()}, "vid_massid elm-study: --plots");
  return 0;
}

}  // namespace

void add_elm_study_command(CLI::App& cli, int* exit_code) {
  auto o = std::make_shared<StudyOptions>();
  CLI::App* cmd = cli.add_subcommand(
      "elm-study", "Data-driven study (seed section 6.3): ELM/RELM/OSELM tables 1-3 and the "
                   "estimate-vs-truth series of figures 13-17, split by run");
  cmd->add_option("--dataset", o->dataset, "Dataset folder written by `vid_massid generate`")
      ->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--out", o->out, "Output folder for tables (.md/.csv), series and figures")->required();
  cmd->add_option("--trajectories", o->trajectories, "Subset of trajectories (default: all)")->delimiter(',');
  cmd->add_option("--hidden", o->hidden, "Table 1 hidden-node counts")->delimiter(',');
  cmd->add_option("--lambdas", o->lambdas, "Table 2 ridge weights")->delimiter(',');
  cmd->add_option("--max-train", o->max_train, "Table 3: 1..N training datasets")->check(CLI::Range(1, 100));
  cmd->add_option("--n-train", o->n_train, "Training datasets of tables 0-2 (one run per profile "
                  "cyclically)")->check(CLI::Range(1, 100));
  cmd->add_option("--base-hidden", o->base_hidden, "Hidden nodes of tables 0, 2, 3")->check(CLI::Range(1, 5000));
  cmd->add_option("--base-lambda", o->base_lambda, "lambda of tables 0, 1, 3")->check(CLI::PositiveNumber);
  cmd->add_option("--test-per-profile", o->test_per_profile, "Held-out runs per profile")->check(CLI::Range(1, 100));
  cmd->add_option("--test-first", o->test_first, "Index of the first held-out run (must exceed the "
                  "training indices)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--repeats", o->repeats, "Trainings per row; the minimum time is reported")->check(CLI::Range(1, 20));
  cmd->add_option("--oselm-chunk", o->oselm_chunk, "OSELM chunk size")->check(CLI::Range(1, 100000));
  cmd->add_option("--seed", o->seed, "Seed of the hidden-layer weights");
  cmd->add_option("--tables", o->tables, "Which tables: 0 methods+series, 1 hidden, 2 lambda, 3 "
                  "training sets")->delimiter(',');
  cmd->add_option("--windows", o->windows, "Feature windows [s], ascending (default 0.25,0.5,1)")
      ->delimiter(',');
  cmd->add_option("--stride", o->stride, "Training stride in samples (default 5)")->check(CLI::Range(1, 1000));
  cmd->add_option("--weight-scale", o->weight_scale, "Half-width of the input weights (0 = 2/sqrt(d))")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--plots", o->plots, "Also draw the figures (`vid-eval elm-plots OUT`; vid-eval found as "
                "$VID_EVAL, on PATH or in the repository's .venv)");
  cmd->callback([o, exit_code]() { *exit_code = run_study(*o); });
}

}  // namespace vid::massid_app
