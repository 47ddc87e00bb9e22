#pragma once
/// @file cli.h
/// @brief Command-line parsing shared by every program (issue #26): a usage error is one line
/// "PROGRAM: error: ... (see --help)" and exit code 2, never CLI11's own codes (105-114) or its
/// second "Run with --help" line. Also the one check of a --start/--end window against the data.

#include <optional>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

namespace vid::app {

/// @brief A command-line mistake: vid::app::run_main prints it in one line and returns 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// @brief Parse argv. Returns the exit code when the program should stop at once (--help: 0);
/// nullopt to go on. Throws UsageError on any parse error.
std::optional<int> parse_cli(CLI::App& app, int argc, char** argv);

/// @brief Check a window [start_s, end_s] (seconds after the data's first measurement;
/// no end_s: to the end) against data that span span_s seconds. Throws UsageError naming the
/// flag and the data's actual span when start is negative or past the data, end is not after
/// start, or end lies past the data's end.
void check_window(double start_s, std::optional<double> end_s, double span_s, const std::string& data);

}  // namespace vid::app
