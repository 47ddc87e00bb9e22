#pragma once
/// @file study_runner.h
/// @brief Runs mass-identification methods over a study dataset (seed section 5.3): picks the
/// evaluated runs per trajectory x mass profile, feeds every sample to each method, times
/// each update() and scores the estimates with RMSPE (docs/model.md eq. (56)). Parallel over runs.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "massid/estimator.h"
#include "massid/filters/tuning.h"
#include "massid/run_data.h"

namespace vid::massid {

/// @brief Settings of a study run.
struct StudyRunOptions {
  std::vector<std::string> methods = {"ekf", "ukf", "msckf", "swls", "vio"};
  int runs_per_case = 10;           ///< evaluated runs per trajectory x profile (seed: 10)
  int threads = 2;
  std::uint64_t selection_seed = 1; ///< which runs are picked (fixed -> reproducible)
  ModelBasedTuning tuning;
  DataDrivenOptions data_driven;    ///< ELM family
  int train_runs_per_case = 2;      ///< ELM family: training runs per case (not evaluated ones)
};

/// @brief One method on one run.
struct MethodRunResult {
  std::string method;
  double rmspe_pct = 0.0;
  double mean_update_ms = 0.0;      ///< wall time per update() [ms]
  double mean_update_cpu_ms = 0.0;  ///< thread CPU time per update() [ms] (robust on a shared machine)
  std::vector<double> mass_hat;  ///< estimate after each sample
};

/// @brief All methods on one run.
struct RunResult {
  RunInfo info;
  std::vector<MassIdSample> samples;
  std::vector<MethodRunResult> methods;
};

/// @brief Every method name `run` accepts.
std::vector<std::string> available_methods();

/// @brief Pick runs_per_case runs of every trajectory x profile (seeded shuffle), in
/// manifest order. Cases with fewer runs use all of them.
std::vector<RunInfo> select_runs(const DatasetIndex& index, int runs_per_case, std::uint64_t seed);

/// @brief Evaluate one loaded run with ready estimators (each is reset first). The update
/// times are the totals over the run's update() calls (samples 1..n-1) divided by their count.
RunResult evaluate_run(const MassIdRun& run, const std::vector<MassEstimator*>& estimators);

/// @brief Run the study. `on_result` is called (serialized, any thread) for each finished run
/// with the number done so far; results are not kept, so memory stays flat.
/// @throws std::invalid_argument on an unknown or unavailable method
void run_study(const DatasetIndex& index, const StudyRunOptions& options,
               const std::function<void(const RunResult&, int done, int total)>& on_result);

}  // namespace vid::massid
