#pragma once
/// @file study_io.h
/// @brief Files of `vid_massid run` / `report`: OUT/runs.csv (one row per run x method),
/// OUT/estimates/<trajectory>/<profile>/run_NNN.csv (per-sample inputs, truth and every
/// method's estimate), and the per-trajectory tables of the seed's figures 7-11.

#include <filesystem>
#include <string>
#include <vector>

#include "massid/filters/study_runner.h"

namespace vid::massid {

/// @brief One row of OUT/runs.csv.
struct RunRow {
  std::string trajectory, profile, method;
  int index = 0;
  int samples = 0;
  double rmspe_pct = 0.0;
  double mean_update_ms = 0.0;      ///< wall
  double mean_update_cpu_ms = 0.0;  ///< thread CPU (what the tables show)
};

/// @brief Header line of OUT/runs.csv.
std::string runs_csv_header();
/// @brief Rows of one run result (one per method) as CSV lines.
std::vector<std::string> runs_csv_lines(const RunResult& r);
/// @brief Write OUT/estimates/<trajectory>/<profile>/run_NNN.csv:
/// t,mass_true,thrust_cmd,wx,wy,wz,<method>...  @throws std::runtime_error naming the file
void write_estimates_csv(const std::filesystem::path& out, const RunResult& r);
/// @brief Read OUT/runs.csv. @throws std::runtime_error "FILE:LINE: message"
std::vector<RunRow> read_runs_csv(const std::filesystem::path& file);

/// @brief Write OUT_DIR/<trajectory>.md and .csv (profile x method: mean update time [ms] and
/// mean RMSPE [%] over runs) and OUT_DIR/summary.md (all trajectories, the seed's loop anchors,
/// targets). @return the summary Markdown.
std::string write_tables(const std::vector<RunRow>& rows, const std::filesystem::path& out_dir);

}  // namespace vid::massid
