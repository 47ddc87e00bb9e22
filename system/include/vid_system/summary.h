#pragma once
/// @file summary.h
/// @brief Accumulates per-frame stage times and writes summary.json (docs/formats.md §2).

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vid_system/outputs.h"
#include "vid_system/stage_stats.h"
#include "vio_core/estimator.h"

namespace vid::system {

/// @brief Collects the per-frame stage times of a run.
class StageTimes {
 public:
  void add(const TimingRow& row);
  std::size_t frames() const { return total_.count(); }
  /// @brief {"tracking": {mean_ms, median_ms, p99_ms, max_ms}, ...}
  nlohmann::json to_json() const;

 private:
  StageStats tracking_, propagation_, accel_, msckf_, marginalization_, total_;
};

/// @brief Peak resident memory of this process [MiB].
double peak_memory_mib();

/// @brief CPU time (user + system) of this process so far [s].
double process_cpu_s();

/// @brief CPU time of the calling thread so far [ms]. Unlike wall-clock stage times it does not
/// grow when other processes compete for the cores (the machine the timings come from is shared).
double thread_cpu_ms();

/// @brief What happened to the accelerometer samples: rejected count, fraction and time spans,
/// and the force jumps (summary.json "accel"). Spans and jumps list at most 200 entries each.
nlohmann::json accel_report(const EstimatorCounters& c);

/// @brief Landed / airborne (vio_core/flight_phase.h): the phase at the end, time in each, the
/// lift-offs and touchdowns (summary.json "flight_phase"; at most 200 events listed).
nlohmann::json flight_phase_report(const EstimatorCounters& c, FlightPhase now);

/// @brief Write @p summary to DIR/summary.json (pretty, flushed).
void write_summary(const std::filesystem::path& out_dir, const nlohmann::json& summary);

}  // namespace vid::system
