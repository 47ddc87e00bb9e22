#pragma once
/// @file data_window.h
/// @brief A dataset's time span and the one check of a --start/--end window against it
/// (vid_run, vid_replay).

#include <filesystem>
#include <optional>

#include "io/dataset_reader.h"

namespace vid::system {

/// @brief Timestamp of the last row of a CSV (read from its tail); nullopt when unreadable.
std::optional<TimeNs> last_timestamp(const std::filesystem::path& csv);

/// @brief Span [s] from the first measurement that a reader with @p options yields to the last
/// imu0 row (the times that --start/--end count from).
double data_span_s(const std::filesystem::path& dataset, const io::ReaderOptions& options);

/// @brief Throw vid::system::UsageError (exit 2) stating the data's span when [start_s, end_s]
/// is negative, empty or outside the dataset (vid::system::check_window).
void check_dataset_window(const std::filesystem::path& dataset, const io::ReaderOptions& options, double start_s,
                          std::optional<double> end_s);

}  // namespace vid::system
