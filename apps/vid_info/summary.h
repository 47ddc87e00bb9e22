#pragma once
/// @file summary.h
/// @brief Formatting of the vid_info dataset summary (text table and JSON).

#include <string>
#include <vector>

#include "io/dataset_reader.h"

namespace vid::app {

/// @brief Everything vid_info reports about one folder.
struct DatasetSummary {
  std::string mav0;
  std::vector<io::StreamStats> streams;
  io::DatasetCalibration calibration;
};

/// @brief Human-readable table; times relative to the earliest stream start.
std::string summary_text(const DatasetSummary& s);
/// @brief Machine-readable JSON (ns integers, rates in Hz, calibration found).
std::string summary_json(const DatasetSummary& s);

}  // namespace vid::app
