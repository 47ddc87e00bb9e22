#pragma once
/// @file dataset_run.h
/// @brief A run over a dataset folder, as vid_run and the Python bindings' run_dataset do it:
/// the reader (images decoded ahead) feeds a System; progress, interruption and the dataset's
/// fields of summary.json.

#include <atomic>
#include <filesystem>
#include <optional>
#include <string>

#include "vid_system/config.h"
#include "vio_core/estimator_params.h"

namespace vid::system {

/// @brief The options of a dataset run (vid_run's command line).
struct RunOptions {
  std::filesystem::path dataset;
  std::filesystem::path out_dir;
  std::optional<std::filesystem::path> config;
  std::optional<PropagationMode> mode;   ///< default: dynamics when rotor0/thrust0 exist
  std::optional<InitMode> init;          ///< default: the config's init_mode
  /// Fixed-lag smoothing with this lag [s] (estimator smoother_lag_s; default: the config's):
  /// force_smoothed.csv and trajectory_smoothed_tum.txt next to the causal outputs.
  std::optional<double> smooth_lag_s;
  FeatureSource features = FeatureSource::kAuto;
  double start_s = 0.0;                  ///< relative to the first measurement
  std::optional<double> end_s;           ///< none: to the end
  bool progress = true;
  /// A camera frame with a missing, unreadable or wrong-size image is an error (default: the
  /// frame is skipped with a warning and counted).
  bool strict = false;
  /// A sensor-stream gap longer than this many sample periods is a load-time error (0: off) ...
  double max_gap_periods = 100.0;
  /// ... or, with allow_gaps, one warning line per gap (the estimator bridges it as usual).
  bool allow_gaps = false;
  /// Threads decoding images ahead of the frontend (plus one reading the files); 0: read and
  /// decode inline on the estimator thread. Outputs are the same either way.
  int decode_threads = 1;
  /// Also write out_dir/tracks.csv (the frontend's tracked features, vid_track's format).
  bool write_tracks = false;
  /// When the health checks report divergence: start the estimator again from the data (the
  /// config's init_mode: in flight with `auto`) and go on (true), or stop with exit 3 (false).
  bool reinit_on_divergence = true;
};

/// @brief How a run ended (the program's exit code follows it; apps/vid_run/README.md "Exit
/// codes"): never initialized (status waiting_for_init) and no camera frame used are failures.
enum class RunResult { kOk = 0, kDiverged = 3, kNotInitialized = 4, kNoFrameUsed = 5, kInterrupted = 130 };

/// @brief Run the estimator over a dataset and write every output; summary.json is always
/// written, also when the run is interrupted or diverges.
/// @param stop  set asynchronously (SIGINT) to end the run cleanly
/// @throws io::DatasetError / io::ConfigError / std::runtime_error on bad input
RunResult run_dataset(const RunOptions& options, const std::atomic<bool>& stop);

}  // namespace vid::system
