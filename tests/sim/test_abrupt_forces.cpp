/// @file test_abrupt_forces.cpp
/// @brief Abrupt external forces (issue #17): tether, impacts, force steps, replayed force
/// table; the analytic force-rate ground truth against numeric differentiation; determinism;
/// the new presets parse and a short run keeps the vehicle in the room with |dF/dt| peaks far
/// above a smooth preset.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "io/errors.h"
#include "sim/environment.h"
#include "sim/render/random.h"
#include "sim_test_util.h"

namespace vid::sim::test {
namespace {

namespace fs = std::filesystem;
constexpr double kMass = 3.1015;

dynamics::QuadrotorState state(const Eigen::Vector3d& p, const Eigen::Vector3d& v, double yaw = 0.0,
                               const Eigen::Vector3d& w_I = Eigen::Vector3d::Zero()) {
  dynamics::QuadrotorState x;
  x.p_WI = p;
  x.v_WI = v;
  x.q_WI = Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  x.w_I = w_I;
  x.rotor_speeds = Eigen::VectorXd::Zero(4);
  return x;
}

RopeConfig tether(double k, double c) {
  RopeConfig t;
  t.enabled = true;
  t.anchor_W = Eigen::Vector3d::Zero();
  t.rest_length_m = 2.0;
  t.stiffness_N_per_m = k;
  t.damping_Ns_per_m = c;
  t.damping_ramp_m = 0.0;
  return t;
}

/// A scratch folder removed at scope exit.
struct Scratch {
  fs::path dir = fs::temp_directory_path() /
                 ("vid_abrupt_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
                  "_" + std::to_string(::getpid()));
  Scratch() { fs::create_directories(dir); }
  ~Scratch() { fs::remove_all(dir); }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return dir / name;
  }
};

TEST(Tether, ExactlyZeroWhileSlackHookePlusDampingWhileTautNeverPushes) {
  EnvironmentConfig cfg;
  cfg.tether = tether(300.0, 8.0);
  const SimEnvironment env(cfg, kMass, 10.0, 1);
  // Slack, even when moving outward fast: exactly zero force and rate.
  for (double r : {0.0, 0.5, 1.0, 1.999999}) {
    const auto x = state(Eigen::Vector3d(r, 0, 0), Eigen::Vector3d(5, 1, 0));
    EXPECT_EQ(env.force_W(0.0, x), Eigen::Vector3d::Zero()) << r;
    EXPECT_EQ(env.force_rate_W(0.0, x, Eigen::Vector3d(1, 2, 3)), Eigen::Vector3d::Zero()) << r;
  }
  // Taut: tension = k stretch + c d(stretch)/dt along the rope, toward the anchor.
  const auto x = state(Eigen::Vector3d(0, 2.1, 0), Eigen::Vector3d(0.3, 0.5, 0));
  EXPECT_NEAR((env.force_W(0.0, x) - Eigen::Vector3d(0, -(300.0 * 0.1 + 8.0 * 0.5), 0)).norm(), 0.0, 1e-9);
  // No damping fade: the full damping acts from the first 0.1 mm of stretch (snap).
  const auto just = state(Eigen::Vector3d(0, 0, 2.0001), Eigen::Vector3d(0, 0, 1.0));
  EXPECT_NEAR(env.tether_force_W(just).z(), -(300.0 * 1e-4 + 8.0), 1e-9);
  // Fast retraction while stretched: the damper would push, the rope goes limp instead.
  EXPECT_EQ(env.force_W(0.0, state(Eigen::Vector3d(2.1, 0, 0), Eigen::Vector3d(-10, 0, 0))), Eigen::Vector3d::Zero());
  // Random states: the force always pulls toward the anchor (or is zero), never more than k s + c max(ds/dt, 0).
  Rng rng(5);
  int taut = 0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d p(rng.uniform(-2.5, 2.5), rng.uniform(-2.5, 2.5), rng.uniform(-2.5, 2.5));
    const Eigen::Vector3d v(rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3));
    const Eigen::Vector3d f = env.force_W(0.0, state(p, v));
    const Eigen::Vector3d u = p.normalized();
    const double stretch = p.norm() - 2.0;
    if (stretch <= 0.0) {
      ASSERT_EQ(f, Eigen::Vector3d::Zero());
      continue;
    }
    taut += f.norm() > 0.0;
    ASSERT_GE(-f.dot(u), 0.0);
    ASSERT_NEAR(f.cross(u).norm(), 0.0, 1e-9);
    ASSERT_LE(f.norm(), 300.0 * stretch + 8.0 * std::max(0.0, u.dot(v)) + 1e-9);
  }
  EXPECT_GT(taut, 100);
}

