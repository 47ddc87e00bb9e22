/// @file test_rotor_faults.cpp
/// @brief Real-sensor effects on the rotor side (`sensor_faults:`, `vehicle.rotor_drag_per_s`):
/// telemetry latency, quantization, lost messages, the written thrust-coefficient error,
/// one-rotor dips, mass-normalized rotor drag; the keys' errors; and that without the keys
/// nothing changes.

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "io/errors.h"
#include "io/sensor_yaml.h"
#include "sim/dataset_sink.h"
#include "sim/sensor_faults.h"
#include "sim_test_util.h"

namespace vid::sim {
namespace {

using test::hover_scenario;
using test::record;

/// @brief Rotor @p r's true speed at @p t_ns, linear between the ground-truth samples.
double true_speed(const test::Recording& rec, TimeNs t_ns, int r) {
  const auto it = std::lower_bound(rec.truth.begin(), rec.truth.end(), t_ns,
                                   [](const TruthSample& s, TimeNs t) { return s.t_ns < t; });
  if (it == rec.truth.begin() || it == rec.truth.end()) return NAN;
  const TruthSample& b = *it;
  const TruthSample& a = *(it - 1);
  const double u = static_cast<double>(t_ns - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  return (1.0 - u) * a.state.rotor_speeds[r] + u * b.state.rotor_speeds[r];
}

// Vertical steps make the rotor speeds move (a cross-correlation needs signal).
const char* kMoving = "trajectory: {type: vertical_steps, center: [0, 0, 1.5], step_heights_m: [1.0, 2.0], "
                      "max_speed: 1.5, max_accel: 3.0, start_delay_s: 1.0}\n";

TEST(RotorFaults, TelemetryLatencyQuantizationAndGaps) {
  const double p = 0.2;
  Scenario sc = hover_scenario(std::string(kMoving) +
                                   "sensor_faults: {rotor_telemetry: {latency_s: 0.03, quantization: 38, "
                                   "drop_probability: 0.2, max_consecutive_drops: 2}}\n",
                               30.0);
  sc.groundtruth_rate_hz = 1000.0;  // fine truth for the latency search
  const test::Recording rec = record(sc);
  // Quantization: every speed is a multiple of 38 rpm.
  for (const RotorSample& s : rec.rotor)
    for (double n : s.speeds) ASSERT_NEAR(std::remainder(n, 38.0), 0.0, 1e-6) << n;
  // Gaps: 10, 20 or 30 ms (message period 10 ms, at most two lost in a row).
  std::map<TimeNs, int> gaps;
  for (std::size_t k = 1; k < rec.rotor.size(); ++k) ++gaps[rec.rotor[k].t_ns - rec.rotor[k - 1].t_ns];
  ASSERT_EQ(gaps.size(), 3u);
  EXPECT_TRUE(gaps.count(10'000'000) && gaps.count(20'000'000) && gaps.count(30'000'000));
  const double sent = 30.0 * 100.0 + 1.0;
  const double lost = 1.0 - static_cast<double>(rec.rotor.size()) / sent;
  // Markov chain of the run length capped at 2: loss = p (1 + p) / (1 + p + p^2).
  EXPECT_NEAR(lost, p * (1.0 + p) / (1.0 + p + p * p), 0.025);
  // Latency: the stamps fit the true speeds best when shifted back by 30 ms.
  double best_tau = -1.0, best_err = INFINITY;
  for (int tau_ms = 0; tau_ms <= 60; ++tau_ms) {
    double err = 0.0;
    for (const RotorSample& s : rec.rotor) {
      for (int r = 0; r < 4; ++r) {
        const double n = true_speed(rec, s.t_ns - tau_ms * 1'000'000LL, r);
        if (std::isfinite(n)) err += (s.speeds[r] - n) * (s.speeds[r] - n);
      }
    }
    if (err < best_err) best_err = err, best_tau = tau_ms * 1e-3;
  }
  EXPECT_NEAR(best_tau, 0.03, 1e-3);
  // The first stamp is the first true sample time plus the latency.
  EXPECT_EQ((rec.rotor.front().t_ns - sc.start_time_ns) % 10'000'000, 0);
  EXPECT_GE(rec.rotor.front().t_ns - sc.start_time_ns, 30'000'000);
}

TEST(RotorFaults, ThrustCoefficientErrorIsInTheWrittenVehicleYaml) {
  Scenario sc = hover_scenario("sensor_faults: {thrust_coefficient_factor: 1.08}\n", 0.2);
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("vid_sim_kfactor_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  {
    Simulator sim(sc);
    DatasetSink sink(dir, sc, nullptr);
    sim.run(sink);
    sink.finish();
    // The physics uses the scenario's (true) coefficients.
    for (std::size_t i = 0; i < 4; ++i)
      EXPECT_EQ(sim.model().params().rotors[i].thrust_coeff, sc.vehicle.rotors[i].thrust_coeff);
  }
  const VehicleParams written = io::load_vehicle_yaml(dir / "mav0" / "vehicle.yaml");
  ASSERT_EQ(written.rotor_thrust_coefficients.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_NEAR(written.rotor_thrust_coefficients[i] / sc.vehicle.rotors[i].thrust_coeff, 1.08, 1e-9);
  std::filesystem::remove_all(dir);
}

TEST(RotorFaults, OneRotorDipActsOnTheVehicleAndShowsInTheRotorData) {
  const std::string dip = "sensor_faults: {rotor_dips: {list: [{t_s: 5.0, rotor: 1, duration_s: 0.1, depth: 0.15}]}}\n";
  const test::Recording base = record(hover_scenario("noise: false\n", 7.0));
  const test::Recording rec = record(hover_scenario("noise: false\n" + dip, 7.0));
  const Scenario sc = hover_scenario("", 7.0);
  auto t_of = [&](TimeNs t) { return static_cast<double>(t - sc.start_time_ns) * 1e-9; };
  double n_before = 0.0, n_min = INFINITY, w_dip = 0.0, w_base = 0.0;
  for (std::size_t k = 0; k < rec.truth.size(); ++k) {
    const double t = t_of(rec.truth[k].t_ns);
    if (t > 4.9 && t <= 5.0) n_before = rec.truth[k].state.rotor_speeds[1];
    if (t >= 5.0 && t <= 5.2) n_min = std::min(n_min, rec.truth[k].state.rotor_speeds[1]);
    if (t >= 5.0 && t <= 6.0) {
      w_dip = std::max(w_dip, rec.truth[k].state.w_I.head<2>().norm());
      w_base = std::max(w_base, base.truth[k].state.w_I.head<2>().norm());
    }
  }
  // 15 % command dip through a 30 ms motor lag for 0.1 s, the controller raising that rotor's
  // command against the roll it starts: the speed drops by ~10 %, never by more than 15 %.
  EXPECT_LT(n_min, 0.93 * n_before);
  EXPECT_GT(n_min, 0.85 * n_before);
  EXPECT_GT(w_dip, 0.05) << "the vehicle must roll / pitch";
  EXPECT_GT(w_dip, 100.0 * w_base);
  // The rotor data shows the dip; before it the runs are identical.
  double r_min = INFINITY;
  for (const RotorSample& s : rec.rotor)
    if (t_of(s.t_ns) >= 5.0 && t_of(s.t_ns) <= 5.2) r_min = std::min(r_min, s.speeds[1]);
  EXPECT_LT(r_min, 0.93 * n_before);
  for (std::size_t k = 0; k < rec.imu.size() && t_of(rec.imu[k].t_ns) < 5.0; ++k)
    ASSERT_EQ(rec.imu[k].accel_I, base.imu[k].accel_I);
  // The controller brings it back.
  EXPECT_LT((rec.gt.back().T_WI.p - base.gt.back().T_WI.p).norm(), 0.05);
}

TEST(RotorFaults, RandomDipsFollowTheirRate) {
  const Scenario sc = hover_scenario(
      "sensor_faults: {rotor_dips: {random: {rate_per_s: 2.0, depth: 0.15, duration_s: 0.1, start_s: 2.0}}}\n", 60.0);
  const RotorDips dips(sc.faults, 4, sc.duration_s, 123);
  const double expected = 2.0 * 58.0;
  EXPECT_NEAR(static_cast<double>(dips.dips().size()), expected, 4.0 * std::sqrt(expected));
  std::array<int, 4> per_rotor{};
  for (const RotorDip& d : dips.dips()) {
    EXPECT_GE(d.t_s, 2.0);
    EXPECT_LE(d.t_s + d.duration_s, 60.0);
    ++per_rotor[d.rotor];
  }
  for (int c : per_rotor) EXPECT_GT(c, 10);
}

TEST(RotorFaults, MassNormalizedRotorDrag) {
  const Scenario s = load_scenario_string("vehicle: {mass_kg: 2.0, rotor_drag_per_s: [0.3, 0.4, 0.2]}\n", "d.yaml");
  EXPECT_LT((s.vehicle.linear_drag - Eigen::Vector3d(0.6, 0.8, 0.4)).norm(), 1e-12);
  // fast_drag: no rope, so force0 is the drag -m R D R^T v alone, ~1 m/s^2 per unit mass or more.
  Scenario sc = load_scenario(test::preset_path("fast_drag_short"));
  sc.duration_s = sc.trajectory.duration_s = 12.0;
  const test::Recording rec = record(sc);
  const Eigen::Vector3d D(0.35, 0.40, 0.29);
  double peak_speed = 0.0, peak_drag = 0.0;
  for (std::size_t k = 0; k < rec.truth.size(); ++k) {
    const TruthSample& t = rec.truth[k];
    const Eigen::Matrix3d R = t.state.q_WI.toRotationMatrix();
    const Eigen::Vector3d expected = -sc.vehicle.mass_kg * R * D.cwiseProduct(R.transpose() * t.state.v_WI);
    ASSERT_LT((rec.force[k].f_W_N - expected).norm(), 1e-9);
    peak_speed = std::max(peak_speed, t.state.v_WI.norm());
    peak_drag = std::max(peak_drag, expected.norm() / sc.vehicle.mass_kg);
  }
  EXPECT_GT(peak_speed, 4.0);
  EXPECT_GT(peak_drag, 1.2);
}

TEST(RotorFaults, BadKeysAreNamed) {
  auto error_of = [](const std::string& yaml) -> std::string {
    try {
      load_scenario_string(yaml, "bad.yaml");
    } catch (const io::ConfigError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(error_of("sensor_faults: {vibrations: {}}\n").find("sensor_faults.vibrations"), std::string::npos);
  EXPECT_NE(error_of("sensor_faults: {rotor_telemetry: {latency: 0.1}}\n").find("sensor_faults.rotor_telemetry.latency"),
            std::string::npos);
  EXPECT_NE(error_of("sensor_faults: {rotor_dips: {list: [{t_s: 1, rotor: 4}]}}\n").find("rotor index"), std::string::npos);
  EXPECT_NE(error_of("sensor_faults: {thrust_coefficient_factor: 3}\n").find("thrust_coefficient_factor"),
            std::string::npos);
  EXPECT_NE(error_of("sensor_faults: {vibration: {bursts: [{t_s: 1, band_hz: [10, 250]}]}}\n").find("band_hz"),
            std::string::npos);
  EXPECT_NE(error_of("sensor_faults: {rotor_telemetry: {drop_probability: 1}}\n").find("drop_probability"),
            std::string::npos);
  EXPECT_NE(error_of("vehicle: {rotor_drag_per_s: [0.3, 0.3, 0.2], linear_drag: [1, 1, 1]}\n").find("rotor_drag_per_s"),
            std::string::npos);
}

TEST(RotorFaults, ZeroFaultsChangeNothing) {
  // Every key at its "off" value gives exactly the run without the section (no extra random
  // draws, no changed arithmetic): the guarantee behind the presets' byte-identical output.
  Scenario plain = load_scenario(test::preset_path("vid17_like_short"));
  plain.duration_s = plain.trajectory.duration_s = 3.0;
  Scenario off = plain;
  off.faults = load_scenario_string(
                   "sensor_faults: {imu_timestamps: {jitter_s: 0}, thrust_axis: {tilt_deg: 0, azimuth_deg: 20}, "
                   "thrust_coefficient_factor: 1, rotor_telemetry: {latency_s: 0, quantization: 0, "
                   "drop_probability: 0}, rotor_dips: {list: []}}\n",
                   "off.yaml")
                   .faults;
  const test::Recording a = record(plain), b = record(off);
  ASSERT_EQ(a.imu.size(), b.imu.size());
  for (std::size_t k = 0; k < a.imu.size(); ++k) {
    ASSERT_EQ(a.imu[k].t_ns, b.imu[k].t_ns);
    ASSERT_EQ(a.imu[k].accel_I, b.imu[k].accel_I);
    ASSERT_EQ(a.imu[k].gyro_I, b.imu[k].gyro_I);
  }
  ASSERT_EQ(a.rotor.size(), b.rotor.size());
  for (std::size_t k = 0; k < a.rotor.size(); ++k) ASSERT_EQ(a.rotor[k].speeds, b.rotor[k].speeds);
  for (std::size_t k = 0; k < a.gt.size(); ++k) ASSERT_EQ(a.gt[k].T_WI.p, b.gt[k].T_WI.p);
  EXPECT_EQ(vehicle_params_of(plain).rotor_thrust_coefficients, vehicle_params_of(off).rotor_thrust_coefficients);
}

}  // namespace
}  // namespace vid::sim
