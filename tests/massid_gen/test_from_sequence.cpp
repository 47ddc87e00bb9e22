/// @file test_from_sequence.cpp
/// @brief vid_massid from-sequence: a sequence folder with known analytic motion, rotor speeds
/// and mass becomes the study run the documentation promises (grid, interpolation, body rate,
/// thrust, noise level, error messages).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "geometry/so3.h"
#include "io/dataset_writer.h"
#include "io/errors.h"
#include "massid/gen/from_sequence.h"

namespace vid::massid::gen {
namespace {

const Eigen::Vector3d kRate(0.3, -0.2, 0.5);  // constant body rate [rad/s]
const Eigen::Vector3d kV0(0.5, -1.0, 0.2), kAcc(0.1, 0.2, -0.3);
constexpr TimeNs kT0 = 1'700'000'000'000'000'000;

Eigen::Quaterniond q_at(double t) { return so3::quat_exp(kRate * t); }
Eigen::Vector3d v_at(double t) { return kV0 + kAcc * t; }
Eigen::Vector3d p_at(double t) { return Eigen::Vector3d(1, 2, 3) + kV0 * t + 0.5 * kAcc * t * t; }
double mass_at(double t) { return t < 1.0 ? 3.0 : 3.6; }

/// 2 s: ground truth at 200 Hz, rotors at 100 Hz (from 0.02 s), mass0 at 50 Hz.
std::filesystem::path write_folder(const std::string& name, bool with_mass) {
  const auto root = std::filesystem::path(::testing::TempDir()) / name;
  std::filesystem::remove_all(root);
  io::DatasetWriter w(root);
  w.write_imu_calibration(ImuNoise{});
  RotorSensor rotor;
  rotor.unit = "rpm";
  w.write_rotor_calibration(rotor);
  VehicleParams vehicle;
  vehicle.mass_kg = 3.0;
  vehicle.gravity = 9.80665;
  vehicle.rotor_thrust_coefficients = {2e-7, 3e-7, 4e-7, 5e-7};
  w.write_vehicle(vehicle);
  for (int k = 0; k <= 400; ++k) {
    const double t = k * 0.005;
    const TimeNs t_ns = kT0 + k * 5'000'000;
    w.write(ImuSample{t_ns, kRate, Eigen::Vector3d(0, 0, 9.8)});
    if (k % 2 == 0 && k >= 4) w.write(RotorSample{t_ns, {5000.0 + k, 5100.0, 5200.0, 5300.0}});
    if (k % 4 == 0 && with_mass) w.write(MassSample{t_ns, mass_at(t)});
    GroundTruthSample g;
    g.t_ns = t_ns;
    g.T_WI.q = q_at(t);
    g.T_WI.p = p_at(t);
    g.v_WI = v_at(t);
    w.write(g);
  }
  return root;
}

double thrust_of(double speed0) {
  return 2e-7 * speed0 * speed0 + 3e-7 * 5100.0 * 5100.0 + 4e-7 * 5200.0 * 5200.0 + 5e-7 * 5300.0 * 5300.0;
}

TEST(FromSequence, NoiseFreeRunIsTheTruthOnTheStudyGrid) {
  FromSequenceSettings s;
  s.sigma_q = s.sigma_p = s.sigma_v = 0.0;
  s.initial_mass_factor = 1.2;
  const SequenceRun r = run_from_sequence(write_folder("fs_clean", true), "clean", s);
  EXPECT_EQ(r.t0_ns, kT0 + 20'000'000);  // the rotors start last
  // [t0, 2 s] at 100 Hz, each sample's interval inside the span: (2.0 - 0.02) / 0.01 = 198.
  ASSERT_EQ(r.run.samples.size(), 198u);
  EXPECT_EQ(r.run.info.trajectory, "clean");
  EXPECT_EQ(r.run.info.mass_profile, "sequence");
  EXPECT_DOUBLE_EQ(r.run.info.gravity, 9.80665);
  EXPECT_DOUBLE_EQ(r.run.info.initial_mass_guess, 3.6);
  for (std::size_t k = 0; k < r.run.samples.size(); ++k) {
    const MassIdSample& x = r.run.samples[k];
    const double t = 0.02 + 0.01 * static_cast<double>(k);
    SCOPED_TRACE(k);
    EXPECT_NEAR(x.t, 0.01 * static_cast<double>(k), 1e-12);
    EXPECT_LT(so3::boxminus(x.q_WI, q_at(t)).norm(), 1e-9);
    // p is quadratic in t: linear interpolation between 5 ms samples is off by <= a dt^2 / 8.
    EXPECT_LT((x.p_WI - p_at(t)).norm(), 1e-12 + 0.4 * 0.005 * 0.005 / 8);
    EXPECT_LT((x.v_WI - v_at(t)).norm(), 1e-12);
    EXPECT_LT((x.w_I - kRate).norm(), 1e-8);  // Log(R_k^T R_k+1) / dt of a constant rate
    const int rotor_k = static_cast<int>(std::lround(t / 0.005));  // the rotor row at t_k
    EXPECT_NEAR(x.thrust_cmd, thrust_of(5000.0 + rotor_k), 1e-9);
    EXPECT_DOUBLE_EQ(x.mass_true, t < 0.98 ? 3.0 : (t >= 1.0 ? 3.6 : 3.0 + 0.6 * (t - 0.98) / 0.02));
  }
}

TEST(FromSequence, NoiseHasTheStatedSigma) {
  FromSequenceSettings s;  // the study's 0.005 rad / 0.01 m / 0.02 m/s
  const SequenceRun r = run_from_sequence(write_folder("fs_noisy", true), "noisy", s);
  double sq = 0, sp = 0, sv = 0;
  for (std::size_t k = 0; k < r.run.samples.size(); ++k) {
    const double t = 0.02 + 0.01 * static_cast<double>(k);
    sq += so3::boxminus(r.run.samples[k].q_WI, q_at(t)).squaredNorm();
    sp += (r.run.samples[k].p_WI - p_at(t)).squaredNorm();
    sv += (r.run.samples[k].v_WI - v_at(t)).squaredNorm();
  }
  const double n = 3.0 * static_cast<double>(r.run.samples.size());  // 594 draws per quantity
  EXPECT_NEAR(std::sqrt(sq / n), 0.005, 0.0008);
  EXPECT_NEAR(std::sqrt(sp / n), 0.01, 0.0016);
  EXPECT_NEAR(std::sqrt(sv / n), 0.02, 0.0032);
}

TEST(FromSequence, MissingMassIsOneLineNamingTheStream) {
  const auto root = write_folder("fs_nomass", false);
  try {
    run_from_sequence(root, "x", {});
    FAIL() << "no error";
  } catch (const io::DatasetError& e) {
    EXPECT_EQ(std::string(e.what()), root.string() + ": needs mass0 (found 0 rows)");
  }
}

}  // namespace
}  // namespace vid::massid::gen
