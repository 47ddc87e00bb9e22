#pragma once
/// @file view_launch.h
/// @brief The Python tools a C++ program hands work to, always through the installed `vid-eval`
/// program (never a script path): `--rerun PATH` of vid_run / vid_live (`vid-eval view RUN_DIR
/// --rrd PATH`, eval/README.md) and the mass study's figures (`vid-eval massid-plots`,
/// `vid-eval elm-plots`).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace vid::app {

/// @brief Where `vid-eval` is: $VID_EVAL, else on PATH, else the repository's .venv next to the
/// build (<exe>/../../.venv/bin); nullopt when none exists.
std::optional<std::filesystem::path> find_vid_eval(const char* argv0);

/// @brief Run `vid-eval ARGS...` (argv0: this program's, to find vid-eval) and wait for it.
/// @throws std::runtime_error with one line, prefixed by @p context, when vid-eval is missing
/// or fails (its own message is on stderr above)
void run_vid_eval(const char* argv0, const std::vector<std::string>& args, const std::string& context);

/// @brief Run `vid-eval view RUN_DIR [--dataset DATASET] --rrd RRD` and wait for it.
/// @throws std::runtime_error with one line when vid-eval is missing or fails
void write_rerun_recording(const char* argv0, const std::filesystem::path& run_dir,
                           const std::optional<std::filesystem::path>& dataset, const std::filesystem::path& rrd);

}  // namespace vid::app
