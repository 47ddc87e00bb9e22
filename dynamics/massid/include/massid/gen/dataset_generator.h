#pragma once
/// @file dataset_generator.h
/// @brief Generate a whole study dataset (trajectories x profiles x runs) in parallel and
/// write it in the layout of run_data.h (run CSVs + manifest.yaml).

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "massid/gen/run_simulator.h"
#include "massid/gen/study_config.h"

namespace vid::massid::gen {

/// @brief Per trajectory x profile summary of a generated dataset.
struct GroupSummary {
  std::string trajectory, profile;
  int runs = 0;
  double position_rmse_mean_m = 0.0;  ///< mean over runs of the true tracking RMSE
  double position_rmse_max_m = 0.0;
  double saturated_fraction_mean = 0.0;
};

/// @brief Result of generate_dataset.
struct GenerationResult {
  std::vector<RunInfo> runs;           ///< in manifest order
  std::vector<RunStats> stats;         ///< same order
  std::vector<GroupSummary> groups;    ///< trajectory-major
};

/// @brief Simulate every run and write DIR/<trajectory>/<profile>/run_NNN.csv and
/// DIR/manifest.yaml. Runs are spread over `threads` worker threads (0 = hardware
/// concurrency); each run depends only on its own seed, so output is identical for any
/// thread count. `progress(done, total)` is called from the calling thread.
/// @throws std::runtime_error when a file cannot be written
/// With `write_truth`, each run also gets run_<NNN>_truth.csv (write_truth_csv).
GenerationResult generate_dataset(const GeneratorSettings& settings,
                                  const std::filesystem::path& out_dir, int threads,
                                  const std::function<void(int, int)>& progress = {},
                                  bool write_truth = false);

}  // namespace vid::massid::gen
