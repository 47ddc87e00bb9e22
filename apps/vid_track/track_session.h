#pragma once
/// @file track_session.h
/// @brief Wiring of vid_track: dataset reader -> KLT tracker -> tracks CSV (+ drawings).

#include <filesystem>
#include <optional>
#include <string>

#include "frontend/frontend_params.h"

namespace vid::app {

/// @brief What vid_track was asked to do.
struct TrackOptions {
  std::filesystem::path dataset;
  std::filesystem::path out_csv;
  std::optional<std::filesystem::path> draw_dir;
  FrontendParams params;
  std::size_t draw_every = 1;  ///< draw every n-th frame
  bool strict = false;         ///< a missing, unreadable or wrong-size image is an error, not a skipped frame
};

/// @brief Totals of a run.
struct TrackSummary {
  std::size_t frames = 0;
  std::size_t frames_skipped = 0;  ///< missing, unreadable or wrong-size images (warned)
  std::size_t observations = 0;
  double mean_features = 0.0;
  double mean_stereo = 0.0;
  double mean_ms = 0.0;
};

/// @brief Run the tracker over the dataset; throws on bad input (message names the file).
TrackSummary run_tracking(const TrackOptions& options);

}  // namespace vid::app
