#pragma once
/// @file cli.h
/// @brief Command-line parsing shared by every program (issue #26): a usage error is one line
/// "PROGRAM: error: ... (see --help)" and exit code 2, never CLI11's own codes (105-114) or its
/// second "Run with --help" line. The error type itself (vid::system::UsageError) and the
/// --start/--end check live in vid_system/usage_error.h: library code throws them too.

#include <optional>

#include <CLI/CLI.hpp>

#include "vid_system/usage_error.h"

namespace vid::app {

/// @brief Parse argv. Returns the exit code when the program should stop at once (--help: 0);
/// nullopt to go on. Throws vid::system::UsageError on any parse error.
std::optional<int> parse_cli(CLI::App& app, int argc, char** argv);

}  // namespace vid::app
