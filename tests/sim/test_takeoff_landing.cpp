/// @file test_takeoff_landing.cpp
/// @brief Flights that start and end on the ground (issue #29): the vehicle rests truly still
/// on its gear, the rotors read exactly 0 while stopped, force0 is the ground reaction, one
/// lift-off and one touchdown happen where the contact says, the touchdown is soft and
/// force0's rate columns agree with differences of force0.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "sim_test_util.h"

namespace vid::sim::test {
namespace {

/// One simulated flight kept for all tests of this file (noise on or off).
struct Flight {
  Scenario sc;
  std::unique_ptr<Simulator> sim;
  Recording rec;
  double time_s(TimeNs t) const { return static_cast<double>(t - sc.start_time_ns) * 1e-9; }
  const TakeoffLandingPlan& plan() const { return *sim->takeoff_landing_plan(); }
  double end_s() const { return sc.duration_s; }
};

const Flight& flight(const std::string& preset, bool noise, double duration_s = 0.0) {
  static std::map<std::tuple<std::string, bool, double>, std::unique_ptr<Flight>> cache;
  auto& slot = cache[{preset, noise, duration_s}];
  if (!slot) {
    slot = std::make_unique<Flight>();
    slot->sc = load_scenario(preset_path(preset));
    slot->sc.noise = noise;
    if (duration_s > 0.0) slot->sc.duration_s = slot->sc.trajectory.duration_s = duration_s;
    slot->sc.cameras.cameras.clear();
    slot->sim = std::make_unique<Simulator>(slot->sc);
    slot->sim->run(slot->rec);
  }
  return *slot;
}

/// Contact phase transitions: (time, new phase).
std::vector<std::pair<double, FlightPhase>> transitions(const Flight& f) {
  std::vector<std::pair<double, FlightPhase>> out;
  for (std::size_t i = 1; i < f.rec.phase.size(); ++i) {
    if (f.rec.phase[i].phase != f.rec.phase[i - 1].phase) out.emplace_back(f.time_s(f.rec.phase[i].t_ns), f.rec.phase[i].phase);
  }
  return out;
}

/// The two rest windows: before arming, and the last rest_end_s.
bool at_rest(const Flight& f, double t) {
  return t < f.plan().arm_s - 1e-9 || t > f.end_s() - f.sc.takeoff_landing.rest_end_s + 1e-9;
}

/// Settled: before arming, and from 0.5 s into the final rest (the run-down of the rotors
/// leaves a transient of the gear that decays at >= 57 /s).
bool settled(const Flight& f, double t) {
  return t < f.plan().arm_s - 1e-9 || t > f.end_s() - f.sc.takeoff_landing.rest_end_s + 0.5;
}

/// Lowest gear foot [m, W z] (negative: compressed into the floor).
double lowest_foot_z(const Flight& f, const dynamics::QuadrotorState& x) {
  double z = INFINITY;
  for (const Eigen::Vector3d& r : f.sim->environment().ground()->feet_I()) z = std::min(z, (x.p_WI + x.q_WI * r).z());
  return z;
}

TEST(TakeoffLanding, RestingVehicleIsTrulyStill) {
  const Flight& f = flight("takeoff_landing_short", false);
  const GroundContactConfig& g = f.sc.environment.ground;
  const double m = f.sc.vehicle.mass_kg, gravity = f.sc.vehicle.gravity;
  const double sag = m * gravity / g.stiffness_N_per_m;
  int n = 0;
  for (const TruthSample& s : f.rec.truth) {
    const double t = f.time_s(s.t_ns);
    EXPECT_GT(lowest_foot_z(f, s.state), -3e-3) << "gear compressed more than 3 mm at t = " << t;
    if (!settled(f, t)) continue;
    ++n;
    ASSERT_LT(s.state.v_WI.norm(), 1e-9) << "t = " << t;
    ASSERT_LT(s.state.w_I.norm(), 1e-9) << "t = " << t;
    ASSERT_NEAR(s.state.p_WI.z(), g.gear_length_m - sag, 1e-6) << "t = " << t;
    EXPECT_NEAR(s.state.p_WI.z(), 0.110, 1e-4);  // the IMU sits at 0.11 m, as on the real vehicle
  }
  EXPECT_GE(n, (2 + 1.5) * 200 - 2);  // settled 2 s + 1.5 s at 200 Hz
  // The accelerometer reads gravity (up, level vehicle) plus its constant bias, nothing else.
  int n_imu = 0;
  for (const ImuSample& s : f.rec.imu) {
    if (!settled(f, f.time_s(s.t_ns))) continue;
    ++n_imu;
    ASSERT_LT((s.accel_I - f.sc.imu.initial_accel_bias - Eigen::Vector3d(0, 0, gravity)).norm(), 1e-9);
    ASSERT_LT((s.gyro_I - f.sc.imu.initial_gyro_bias).norm(), 1e-12);
  }
  EXPECT_GE(n_imu, (2 + 1.5) * 400 - 2);
}

TEST(TakeoffLanding, RotorSpeedsAreExactlyZeroWhileStopped) {
  const Flight& f = flight("takeoff_landing_short", true);
  int zero_rows = 0, spinning_rows = 0;
  for (const RotorSample& s : f.rec.rotor) {
    const double t = f.time_s(s.t_ns);
    for (double n : s.speeds) ASSERT_GE(n, 0.0) << "a tachometer never reads below 0 (t = " << t << ")";
    if (at_rest(f, t)) {
      for (double n : s.speeds) ASSERT_EQ(n, 0.0) << "stopped rotor at t = " << t;
      ++zero_rows;
    } else if (t > f.plan().spin_up_end_s && t < f.plan().touchdown_s) {
      for (double n : s.speeds) ASSERT_GT(n, 1000.0) << "t = " << t;
      ++spinning_rows;
    }
  }
  EXPECT_GT(zero_rows, 2 * 100 * 2 - 5);  // 2 s + 2 s at 100 Hz
  EXPECT_GT(spinning_rows, 1000);
  // The true speeds are exactly 0 too, and they start turning only when armed.
  for (const TruthSample& s : f.rec.truth) {
    const double t = f.time_s(s.t_ns);
    if (t <= f.plan().arm_s || at_rest(f, t)) {
      ASSERT_EQ(s.state.rotor_speeds.cwiseAbs().maxCoeff(), 0.0) << t;
    }
  }
}

TEST(TakeoffLanding, Force0IsTheGroundReactionAtRest) {
  // No other force acts in takeoff_landing_short: force0 is the ground reaction, m g up.
  const Flight& f = flight("takeoff_landing_short", false);
  const double mg = f.sc.vehicle.mass_kg * f.sc.vehicle.gravity;
  for (std::size_t i = 0; i < f.rec.force.size(); ++i) {
    const ForceSample& s = f.rec.force[i];
    const double t = f.time_s(s.t_ns);
    ASSERT_LT((s.f_W_N - f.rec.truth[i].ground.f_W).norm(), 1e-12) << "force0 = ground reaction, t = " << t;
    if (!settled(f, t)) continue;
    ASSERT_LT((s.f_W_N - Eigen::Vector3d(0, 0, mg)).norm(), 1e-9) << "t = " << t;
    ASSERT_LT(s.df_W_Nps.norm(), 1e-6) << "t = " << t;
  }
}

TEST(TakeoffLanding, FrictionHoldsARopeAtRest) {
  // vid17_like_ground: the rope pulls ~4 N sideways on the resting vehicle; the gear's
  // friction carries it (no creep), so force0 (rope + ground) is exactly the weight's reaction.
  const Flight& f = flight("vid17_like_ground", false, 40.0);
  const double mg = f.sc.vehicle.mass_kg * f.sc.vehicle.gravity;
  const Eigen::Vector3d p0 = f.rec.truth.front().state.p_WI;
  int n = 0;
  for (std::size_t i = 0; i < f.rec.truth.size(); ++i) {
    const TruthSample& s = f.rec.truth[i];
    const double t = f.time_s(s.t_ns);
    if (t >= f.plan().arm_s) break;
    ++n;
    const Eigen::Vector3d rope = f.sim->environment().rope_force_W(s.state);
    ASSERT_GT(rope.head<2>().norm(), 3.0);
    ASSERT_LT((s.ground.f_W.head<2>() + rope.head<2>()).norm(), 1e-6) << "friction = -rope, t = " << t;
    ASSERT_EQ(s.ground.feet_sliding, 0) << t;
    ASSERT_LT((s.state.p_WI - p0).norm(), 1e-9) << "the vehicle creeps, t = " << t;
    ASSERT_LT((f.rec.force[i].f_W_N - Eigen::Vector3d(0, 0, mg)).norm(), 1e-6) << t;
  }
  EXPECT_GT(n, 900);
}

TEST(TakeoffLanding, OneLiftOffAndOneTouchdownWhereTheContactSays) {
  const Flight& f = flight("takeoff_landing_short", false);
  ASSERT_EQ(f.rec.phase.size(), f.rec.truth.size());
  for (std::size_t i = 0; i < f.rec.phase.size(); ++i) {
    const TruthSample& s = f.rec.truth[i];
    ASSERT_EQ(f.rec.phase[i].t_ns, s.t_ns);
    const bool feet_down = lowest_foot_z(f, s.state) < 0.0;
    ASSERT_EQ(f.rec.phase[i].phase == FlightPhase::kOnGround, feet_down) << f.time_s(s.t_ns);
    ASSERT_EQ(s.ground.on_ground(), feet_down);
    if (!feet_down) {
      ASSERT_EQ(s.ground.f_W.norm(), 0.0) << "airborne: no ground force at all";
    }
  }
  const auto tr = transitions(f);
  ASSERT_EQ(tr.size(), 2u) << "expected exactly one lift-off and one touchdown";
  EXPECT_EQ(tr[0].second, FlightPhase::kAirborne);
  EXPECT_EQ(tr[1].second, FlightPhase::kOnGround);
  const TakeoffLandingPlan& P = f.plan();
  EXPECT_GT(tr[0].first, P.spin_up_s);
  EXPECT_LT(tr[0].first, P.spin_up_end_s + 0.2) << "lift-off must follow the spin-up";
  EXPECT_NEAR(tr[1].first, P.touchdown_s, 0.3) << "touchdown far from the planned one";
  // Lift-off happens when the thrust exceeds the weight: at the first airborne sample the
  // vertical thrust carries the vehicle.
  const double mg = f.sc.vehicle.mass_kg * f.sc.vehicle.gravity;
  for (const TruthSample& s : f.rec.truth) {
    if (f.time_s(s.t_ns) < tr[0].first - 1e-9) continue;
    EXPECT_GT((s.state.q_WI * s.forces.thrust_I).z(), mg);
    break;
  }
  // The climb reaches the flight height.
  double z_max = 0.0;
  for (const TruthSample& s : f.rec.truth) z_max = std::max(z_max, s.state.p_WI.z());
  EXPECT_NEAR(z_max, 1.2, 0.05);
}

TEST(TakeoffLanding, TouchdownIsSoft) {
  const Flight& f = flight("takeoff_landing_short", false);
  const auto tr = transitions(f);
  ASSERT_EQ(tr.size(), 2u);
  const double t_td = tr[1].first;
  double vz_td = 0.0, deepest = 0.0, peak_N = 0.0;
  bool first = true;
  for (const TruthSample& s : f.rec.truth) {
    const double t = f.time_s(s.t_ns);
    if (t < t_td - 1e-9) continue;
    if (first) vz_td = s.state.v_WI.z(), first = false;
    deepest = std::min(deepest, lowest_foot_z(f, s.state));
    peak_N = std::max(peak_N, s.ground.normal_N);
    if (t > t_td + 0.5) {
      EXPECT_LT(s.state.v_WI.norm(), 0.01) << "still moving after touchdown, t = " << t;
    }
  }
  EXPECT_LT(vz_td, -0.1) << "the vehicle came down";
  EXPECT_GT(vz_td, -0.5) << "touchdown faster than 0.5 m/s";
  EXPECT_GT(deepest, -3e-3) << "gear compressed beyond 3 mm";
  const double mg = f.sc.vehicle.mass_kg * f.sc.vehicle.gravity;
  EXPECT_LT(peak_N, 8.0 * mg) << "touchdown harder than 8 g";
}

/// Central differences of force0 at 200 Hz against its rate columns, away from contact
/// events (where the force has kinks or impacts shorter than the sample spacing).
void check_rate_columns(const Flight& f, double touchdown_settle_s) {
  const auto tr = transitions(f);
  ASSERT_EQ(tr.size(), 2u);
  const auto& F = f.rec.force;
  int checked = 0, ground_checked = 0, bad = 0;
  double worst = 0.0;
  for (std::size_t i = 1; i + 1 < F.size(); ++i) {
    const double t = f.time_s(F[i].t_ns);
    if (std::abs(t - tr[0].first) < 0.05 || (t > tr[1].first - 0.05 && t < tr[1].first + touchdown_settle_s)) continue;
    // Stick <-> slide or load changes of a foot inside the stencil are kinks too.
    const auto& a = f.rec.truth[i - 1].ground;
    const auto& c = f.rec.truth[i + 1].ground;
    if (a.feet_sliding != c.feet_sliding || a.feet_loaded != c.feet_loaded) continue;
    const double dt = static_cast<double>(F[i + 1].t_ns - F[i - 1].t_ns) * 1e-9;
    const Eigen::Vector3d fd = (F[i + 1].f_W_N - F[i - 1].f_W_N) / dt;
    const double err = (fd - F[i].df_W_Nps).norm();
    ++checked;
    if (f.rec.truth[i].ground.normal_N > 0.0 && F[i].df_W_Nps.norm() > 1.0) ++ground_checked;
    if (err > 0.02 * F[i].df_W_Nps.norm() + 0.05) ++bad;
    worst = std::max(worst, err);
  }
  EXPECT_GT(ground_checked, 50) << "the spin-up's falling ground reaction must be among the checked samples";
  EXPECT_LE(bad, checked / 200) << bad << " of " << checked << " rate samples off (worst " << worst << " N/s)";
}

TEST(TakeoffLanding, ForceRateColumnsMatchDifferences) {
  check_rate_columns(flight("takeoff_landing_short", false), 1.0);
}

TEST(TakeoffLanding, ForceRateColumnsMatchDifferencesWithARope) {
  check_rate_columns(flight("vid17_like_ground", false, 40.0), 1.0);
}

TEST(TakeoffLanding, RestsAtBothEndsForTheConfiguredTimes) {
  // The timeline keeps the promises of the preset: rotors stopped for rest_start_s and for the
  // last rest_end_s (checked above), and everything in between flies.
  const Flight& f = flight("takeoff_landing", false);
  const auto tr = transitions(f);
  ASSERT_EQ(tr.size(), 2u);
  EXPECT_GT(tr[0].first, 5.0 + 1.0);  // 5 s at rest, 1 s idle
  EXPECT_LT(tr[0].first, 5.0 + 1.0 + 0.7);
  const double last_spin = [&] {
    double t_last = 0.0;
    for (const RotorSample& s : f.rec.rotor) {
      if (Eigen::Map<const Eigen::VectorXd>(s.speeds.data(), static_cast<Eigen::Index>(s.speeds.size())).maxCoeff() > 0.0)
        t_last = f.time_s(s.t_ns);
    }
    return t_last;
  }();
  EXPECT_LE(last_spin, f.end_s() - 5.0) << "rotors must stand still for the last 5 s";
  EXPECT_GT(last_spin, f.end_s() - 5.5);
  EXPECT_LT(tr[1].first, last_spin - 1.0) << "spin-down happens on the ground";
}

}  // namespace
}  // namespace vid::sim::test