TEST(Tether, KeyHasNoDampingFade) {
  try {
    load_scenario_string("forces:\n  tether: {anchor: [0, 0, 0], damping_ramp_m: 0.02}\n", "t.yaml");
    FAIL() << "damping_ramp_m accepted for the tether";
  } catch (const io::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("forces.tether.damping_ramp_m"), std::string::npos) << e.what();
  }
}

TEST(Impacts, PulseDurationPeakAndImpulse) {
  EnvironmentConfig cfg;
  cfg.impacts.push_back(PushConfig{1.0, Eigen::Vector3d(0, 60, 0), 0.03});
  const SimEnvironment env(cfg, kMass, 10.0, 1);
  const auto x = state(Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::Zero());
  const double dt = 1e-5;
  double first = -1, last = -1, peak = 0, peak_t = 0, impulse = 0;
  for (double t = 0.9; t < 1.1; t += dt) {
    const Eigen::Vector3d f = env.force_W(t, x);
    EXPECT_EQ(f.x(), 0.0);
    if (f.norm() > 0.0) {
      if (first < 0) first = t;
      last = t;
    }
    if (f.norm() > peak) peak = f.norm(), peak_t = t;
    impulse += f.y() * dt;
  }
  EXPECT_NEAR(first, 1.0, 2 * dt);
  EXPECT_NEAR(last - first, 0.03, 3 * dt);
  EXPECT_NEAR(peak, 60.0, 1e-3);
  EXPECT_NEAR(peak_t, 1.015, 2 * dt);
  EXPECT_NEAR(impulse, 60.0 * 0.03 / 2.0, 1e-3);  // integral of a sin^2 pulse: F D / 2
  // Peak rate pi F / D (~6300 N/s) a quarter into the pulse.
  EXPECT_NEAR(env.force_rate_W(1.0075, x, Eigen::Vector3d::Zero()).y(), M_PI * 60.0 / 0.03, 1e-6);
}

TEST(Impacts, RandomOnesFollowTheirRangesAndTheSeed) {
  EnvironmentConfig cfg;
  RandomImpactsConfig& r = cfg.random_impacts;
  r.rate_per_s = 2.0;
  r.peak_min_N = 20.0;
  r.peak_max_N = 91.0;
  r.duration_min_s = 0.02;
  r.duration_max_s = 0.05;
  r.start_s = 2.0;
  const SimEnvironment a(cfg, kMass, 60.0, 11), b(cfg, kMass, 60.0, 11), c(cfg, kMass, 60.0, 12);
  const auto& ia = a.impacts();
  // Poisson count: mean 116, sd 10.8.
  EXPECT_GT(ia.size(), 70u);
  EXPECT_LT(ia.size(), 170u);
  for (std::size_t i = 0; i < ia.size(); ++i) {
    EXPECT_GE(ia[i].t_s, 2.0);
    EXPECT_LE(ia[i].t_s + ia[i].duration_s, 60.0);
    if (i > 0) {
      EXPECT_GT(ia[i].t_s, ia[i - 1].t_s);
    }
    EXPECT_GE(ia[i].duration_s, 0.02);
    EXPECT_LE(ia[i].duration_s, 0.05);
    EXPECT_GE(ia[i].force_N.norm(), 20.0 - 1e-9);
    EXPECT_LE(ia[i].force_N.norm(), 91.0 + 1e-9);
    EXPECT_EQ(ia[i].force_N.z(), 0.0);  // horizontal (wall) bumps
    ASSERT_EQ(ia[i].t_s, b.impacts()[i].t_s);
    ASSERT_EQ(ia[i].force_N, b.impacts()[i].force_N);
  }
  ASSERT_FALSE(c.impacts().empty());
  EXPECT_NE(c.impacts()[0].t_s, ia[0].t_s);
  cfg.random_impacts.directions = "up";
  const SimEnvironment up(cfg, kMass, 60.0, 11);
  ASSERT_EQ(up.impacts().size(), ia.size());  // same times, only the direction differs
  for (const PushConfig& p : up.impacts()) EXPECT_NEAR(p.force_N.normalized().z(), 1.0, 1e-12);
}

