#pragma once
/// @file flight_phase.h
/// @brief Landed or airborne, from the estimate alone (dynamics mode).
///
/// On the ground the accelerometer reads gravity while the rotors carry less than the weight;
/// the dynamics model explains the difference as an external force: the ground reaction,
/// F_W ~ (g - T/m) up. So the estimate itself says whether the ground carries the vehicle: the
/// phase is *landed* once the upward external force carries at least `landed_weight_fraction`
/// of the weight for `flight_phase_hold_s`, and *airborne* once it falls below
/// `airborne_weight_fraction` for as long (hysteresis: a bump or a noisy sample does not
/// toggle it). It is a statement about support, not contact: a vehicle that touches down
/// with its rotors still carrying the weight is airborne until they spin down, and a strong
/// upward pull (a tether lifting it) would read as landed. No ground truth is used.

#include <Eigen/Core>
#include <string>

#include "types/measurements.h"
#include "vio_core/estimator_params.h"

namespace vid {

/// @brief What carries the vehicle: unknown (before initialization or in imu mode), the
/// ground, or the rotors.
enum class FlightPhase { kUnknown, kLanded, kAirborne };
/// @brief "unknown" / "landed" / "airborne".
std::string to_string(FlightPhase p);

/// @brief Hysteresis classifier of the flight phase from the estimated world-frame force.
class FlightPhaseClassifier {
 public:
  explicit FlightPhaseClassifier(const EstimatorParams& p);
  /// @brief Feed the estimate at time t: external force in W, mass-normalized [m/s^2].
  /// Returns the phase after this sample.
  FlightPhase update(TimeNs t_ns, const Eigen::Vector3d& F_W);
  FlightPhase phase() const { return phase_; }
  /// @brief Start over (re-initialization).
  void reset();

 private:
  double landed_up_;    ///< [m/s^2] upward force that makes it landed
  double airborne_up_;  ///< [m/s^2] below this it is airborne
  TimeNs hold_ns_;
  FlightPhase phase_ = FlightPhase::kUnknown;
  FlightPhase candidate_ = FlightPhase::kUnknown;
  TimeNs candidate_since_ = 0;
};

}  // namespace vid
