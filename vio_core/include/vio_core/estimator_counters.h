#pragma once
/// @file estimator_counters.h
/// @brief The estimator's event counters and records (summary.json, docs/formats.md §2).

#include <Eigen/Core>
#include <string>
#include <vector>

#include "types/measurements.h"
#include "vio_core/flight_phase.h"

namespace vid {

/// @brief A time span [first, last] of consecutive events.
struct TimeSpan {
  TimeNs first_ns = 0;
  TimeNs last_ns = 0;
};

/// @brief A force step found by the detector (force_jump.h).
struct ForceJumpRecord {
  TimeNs t_ns = 0;        ///< newest sample of the window
  int window = 0;         ///< samples it was estimated from
  double size_mps2 = 0.0; ///< |mean innovation| of the window
};

/// @brief A change of flight phase (flight_phase.h): lift-off or touchdown.
struct FlightPhaseRecord {
  TimeNs t_ns = 0;
  FlightPhase to = FlightPhase::kUnknown;  ///< kAirborne: lift-off, kLanded: touchdown
};

/// @brief An initialization (docs/notes/initialization.md): how and when.
struct InitRecord {
  TimeNs t_ns = 0;
  std::string how;  ///< "still" (still/hover window), "in_flight" (camera window), "groundtruth"
};

/// @brief Event counters.
struct EstimatorCounters {
  std::vector<InitRecord> inits;  ///< every (re-)initialization
  long imu_samples = 0;
  long accel_updates = 0;     ///< accelerometer samples applied one by one at full weight
  /// Samples the chi2 gate held back and no force jump used: final once a sample has left
  /// the detector's window (force_jump_window samples later) or at finish().
  long accel_rejected = 0;
  long accel_used_in_jumps = 0;  ///< past the gate, then used at full weight in a jump's estimate
  /// Past the gate, applied down-weighted (accel_gate_downweight) and used by no force jump;
  /// final like accel_rejected.
  long accel_downweighted = 0;
  std::vector<TimeSpan> accel_downweighted_spans;  ///< down-weighted samples less than 50 ms apart joined
  long force_jumps = 0;
  std::vector<TimeSpan> accel_rejected_spans;  ///< rejected samples less than 50 ms apart joined
  std::vector<ForceJumpRecord> force_jump_events;
  long rotor_gap_samples = 0;  ///< IMU samples propagated with held thrust
  long imu_gaps = 0;
  long frames = 0;
  long frames_skipped = 0;      ///< frames before init or behind the filter time
  long visual_updates = 0;
  long features_used = 0;
  long features_rejected = 0;   ///< chi2 + triangulation
  long features_rejected_chi2 = 0;
  long features_too_short = 0;
  long zero_velocity_updates = 0;  ///< frames whose window showed no parallax (one camera, or landed)
  long zero_velocity_updates_landed = 0;  ///< of those, while landed (any camera count)
  long observations_without_norm = 0;
  double landed_s = 0.0;    ///< time classified landed (flight_phase.h) [s]
  double airborne_s = 0.0;  ///< time classified airborne [s]
  std::vector<FlightPhaseRecord> flight_phase_events;  ///< lift-offs and touchdowns
  long starvation_episodes = 0;  ///< health_monitor.h: no feature used for health_starvation_s
  double starved_s = 0.0;        ///< total time starving [s]
  /// Largest fraction of tested features that failed the chi2 gate over one health window
  /// (windows with at least health_min_tested_features); the out-of-band test's margin.
  double max_chi2_rejected_fraction = 0.0;
  /// Noise fit (docs/notes/real-sensors.md, "Noise that does not fit the data"): per body axis, the sum of the
  /// accelerometer innovations' r_i^2 / S_ii (mean 1 when the noise model fits) ...
  Eigen::Vector3d accel_nis_sum = Eigen::Vector3d::Zero();
  long accel_nis_count = 0;
  /// ... and the visual features' chi2 over their degrees of freedom (features used).
  double visual_chi2_sum = 0.0;
  long visual_dof_sum = 0;
  long accel_noise_inflated = 0;  ///< accelerometer samples with the vibration-aware noise above nominal

  /// @brief Add another run piece's counts (a re-initialized estimator's): sums, event lists
  /// appended, the largest chi2-rejected fraction kept.
  void merge(const EstimatorCounters& b);
};

}  // namespace vid