TEST(Steps, WorldFrameStaysBodyFrameRotatesWithTheVehicle) {
  EnvironmentConfig cfg;
  cfg.steps.push_back(ForceStepConfig{1.0, Eigen::Vector3d(8, 0, 0), false, 0.0});
  cfg.steps.push_back(ForceStepConfig{2.0, Eigen::Vector3d(7, 0, 0), true, 0.0});
  cfg.steps.push_back(ForceStepConfig{3.0, Eigen::Vector3d(0, 0, 5), true, 0.5});
  const SimEnvironment env(cfg, kMass, 10.0, 1);
  const Eigen::Vector3d p(0, 0, 1), v(0.2, 0, 0), a = Eigen::Vector3d::Zero();
  const auto yaw90 = state(p, v, M_PI / 2), yaw0 = state(p, v, 0.0);
  EXPECT_EQ(env.force_W(0.999, yaw90), Eigen::Vector3d::Zero());
  EXPECT_NEAR((env.force_W(1.0, yaw90) - Eigen::Vector3d(8, 0, 0)).norm(), 0.0, 1e-12);  // true step
  EXPECT_NEAR((env.force_W(2.5, yaw90) - Eigen::Vector3d(8, 7, 0)).norm(), 0.0, 1e-12);  // x_I = y_W
  EXPECT_NEAR((env.force_W(2.5, yaw0) - Eigen::Vector3d(15, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_EQ(env.force_rate_W(2.5, yaw90, a), Eigen::Vector3d::Zero());  // a true step has no finite rate
  // Linear rise: half way after rise_s / 2, slope F / rise_s.
  EXPECT_NEAR(env.force_W(3.25, yaw0).z(), 2.5, 1e-12);
  EXPECT_NEAR(env.force_rate_W(3.25, yaw0, a).z(), 10.0, 1e-12);
  EXPECT_NEAR(env.force_W(4.0, yaw0).z(), 5.0, 1e-12);
  // Spinning at 1 rad/s: the body-frame step turns, rate R (w x F_I) = yaw90 * (0, 7, 0) = (-7, 0, 0).
  const auto spin = state(p, v, M_PI / 2, Eigen::Vector3d(0, 0, 1));
  EXPECT_NEAR((env.force_rate_W(2.5, spin, a) - Eigen::Vector3d(-7, 0, 0)).norm(), 0.0, 1e-12);
}

TEST(FromFile, InterpolatesHoldsTheEndsAndIsRelativeToTheScenario) {
  Scratch s;
  s.write("f.csv", "# header\n#t_ns,Fx,Fy,Fz\n1000000000,0,0,0\n2000000000,10,-4,2\n3000000000, 10, -4, 2\n");
  const fs::path yaml = s.write("s.yaml", "base: " + preset_path("hover") + "\nforces:\n  from_file: {file: f.csv}\n");
  const Scenario sc = load_scenario(yaml);
  ASSERT_EQ(sc.environment.from_file.t_s.size(), 3u);
  const SimEnvironment env(sc.environment, kMass, 10.0, 1);
  const auto x = state(Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::Zero());
  const Eigen::Vector3d a = Eigen::Vector3d::Zero();
  EXPECT_EQ(env.force_W(0.5, x), Eigen::Vector3d::Zero());  // held before the first row
  EXPECT_NEAR((env.force_W(1.5, x) - Eigen::Vector3d(5, -2, 1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((env.force_rate_W(1.5, x, a) - Eigen::Vector3d(10, -4, 2)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((env.force_W(1.25, x) - Eigen::Vector3d(2.5, -1, 0.5)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((env.force_W(2.5, x) - Eigen::Vector3d(10, -4, 2)).norm(), 0.0, 1e-12);
  EXPECT_EQ(env.force_rate_W(2.5, x, a), Eigen::Vector3d::Zero());
  EXPECT_NEAR((env.force_W(50.0, x) - Eigen::Vector3d(10, -4, 2)).norm(), 0.0, 1e-12);  // held after
  EXPECT_EQ(env.force_rate_W(50.0, x, a), Eigen::Vector3d::Zero());
}

TEST(FromFile, BadFileGivesOneErrorNamingFileLineAndColumn) {
  Scratch s;
  const fs::path yaml = s.write("s.yaml", "base: " + preset_path("hover") + "\nforces:\n  from_file: {file: f.csv}\n");
  auto error_of = [&](const std::string& csv) -> std::string {
    s.write("f.csv", csv);
    try {
      load_scenario(yaml);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  };
  const std::string f = (s.dir / "f.csv").string();
  std::string e = error_of("#t_ns,Fx,Fy,Fz\n0,0,0,0\n1000,1,abc,0\n");
  EXPECT_NE(e.find(f + ":3: column 3 'Fy [N]': expected a number, got 'abc'"), std::string::npos) << e;
  e = error_of("0,0,0,0\n1000,1,0,0\n1000,2,0,0\n");
  EXPECT_NE(e.find(f + ":3: column 1 't_ns': times must be strictly increasing"), std::string::npos) << e;
  e = error_of("0,0,0\n");
  EXPECT_NE(e.find(f + ":1: expected 4 columns, got 3"), std::string::npos) << e;
  e = error_of("# only a header\n");
  EXPECT_NE(e.find(f + ": no data rows"), std::string::npos) << e;
  fs::remove(s.dir / "f.csv");
  try {
    load_scenario(yaml);
    FAIL() << "missing file accepted";
  } catch (const io::ConfigError& err) {
    EXPECT_NE(std::string(err.what()).find("key 'forces.from_file.file': no such file"), std::string::npos) << err.what();
  }
}

TEST(ForceRate, EverySourceMatchesNumericDifferentiationAlongAMotion) {
  // All sources at once along an analytic motion (constant acceleration and yaw rate), rate
  // against a central difference of the force wherever the force is differentiable.
  EnvironmentConfig cfg;
  cfg.rope.enabled = true;
  cfg.rope.anchor_W = Eigen::Vector3d(-3, 0, 0);
  cfg.rope.rest_length_m = 2.9;  // in the damping fade at first, then past it
  cfg.rope.stiffness_N_per_m = 8;
  cfg.rope.damping_Ns_per_m = 1.5;
  cfg.tether = tether(150.0, 6.0);
  cfg.tether.anchor_W = Eigen::Vector3d(0, -1.8, 1);
  cfg.wind = WindConfig{true, Eigen::Vector3d(1, 0.5, 0), 0.8, 1.5, 0.4};
  cfg.pushes.push_back(PushConfig{0.3, Eigen::Vector3d(4, 0, 1), 0.2});
  cfg.impacts.push_back(PushConfig{0.55, Eigen::Vector3d(0, 50, 0), 0.03});
  cfg.steps.push_back(ForceStepConfig{0.2, Eigen::Vector3d(3, 1, 0), true, 0.3});
  cfg.steps.push_back(ForceStepConfig{0.4, Eigen::Vector3d(0, 2, -1), false, 0.25});
  cfg.from_file.t_s = {0.1, 0.35, 0.7};
  cfg.from_file.f_W_N = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, -1, 3), Eigen::Vector3d(-1, 0, 1)};
  const SimEnvironment env(cfg, kMass, 5.0, 3);
  dynamics::QuadrotorParams vehicle = load_scenario(preset_path("vid17_like_short")).vehicle;
  vehicle.linear_drag = Eigen::Vector3d(0.3, 0.2, 0.1);
  const dynamics::QuadrotorModel model(vehicle);

  const Eigen::Vector3d p0(0.1, 0.3, 1.0), v0(0.4, 1.2, -0.1), a(0.5, -0.8, 0.3);
  const Eigen::Vector3d w_I(0.2, -0.1, 1.3);
  auto x_at = [&](double t) {
    dynamics::QuadrotorState x = state(p0 + v0 * t + 0.5 * a * t * t, v0 + a * t);
    x.q_WI = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ())) *
             Eigen::Quaterniond(Eigen::AngleAxisd(w_I.norm() * t, w_I.normalized()));  // constant body rate w_I
    x.w_I = w_I;
    return x;
  };
  // force0 = environment + linear rotor drag (from the model, independent of the rate code).
  auto force0 = [&](double t) { return model.forces(t, x_at(t), env).external_W(); };
  const std::vector<double> kinks = {0.1, 0.2, 0.3, 0.35, 0.4, 0.5, 0.55, 0.58, 0.65, 0.7};
  const double h = 1e-6;
  int checked = 0, tether_taut = 0;
  double worst = 0.0;
  for (double t = 0.05; t < 0.8; t += 0.00173) {
    bool near_kink = false;
    for (double k : kinks) near_kink |= std::abs(t - k) < 3 * h;
    // gust knots every 10 ms, rope / tether onsets (force jumps with the damping)
    near_kink |= std::floor((t - h) / 0.01) != std::floor((t + h) / 0.01);
    const bool taut_m = env.tether_force_W(x_at(t - h)).norm() > 0, taut_p = env.tether_force_W(x_at(t + h)).norm() > 0;
    if (near_kink || taut_m != taut_p) continue;
    tether_taut += taut_p;
    const Eigen::Vector3d numeric = (force0(t + h) - force0(t - h)) / (2 * h);
    const Eigen::Vector3d analytic = external_force_rate_W(env, vehicle, t, x_at(t), a);
    worst = std::max(worst, (numeric - analytic).norm() / (1.0 + analytic.norm()));
    ++checked;
  }
  EXPECT_GT(checked, 350);
  EXPECT_GT(tether_taut, 50);
  EXPECT_LT(worst, 1e-4);
}

/// Peak |dF/dt| and |F| of a recorded run (rate from the analytic ground truth).
struct RunPeaks {
  double rate = 0.0, force = 0.0;
};

RunPeaks peaks_of(const Simulator& sim, const Recording& rec) {
  RunPeaks out;
  for (const TruthSample& tr : rec.truth) {
    const double t = static_cast<double>(tr.t_ns - sim.scenario().start_time_ns) * 1e-9;
    const Eigen::Vector3d r =
        external_force_rate_W(sim.environment(), sim.model().params(), t, tr.state, tr.forces.accel_W);
    out.rate = std::max(out.rate, r.norm());
    out.force = std::max(out.force, tr.forces.external_W().norm());
  }
  return out;
}

/// What a short run of a preset did (noise off, no cameras).
struct RunStats {
  RunPeaks peaks;
  double worst_outside_room_m = 0.0;  ///< largest excursion beyond the room shrunk by 0.2 m
  double saturated_fraction = 0.0;    ///< ground-truth samples with a rotor at its limit
  double max_rotor_speed = 0.0;
  std::vector<double> snap_rise_N;    ///< tether: tension 0.2 s after each slack -> taut onset
  double tether_peak_N = 0.0;
  double max_jump_N = 0.0;            ///< largest |F| change between consecutive force0 samples
  double rate_median_rel_err = 1.0;   ///< analytic rate vs central difference of force0
  std::size_t samples = 0;
};

RunStats run_preset(const std::string& name, double duration_s, std::uint64_t seed = 0) {
  Scenario sc = load_scenario(preset_path(name));
  sc.noise = false;
  sc.duration_s = std::min(sc.duration_s, duration_s);
  sc.trajectory.duration_s = sc.duration_s;
  if (seed != 0) sc.seed = sc.trajectory.seed = seed;
  sc.cameras.cameras.clear();
  Simulator sim(sc);
  Recording rec;
  sim.run(rec);
  RunStats st;
  st.samples = rec.truth.size();
  st.peaks = peaks_of(sim, rec);
  const auto room = sc.scene_node["room_size"].as<std::vector<double>>();
  const auto centre = sc.scene_node["room_center"].as<std::vector<double>>();
  const dynamics::QuadrotorParams& v = sc.vehicle;
  std::size_t saturated = 0;
  const double gt_dt = 1.0 / sc.groundtruth_rate_hz;
  const auto rise_window = static_cast<std::size_t>(std::lround(0.2 / gt_dt));
  std::vector<double> tension, rel_err;
  for (const TruthSample& tr : rec.truth) {
    for (int k = 0; k < 3; ++k) {
      const double out = std::abs(tr.state.p_WI[k] - centre[k]) - (0.5 * room[k] - 0.2);
      st.worst_outside_room_m = std::max(st.worst_outside_room_m, out);
    }
    st.max_rotor_speed = std::max(st.max_rotor_speed, tr.state.rotor_speeds.maxCoeff());
    saturated += (tr.state.rotor_speeds.array() >= v.rotor_speed_max - 1e-6).any() ||
                 (tr.state.rotor_speeds.array() <= v.rotor_speed_min + 1e-6).any();
    tension.push_back(sim.environment().tether_force_W(tr.state).norm());
  }
  st.saturated_fraction = static_cast<double>(saturated) / static_cast<double>(rec.truth.size());
  for (std::size_t i = 1; i + 1 < rec.truth.size(); ++i) {
    st.tether_peak_N = std::max(st.tether_peak_N, tension[i]);
    st.max_jump_N = std::max(st.max_jump_N, (rec.force[i].f_W_N - rec.force[i - 1].f_W_N).norm());
    if (tension[i - 1] == 0.0 && tension[i] > 0.0 && i + rise_window < tension.size())
      st.snap_rise_N.push_back(*std::max_element(tension.begin() + i, tension.begin() + i + rise_window));
    if ((tension[i - 1] > 0.0) != (tension[i + 1] > 0.0) || (tension[i] > 0.0) != (tension[i + 1] > 0.0)) continue;
    const double t = static_cast<double>(rec.truth[i].t_ns - sc.start_time_ns) * 1e-9;
    const Eigen::Vector3d analytic = external_force_rate_W(sim.environment(), v, t, rec.truth[i].state,
                                                           rec.truth[i].forces.accel_W);
    const Eigen::Vector3d numeric = (rec.force[i + 1].f_W_N - rec.force[i - 1].f_W_N) / (2 * gt_dt);
    if (analytic.norm() > 1.0) rel_err.push_back((numeric - analytic).norm() / analytic.norm());
    // Once the simulator writes the rate into force0 it must be this very ground truth.
    if (rec.force[i].has_rate) {
      EXPECT_NEAR((rec.force[i].df_W_Nps - analytic).norm(), 0.0, 1e-9);
    }
  }
  if (!rel_err.empty()) {
    std::nth_element(rel_err.begin(), rel_err.begin() + rel_err.size() / 2, rel_err.end());
    st.rate_median_rel_err = rel_err[rel_err.size() / 2];
  }
  const auto [rise_lo, rise_hi] = std::minmax_element(st.snap_rise_N.begin(), st.snap_rise_N.end());
  std::printf("%s %.0f s: peak |F| %.1f N, peak |dF/dt| %.0f N/s, largest jump %.1f N, tether peak %.1f N, "
              "snaps %zu (0.2 s rise %.1f-%.1f N), outside %.2f m, max rotor %.0f (saturated %.3f %%), "
              "rate median rel err %.4f\n",
              name.c_str(), sc.duration_s, st.peaks.force, st.peaks.rate, st.max_jump_N, st.tether_peak_N,
              st.snap_rise_N.size(), st.snap_rise_N.empty() ? 0.0 : *rise_lo, st.snap_rise_N.empty() ? 0.0 : *rise_hi,
              st.worst_outside_room_m, st.max_rotor_speed, 100.0 * st.saturated_fraction, st.rate_median_rel_err);
  return st;
}

TEST(AbruptPresets, ParseWithTheVid17VehicleAndSensors) {
  const Scenario ref = load_scenario(preset_path("vid17_like"));
  for (const char* base : {"rope_snap", "impacts", "force_steps", "from_file"}) {
    for (const std::string& name : {std::string(base), std::string(base) + "_short"}) {
      SCOPED_TRACE(name);
      const Scenario s = load_scenario(preset_path(name));
      EXPECT_EQ(s.name, name);
      EXPECT_EQ(s.duration_s, name.size() > std::string(base).size() ? 25.0 : 120.0);
      EXPECT_EQ(s.vehicle.mass_kg, ref.vehicle.mass_kg);
      EXPECT_EQ(s.vehicle.rotors.size(), ref.vehicle.rotors.size());
      EXPECT_EQ(s.imu.noise.accel_noise_density, ref.imu.noise.accel_noise_density);
      EXPECT_EQ(s.cameras.cameras.size(), ref.cameras.cameras.size());
      EXPECT_EQ(s.rotor.enabled, ref.rotor.enabled);
      EXPECT_FALSE(s.environment.rope.enabled);  // only the abrupt source of the preset
    }
  }
  EXPECT_TRUE(load_scenario(preset_path("rope_snap")).environment.tether.enabled);
  EXPECT_EQ(load_scenario(preset_path("from_file")).environment.from_file.t_s.size(), 10u);
  EXPECT_GT(load_scenario(preset_path("impacts")).environment.random_impacts.rate_per_s, 0.0);
}

TEST(AbruptPresets, RopeSnapShortSnapsRepeatedlyAndStaysControllable) {
  const RunStats st = run_preset("rope_snap_short", 25.0);
  EXPECT_EQ(st.worst_outside_room_m, 0.0);
  EXPECT_LT(st.saturated_fraction, 0.01);
  ASSERT_GE(st.snap_rise_N.size(), 3u);  // slack -> taut several times
  EXPECT_GE(*std::max_element(st.snap_rise_N.begin(), st.snap_rise_N.end()), 5.0);
  EXPECT_LE(st.tether_peak_N, 40.0);
  EXPECT_GT(st.peaks.rate, 50.0);
  EXPECT_LT(st.rate_median_rel_err, 0.05);  // 200 Hz central differences vs the analytic rate
}

TEST(AbruptPresets, ShortRunsStayInTheRoomWithRatePeaksFarAboveASmoothPreset) {
  const RunStats smooth = run_preset("vid17_like_short", 25.0);
  EXPECT_EQ(smooth.worst_outside_room_m, 0.0);
  const RunStats impacts = run_preset("impacts_short", 25.0);
  const RunStats steps = run_preset("force_steps_short", 25.0);
  const RunStats file = run_preset("from_file_short", 25.0);
  for (const RunStats* s : {&impacts, &steps, &file}) {
    EXPECT_EQ(s->worst_outside_room_m, 0.0);
    EXPECT_LT(s->saturated_fraction, 0.02);
  }
  EXPECT_GT(impacts.peaks.force, 85.0);                     // the 3 g bumps
  EXPECT_GT(impacts.peaks.rate, 1000.0);                    // pi F / D
  EXPECT_GT(impacts.peaks.rate, 50.0 * smooth.peaks.rate);
  EXPECT_GE(steps.peaks.force, 10.0);
  EXPECT_GE(steps.max_jump_N, 6.2);                         // true steps: >= 2 m/s^2 in one sample
  EXPECT_GT(steps.peaks.rate, 10.0 * smooth.peaks.rate);    // the ramps (true steps have no finite rate)
  EXPECT_LT(steps.rate_median_rel_err, 0.01);               // incl. body-frame steps turning with the vehicle
  EXPECT_GT(file.peaks.force, 19.9);
  EXPECT_GT(file.max_jump_N, 19.9);                         // the 20 N step of step_pulse.csv
  EXPECT_LT(smooth.max_jump_N, 0.2);
}

TEST(AbruptPresets, SameSeedSameForcesOtherSeedOtherImpacts) {
  auto forces = [](std::uint64_t seed) {
    Scenario sc = load_scenario(preset_path("impacts_short"));
    sc.duration_s = sc.trajectory.duration_s = 6.0;
    sc.seed = sc.trajectory.seed = seed;
    sc.environment.random_impacts.rate_per_s = 2.0;  // random ones inside the 6 s
    sc.environment.random_impacts.start_s = 1.0;
    return record(sc).force;
  };
  const auto a = forces(43), b = forces(43), c = forces(44);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.size(), c.size());
  bool differs = false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].f_W_N, b[i].f_W_N) << i;
    differs |= a[i].f_W_N != c[i].f_W_N;
  }
  EXPECT_TRUE(differs);
}

/// Measurement for the documentation (config/sim/README.md): the full 120 s presets.
/// Run with --gtest_also_run_disabled_tests.
TEST(AbruptPresets, DISABLED_FullLengthPeaks) {
  for (const char* name : {"vid17_like", "rope_snap", "impacts", "force_steps", "from_file"}) run_preset(name, 120.0);
}

}  // namespace
}  // namespace vid::sim::test
