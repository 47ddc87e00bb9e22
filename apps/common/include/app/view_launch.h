#pragma once
/// @file view_launch.h
/// @brief `--rerun PATH` of vid_run / vid_live: after the run, its output folder is logged to a
/// Rerun recording by the Python tool (`vid-eval view RUN_DIR --rrd PATH`, eval/README.md).

#include <filesystem>
#include <optional>
#include <string>

namespace vid::app {

/// @brief Where `vid-eval` is: $VID_EVAL, else on PATH, else the repository's .venv next to the
/// build (<exe>/../../.venv/bin); nullopt when none exists.
std::optional<std::filesystem::path> find_vid_eval(const char* argv0);

/// @brief Run `vid-eval view RUN_DIR [--dataset DATASET] --rrd RRD` and wait for it.
/// @throws std::runtime_error with one line when vid-eval is missing or fails
void write_rerun_recording(const char* argv0, const std::filesystem::path& run_dir,
                           const std::optional<std::filesystem::path>& dataset, const std::filesystem::path& rrd);

}  // namespace vid::app
