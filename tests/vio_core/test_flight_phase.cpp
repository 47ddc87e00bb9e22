/// Flight phase from the estimated ground reaction (vio_core/flight_phase.h): thresholds,
/// hysteresis, hold time and reset.
#include <gtest/gtest.h>

#include "vio_core/flight_phase.h"

namespace vid {
namespace {

constexpr TimeNs kDt = 2'500'000;  // 400 Hz

Eigen::Vector3d up(double a) { return {0.1, -0.2, a}; }

// Feed a constant force for `seconds` starting at t; returns the time after the last sample.
TimeNs feed(FlightPhaseClassifier& c, TimeNs t, double seconds, double a_up) {
  const TimeNs end = t + seconds_to_ns(seconds);
  for (; t < end; t += kDt) c.update(t, up(a_up));
  return t;
}

TEST(FlightPhase, FirstSampleDecidesOnTheGroundOrInTheAir) {
  EstimatorParams p;
  FlightPhaseClassifier ground(p), air(p), between(p);
  EXPECT_EQ(ground.phase(), FlightPhase::kUnknown);
  EXPECT_EQ(ground.update(0, up(9.81)), FlightPhase::kLanded);   // rotors stopped: g up
  EXPECT_EQ(air.update(0, up(0.2)), FlightPhase::kAirborne);      // hover
  EXPECT_EQ(between.update(0, up(0.4 * 9.81)), FlightPhase::kAirborne);  // rotors carry most
}

TEST(FlightPhase, AChangeMustHoldForTheHoldTime) {
  EstimatorParams p;  // hold 0.1 s
  FlightPhaseClassifier c(p);
  TimeNs t = feed(c, 0, 1.0, 9.81);
  ASSERT_EQ(c.phase(), FlightPhase::kLanded);
  t = feed(c, t, 0.05, 0.0);  // a 50 ms dip (a bump) does not lift it off
  EXPECT_EQ(c.phase(), FlightPhase::kLanded);
  t = feed(c, t, 0.5, 9.81);
  const TimeNs lift = t;
  for (; c.phase() == FlightPhase::kLanded && t < lift + seconds_to_ns(1.0); t += kDt) c.update(t, up(0.0));
  EXPECT_EQ(c.phase(), FlightPhase::kAirborne);
  EXPECT_NEAR(ns_to_s(t - lift), 0.1, 2.0 * ns_to_s(kDt)) << "lift-off declared after the hold time";
}

TEST(FlightPhase, BetweenTheThresholdsThePhaseStays) {
  EstimatorParams p;  // landed at >= 0.5 g, airborne below 0.25 g
  FlightPhaseClassifier c(p);
  TimeNs t = feed(c, 0, 0.5, 9.81);
  t = feed(c, t, 2.0, 0.35 * 9.81);  // spinning up: the ground still carries 35 %
  EXPECT_EQ(c.phase(), FlightPhase::kLanded);
  t = feed(c, t, 0.5, 0.1);
  EXPECT_EQ(c.phase(), FlightPhase::kAirborne);
  t = feed(c, t, 2.0, 0.35 * 9.81);  // a 35 % upward pull in the air is not a touchdown
  EXPECT_EQ(c.phase(), FlightPhase::kAirborne);
  feed(c, t, 0.5, 0.9 * 9.81);
  EXPECT_EQ(c.phase(), FlightPhase::kLanded);
}

TEST(FlightPhase, ResetForgetsThePhase) {
  EstimatorParams p;
  FlightPhaseClassifier c(p);
  feed(c, 0, 0.5, 9.81);
  c.reset();
  EXPECT_EQ(c.phase(), FlightPhase::kUnknown);
  EXPECT_EQ(c.update(seconds_to_ns(1.0), up(0.0)), FlightPhase::kAirborne);
  EXPECT_EQ(to_string(FlightPhase::kLanded), "landed");
  EXPECT_EQ(to_string(FlightPhase::kAirborne), "airborne");
  EXPECT_EQ(to_string(FlightPhase::kUnknown), "unknown");
}

}  // namespace
}  // namespace vid
