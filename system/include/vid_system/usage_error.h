#pragma once
/// @file usage_error.h
/// @brief A request that cannot be met as asked (a flag, an option, a --start/--end window):
/// the programs report it as a usage error, one line and exit code 2 (apps/common app/cli.h,
/// vid::app::run_main); library code that runs a dataset throws it too.

#include <optional>
#include <stdexcept>
#include <string>

namespace vid::system {

/// @brief A command-line (or option) mistake: vid::app::run_main prints it in one line and returns 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// @brief Check a window [start_s, end_s] (seconds after the data's first measurement;
/// no end_s: to the end) against data that span span_s seconds. Throws UsageError naming the
/// flag and the data's actual span when start is negative or past the data, end is not after
/// start, or end lies past the data's end.
void check_window(double start_s, std::optional<double> end_s, double span_s, const std::string& data);

}  // namespace vid::system
