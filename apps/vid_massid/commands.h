#pragma once
/// @file commands.h
/// @brief Registration of vid_massid's subcommands; each is defined in its own *_cmd.cpp.
///
/// Each add_* function adds a CLI11 subcommand to `cli` and sets its callback; the callback
/// stores the program's exit code in `*exit_code` (0 ok, non-zero on failure) and throws on
/// bad input (main turns exceptions into one line on stderr, exit 1).

#include <CLI/CLI.hpp>

namespace vid::massid_app {

/// @brief `generate`: simulate the study's runs (trajectories x mass profiles x runs) as CSV.
void add_generate_command(CLI::App& cli, int* exit_code);
/// @brief `run` and `report`: run methods over a dataset, write tables and plots.
void add_run_report_commands(CLI::App& cli, int* exit_code);
/// @brief `elm-study`: the seed's tables 1-3 (hidden nodes, lambda, training sets).
void add_elm_study_command(CLI::App& cli, int* exit_code);
/// @brief `from-sequence`: simulated VID sequence folders as a study dataset (same mass profiles
/// for the study's methods and the VIO).
void add_from_sequence_command(CLI::App& cli, int* exit_code);

}  // namespace vid::massid_app
