/// @file test_ground_contact.cpp
/// @brief The floor contact model (friction sticks below mu N and slides above), the
/// `ground:` / `takeoff_landing:` keys and their errors, the phase0 stream on disk and its
/// readers, and that presets without `ground:` are unchanged by it (golden values from main
/// at 6a5dc8f, before the ground model existed).

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <variant>

#include "io/dataset_reader.h"
#include "io/errors.h"
#include "sim_test_util.h"

namespace vid::sim::test {
namespace {

namespace fs = std::filesystem;

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// takeoff_landing_short with @p from replaced by @p to (must occur).
std::string edited_preset(const std::string& from, const std::string& to) {
  std::string text = read_text(preset_path("takeoff_landing_short"));
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

std::string load_error(const std::string& text) {
  try {
    const Scenario sc = load_scenario_string(text, "edited.yaml");
    Simulator sim(sc);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(GroundContact, FrictionSticksBelowMuNAndSlidesAbove) {
  // Half of mu m g: even the feet unloaded by the load's pitching moment (it acts 0.11 m
  // above the floor) stay below their own cap; 1.3 mu m g exceeds the whole gear's.
  for (const double fraction : {0.5, 1.3}) {
    Scenario sc = load_scenario(preset_path("takeoff_landing_short"));
    sc.noise = false;
    const double mu = sc.environment.ground.friction_coefficient;
    const double side_N = fraction * mu * sc.vehicle.mass_kg * sc.vehicle.gravity;
    sc.environment.steps.push_back({0.5, Eigen::Vector3d(side_N, 0, 0), false, 0.0});   // push sideways ...
    sc.environment.steps.push_back({1.0, Eigen::Vector3d(-side_N, 0, 0), false, 0.0});  // ... for 0.5 s
    const Recording rec = record(sc);
    const Eigen::Vector3d p0 = rec.truth.front().state.p_WI;
    double moved = 0.0;
    int sliding = 0;
    for (const TruthSample& s : rec.truth) {
      const double t = static_cast<double>(s.t_ns - sc.start_time_ns) * 1e-9;
      if (t > 1.9) break;
      moved = std::max(moved, (s.state.p_WI - p0).head<2>().norm());
      if (t > 0.55 && t < 0.95 && s.ground.feet_sliding == 4) {
        ++sliding;
        EXPECT_NEAR(s.ground.f_W.head<2>().norm(), mu * s.ground.normal_N, 1e-9 * s.ground.normal_N);
      }
    }
    if (fraction < 1.0) {
      EXPECT_LT(moved, 1e-3) << "a side load below mu N must not move the vehicle beyond the gear's deflection";
      EXPECT_EQ(sliding, 0);
    } else {
      EXPECT_GT(moved, 0.05) << "a side load above mu N must drag the vehicle";
      EXPECT_GT(sliding, 50);
    }
  }
}

TEST(GroundContact, BeforeRunTheEnvironmentIsTheOneOfTimeZero) {
  // The settled friction anchors are in place as soon as the Simulator exists: the contact at
  // the initial state carries the weight and holds the rope, nothing slides.
  Scenario sc = load_scenario(preset_path("vid17_like_ground"));
  sc.duration_s = sc.trajectory.duration_s = 40.0;
  const Simulator sim(sc);
  const dynamics::QuadrotorState x = sim.initial_state();
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  const ContactWrench c = sim.environment().ground_contact(x, zero, zero);
  const Eigen::Vector3d rope = sim.environment().rope_force_W(x);
  EXPECT_EQ(c.feet_loaded, 4);
  EXPECT_EQ(c.feet_sliding, 0);
  EXPECT_LT((c.f_W + rope - Eigen::Vector3d(0, 0, sc.vehicle.mass_kg * sc.vehicle.gravity)).norm(), 1e-6);
  EXPECT_LT(x.v_WI.norm(), 1e-12);
  EXPECT_EQ(x.rotor_speeds.cwiseAbs().maxCoeff(), 0.0);
}

TEST(GroundContact, KeysAndTheirErrors) {
  const Scenario sc = load_scenario(preset_path("takeoff_landing_short"));
  EXPECT_TRUE(sc.environment.ground.enabled);
  EXPECT_TRUE(sc.takeoff_landing.enabled);
  EXPECT_DOUBLE_EQ(sc.environment.ground.gear_length_m, 0.111);
  EXPECT_DOUBLE_EQ(sc.takeoff_landing.rest_start_s, 2.0);
  // Presets without the sections have neither.
  const Scenario plain = load_scenario(preset_path("vid17_like_short"));
  EXPECT_FALSE(plain.environment.ground.enabled);
  EXPECT_FALSE(plain.takeoff_landing.enabled);

  EXPECT_NE(load_error(edited_preset("  friction_coefficient: 0.6\n", "  friction_coefficient: 0.6\n  foo: 1\n"))
                .find("unknown key 'ground.foo'"),
            std::string::npos);
  EXPECT_NE(load_error(edited_preset("ground:", "unused_ground:")).find("key 'takeoff_landing'"), std::string::npos);
  EXPECT_NE(load_error(edited_preset("room_center: [0.0, 0.0, 2.0]", "room_center: [0.0, 0.0, 1.5]"))
                .find("scene's floor is at z = -0.5"),
            std::string::npos);
  EXPECT_NE(load_error(edited_preset("stiffness_N_per_m: 30000", "stiffness_N_per_m: 3e7")).find("too stiff"),
            std::string::npos);
  EXPECT_NE(load_error(edited_preset("stiffness_N_per_m: 30000", "stiffness_N_per_m: 100")).find("too soft"),
            std::string::npos);
  EXPECT_NE(load_error(edited_preset("damping_Ns_per_m: 600", "damping_Ns_per_m: 3000")).find("too much damping"),
            std::string::npos);
  EXPECT_NE(load_error(edited_preset("rotor_speed_min: 1000", "rotor_speed_min: 0")).find("rotor_speed_min > 0"),
            std::string::npos);
  EXPECT_NE(load_error(edited_preset("descent_speed_mps: 0.3", "descent_speed_mps: 2")).find("descent_speed_mps"),
            std::string::npos);
  EXPECT_NE(load_error(edited_preset("duration_s: 22", "duration_s: 12")).find("leaves no time"), std::string::npos);
  EXPECT_EQ(load_error(edited_preset("duration_s: 22", "duration_s: 30")), "");
}

/// Exact doubles written by vid_sim of main at 6a5dc8f (before the ground model) at one time
/// of a preset: presets without `ground:` must not change by a single bit.
struct Golden {
  const char* preset;
  TimeNs t_ns;
  Eigen::Matrix<double, 6, 1> imu;  ///< gyro, accel
  Eigen::Vector4d rotor;
  Eigen::Vector3d p, v;
  Eigen::Vector4d q;                ///< w, x, y, z
  TimeNs force_t_ns;
  Eigen::Matrix<double, 6, 1> force;  ///< f, df
};

TEST(GroundContact, PresetsWithoutGroundAreUnchanged) {
  const Golden goldens[] = {
      {"vid17_like_short", 1700000025000000000LL,
       (Eigen::Matrix<double, 6, 1>() << -0.03258057816198725, -0.018228185532700194, -0.27743369774056337,
        -4.1684437240323655, 2.151041940609965, 12.200723415972515).finished(),
       {5643.039474713086, 5555.473614961173, 5631.346988889197, 5623.573033002927},
       {0.7554044545276506, 0.2941736565137563, 1.205833662453249},
       {-0.5258853514304385, 0.29661796265925094, 0.036317826893386085},
       {0.9857034615290178, 0.013814512420052336, 0.1425873777511679, 0.0886943339923943},
       1700000025000000000LL,
       (Eigen::Matrix<double, 6, 1>() << -10.318883904727008, -0.7133384950435778, -2.924012912104734,
        4.018579291354303, -0.5296183819533842, 0.6893077306382563).finished()},
      {"rope_snap_short", 1700000025000000000LL,
       (Eigen::Matrix<double, 6, 1>() << 0.07302060406108173, -0.10004966529278299, -0.02335931499841269,
        2.309399548441427, 1.0997582934618877, 8.498982653034707).finished(),
       {5336.898704607979, 5142.2856942363205, 5154.918691733594, 5269.666466654342},
       {0.23442880843706512, 0.9743892041843156, 1.4923577014837628},
       {-1.2097625441128477, 0.2601134781739764, 0.05861689760227249},
       {0.9975001797668265, 0.06643624398355644, 0.02404147910251255, 0.001274414795038103},
       1700000013090000000LL,
       (Eigen::Matrix<double, 6, 1>() << -10.076032272918606, 0.20772134850432486, 0.040394919374488504,
        -21.204269431950618, -1.9238177946180546, -0.3979553472142).finished()},
  };
  for (const Golden& g : goldens) {
    SCOPED_TRACE(g.preset);
    const Scenario sc = load_scenario(preset_path(g.preset));  // cameras kept: they set integrator steps
    Simulator sim(sc);
    Recording rec;
    sim.run(rec);
    EXPECT_TRUE(rec.phase.empty()) << "no phase stream without ground:";
    const auto find = [](const auto& v, TimeNs t) {
      return std::find_if(v.begin(), v.end(), [t](const auto& s) { return s.t_ns == t; });
    };
    const auto imu = find(rec.imu, g.t_ns);
    ASSERT_NE(imu, rec.imu.end());
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(imu->gyro_I[k], g.imu[k]);
      EXPECT_EQ(imu->accel_I[k], g.imu[3 + k]);
    }
    const auto rotor = find(rec.rotor, g.t_ns);
    ASSERT_NE(rotor, rec.rotor.end());
    for (int k = 0; k < 4; ++k) EXPECT_EQ(rotor->speeds[k], g.rotor[k]);
    // World-frame values as DatasetSink writes them (through R_GS, identity here).
    const Eigen::Matrix3d& R_GS = sim.R_GS();
    const auto gt = find(rec.gt, g.t_ns);
    ASSERT_NE(gt, rec.gt.end());
    const Eigen::Vector3d p = R_GS * gt->T_WI.p, v = R_GS * gt->v_WI;
    const Eigen::Quaterniond q = Eigen::Quaterniond(R_GS * gt->T_WI.R()).normalized();
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(p[k], g.p[k]);
      EXPECT_EQ(v[k], g.v[k]);
    }
    EXPECT_EQ(q.w(), g.q[0]);
    EXPECT_EQ(q.x(), g.q[1]);
    EXPECT_EQ(q.y(), g.q[2]);
    EXPECT_EQ(q.z(), g.q[3]);
    const auto force = find(rec.force, g.force_t_ns);
    ASSERT_NE(force, rec.force.end());
    const Eigen::Vector3d f = R_GS * force->f_W_N, df = R_GS * force->df_W_Nps;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(f[k], g.force[k]);
      EXPECT_EQ(df[k], g.force[3 + k]);
    }
  }
}

TEST(GroundContact, PhaseStreamOnDiskAndReadersIgnoreIt) {
  const fs::path out = fs::temp_directory_path() / ("vid_sim_phase_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string bin = std::string(VID_BINARY_DIR) + "/bin/";
  const std::string cmd = bin + "vid_sim --scenario " + preset_path("takeoff_landing_short") + " --features-only --out " +
                          out.string() + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream in(out / "mav0" / "phase0" / "data.csv");
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "#timestamp [ns],phase");
  int rows = 0, changes = 0;
  std::string last;
  const std::regex row("^[0-9]{19},[01]$");
  while (std::getline(in, line)) {
    ASSERT_TRUE(std::regex_match(line, row)) << line;
    const std::string phase = line.substr(line.find(',') + 1);
    if (!last.empty() && phase != last) ++changes;
    last = phase;
    ++rows;
  }
  EXPECT_EQ(rows, 22 * 200 + 1);  // one row per ground-truth sample
  EXPECT_EQ(changes, 2);
  // The dataset reader (and so vid_run) and vid_info read the folder as before.
  io::DatasetReader reader(out);
  std::size_t n = 0;
  while (reader.next()) ++n;
  EXPECT_GT(n, 22u * 400u);
  EXPECT_EQ(std::system((bin + "vid_info " + out.string() + " > /dev/null 2>&1").c_str()), 0);
  fs::remove_all(out);
}

}  // namespace
}  // namespace vid::sim::test
