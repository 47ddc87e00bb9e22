/// @file estimator_counters.cpp
/// @brief EstimatorCounters::merge (estimator_counters.h).
#include "vio_core/estimator_counters.h"

#include <algorithm>

namespace vid {

void EstimatorCounters::merge(const EstimatorCounters& b) {
  EstimatorCounters& a = *this;
  a.imu_samples += b.imu_samples;
  a.inits.insert(a.inits.end(), b.inits.begin(), b.inits.end());
  a.accel_updates += b.accel_updates;
  a.accel_rejected += b.accel_rejected;
  a.accel_used_in_jumps += b.accel_used_in_jumps;
  a.accel_downweighted += b.accel_downweighted;
  a.accel_downweighted_spans.insert(a.accel_downweighted_spans.end(), b.accel_downweighted_spans.begin(),
                                    b.accel_downweighted_spans.end());
  a.force_jumps += b.force_jumps;
  a.accel_rejected_spans.insert(a.accel_rejected_spans.end(), b.accel_rejected_spans.begin(),
                                b.accel_rejected_spans.end());
  a.force_jump_events.insert(a.force_jump_events.end(), b.force_jump_events.begin(), b.force_jump_events.end());
  a.rotor_gap_samples += b.rotor_gap_samples;
  a.imu_gaps += b.imu_gaps;
  a.frames += b.frames;
  a.frames_skipped += b.frames_skipped;
  a.visual_updates += b.visual_updates;
  a.features_used += b.features_used;
  a.features_rejected += b.features_rejected;
  a.features_rejected_chi2 += b.features_rejected_chi2;
  a.features_too_short += b.features_too_short;
  a.zero_velocity_updates += b.zero_velocity_updates;
  a.zero_velocity_updates_landed += b.zero_velocity_updates_landed;
  a.starvation_episodes += b.starvation_episodes;
  a.starved_s += b.starved_s;
  a.max_chi2_rejected_fraction = std::max(a.max_chi2_rejected_fraction, b.max_chi2_rejected_fraction);
  a.observations_without_norm += b.observations_without_norm;
  a.landed_s += b.landed_s;
  a.airborne_s += b.airborne_s;
  a.flight_phase_events.insert(a.flight_phase_events.end(), b.flight_phase_events.begin(),
                               b.flight_phase_events.end());
  a.accel_nis_sum += b.accel_nis_sum;
  a.accel_nis_count += b.accel_nis_count;
  a.visual_chi2_sum += b.visual_chi2_sum;
  a.visual_dof_sum += b.visual_dof_sum;
  a.accel_noise_inflated += b.accel_noise_inflated;
}

}  // namespace vid
