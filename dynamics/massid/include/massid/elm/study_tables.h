#pragma once
/// @file study_tables.h
/// @brief Markdown + CSV writers of the data-driven study's tables (seed tables 1-3) and the
/// per-run series behind the figure 13-17 analogs.

#include <filesystem>
#include <string>
#include <vector>

#include "massid/elm/study.h"

namespace vid::massid::elm {

/// @brief Which sweep a table shows (decides the key column).
enum class SweepKind { kHidden, kLambda, kTrainingSets, kMethods };

/// @brief Write DIR/<stem>.csv (one line per row, every field) and DIR/<stem>.md (a
/// Markdown table per trajectory, methods side by side as in the seed).
/// @throws std::runtime_error naming the file when it cannot be written
void write_study_table(const std::filesystem::path& dir, const std::string& stem,
                       const std::string& title, SweepKind kind,
                       const std::vector<StudyRow>& rows);

/// @brief One test run's series: t, truth and one column per method.
/// @throws std::runtime_error naming the file when it cannot be written
void write_series_csv(const std::filesystem::path& file, const MassIdRun& run,
                      const std::vector<std::string>& methods,
                      const std::vector<std::vector<double>>& estimates);

}  // namespace vid::massid::elm
