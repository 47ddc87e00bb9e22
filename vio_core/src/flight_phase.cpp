/// @file flight_phase.cpp
/// @brief Landed / airborne hysteresis on the estimated ground reaction.
#include "vio_core/flight_phase.h"

namespace vid {

std::string to_string(FlightPhase p) {
  switch (p) {
    case FlightPhase::kLanded: return "landed";
    case FlightPhase::kAirborne: return "airborne";
    case FlightPhase::kUnknown: break;
  }
  return "unknown";
}

FlightPhaseClassifier::FlightPhaseClassifier(const EstimatorParams& p)
    : landed_up_(p.landed_weight_fraction * p.gravity),
      airborne_up_(p.airborne_weight_fraction * p.gravity),
      hold_ns_(seconds_to_ns(p.flight_phase_hold_s)) {}

void FlightPhaseClassifier::reset() {
  phase_ = candidate_ = FlightPhase::kUnknown;
  candidate_since_ = 0;
}

FlightPhase FlightPhaseClassifier::update(TimeNs t_ns, const Eigen::Vector3d& F_W) {
  const double up = F_W.z();
  // The first sample decides at once (the initializer saw a still window already); later a
  // new phase must hold for hold_ns_ before it is taken.
  FlightPhase seen = phase_;
  if (up >= landed_up_) {
    seen = FlightPhase::kLanded;
  } else if (up < airborne_up_) {
    seen = FlightPhase::kAirborne;
  } else if (phase_ == FlightPhase::kUnknown) {
    seen = FlightPhase::kAirborne;  // between the thresholds: the rotors carry most of it
  }
  if (phase_ == FlightPhase::kUnknown) {
    phase_ = candidate_ = seen;
    candidate_since_ = t_ns;
    return phase_;
  }
  if (seen == phase_) {
    candidate_ = phase_;
    return phase_;
  }
  if (candidate_ != seen) {
    candidate_ = seen;
    candidate_since_ = t_ns;
  }
  if (t_ns - candidate_since_ >= hold_ns_) phase_ = seen;
  return phase_;
}

}  // namespace vid
