/// @file test_determinism.cpp
/// @brief vid_sim is deterministic: the same seed gives a byte-identical folder, another seed
/// different noise (feature-only mode to keep it fast). Also checks the CLI error path.

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <variant>

#include "io/dataset_reader.h"
#include "sim/scenario.h"

namespace {

namespace fs = std::filesystem;

std::string program() { return std::string(VID_BINARY_DIR) + "/bin/vid_sim"; }
std::string preset(const std::string& n) { return std::string(VID_SOURCE_DIR) + "/config/sim/" + n + ".yaml"; }

int run(const std::string& args) {
  const std::string cmd = program() + " " + args + " > /dev/null 2>&1";
  return std::system(cmd.c_str());
}

std::map<std::string, std::string> read_tree(const fs::path& root) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (!e.is_regular_file()) continue;
    std::ifstream in(e.path(), std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    files[fs::relative(e.path(), root).string()] = ss.str();
  }
  return files;
}

TEST(VidSim, SameSeedGivesIdenticalFolder) {
  const fs::path base = fs::temp_directory_path() / ("vid_sim_det_" + std::to_string(::getpid()));
  fs::remove_all(base);
  const std::string common = "--scenario " + preset("vid17_like_short") + " --duration 4 --features-only";
  ASSERT_EQ(run(common + " --seed 5 --out " + (base / "a").string()), 0);
  ASSERT_EQ(run(common + " --seed 5 --out " + (base / "b").string()), 0);
  ASSERT_EQ(run(common + " --seed 6 --out " + (base / "c").string()), 0);
  const auto a = read_tree(base / "a"), b = read_tree(base / "b"), c = read_tree(base / "c");
  for (const char* f : {"mav0/imu0/data.csv", "mav0/rotor0/data.csv", "mav0/state_groundtruth_estimate0/data.csv",
                        "mav0/force0/data.csv", "mav0/mass0/data.csv", "mav0/vehicle.yaml", "mav0/imu0/sensor.yaml",
                        "mav0/rotor0/sensor.yaml", "mav0/cam0/sensor.yaml", "mav0/cam1/sensor.yaml"}) {
    EXPECT_TRUE(a.count(f)) << "missing " << f;
  }
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [name, content] : a) {
    ASSERT_TRUE(b.count(name)) << name;
    EXPECT_TRUE(content == b.at(name)) << name << " differs between two runs with the same seed";
  }
  EXPECT_NE(a.at("mav0/imu0/data.csv"), c.at("mav0/imu0/data.csv")) << "another seed must change the IMU noise";
  EXPECT_NE(a.at("mav0/rotor0/data.csv"), c.at("mav0/rotor0/data.csv"));
  // 4 s at 400 Hz plus the sample at t = 0, plus the header line.
  const std::string& imu = a.at("mav0/imu0/data.csv");
  EXPECT_EQ(std::count(imu.begin(), imu.end(), '\n'), 1602);
  ASSERT_TRUE(a.count("mav0/landmarks.csv"));
  EXPECT_EQ(a.at("mav0/landmarks.csv").rfind("#id,x,y,z\n", 0), 0u);

  // The folder reads back through the io reader with the scenario's calibration.
  const vid::sim::Scenario sc = vid::sim::load_scenario(preset("vid17_like_short"));
  vid::io::DatasetReader reader(base / "a");
  const auto& cal = reader.calibration();
  ASSERT_EQ(cal.cameras.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    EXPECT_LT((cal.cameras[k].T_IC.matrix() - sc.cameras.cameras[k].T_IC.matrix()).norm(), 1e-9);
    EXPECT_LT((cal.cameras[k].intrinsics - sc.cameras.cameras[k].intrinsics).norm(), 1e-9);
  }
  ASSERT_TRUE(cal.rotor.has_value());
  EXPECT_EQ(cal.rotor->unit, "rpm");
  EXPECT_EQ(cal.rotor->count, 4);
  ASSERT_TRUE(cal.vehicle.has_value());
  EXPECT_DOUBLE_EQ(cal.vehicle->mass_kg, 3.1015);
  ASSERT_EQ(cal.vehicle->rotor_thrust_coefficients.size(), 4u);
  EXPECT_DOUBLE_EQ(cal.vehicle->rotor_thrust_coefficients[2], 2.7263e-7);
  ASSERT_TRUE(cal.imu.has_value());
  EXPECT_DOUBLE_EQ(cal.imu->rate_hz, 400.0);
  EXPECT_DOUBLE_EQ(cal.imu->accel_noise_density, 0.1);
  std::size_t n_imu = 0, n_rotor = 0, n_feat = 0, n_gt = 0, n_force = 0, n_mass = 0;
  vid::TimeNs last = 0;
  while (auto m = reader.next()) {
    EXPECT_GE(vid::stamp_of(*m), last);
    last = vid::stamp_of(*m);
    if (std::holds_alternative<vid::ImuSample>(*m)) ++n_imu;
    if (std::holds_alternative<vid::RotorSample>(*m)) ++n_rotor;
    if (std::holds_alternative<vid::FeatureFrame>(*m)) ++n_feat;
    if (std::holds_alternative<vid::GroundTruthSample>(*m)) ++n_gt;
    if (std::holds_alternative<vid::ForceSample>(*m)) ++n_force;
    if (std::holds_alternative<vid::MassSample>(*m)) ++n_mass;
  }
  EXPECT_EQ(n_imu, 1601u);
  EXPECT_EQ(n_rotor, 401u);
  EXPECT_EQ(n_gt, 801u);
  EXPECT_EQ(n_force, 801u);
  EXPECT_EQ(n_mass, 801u);
  EXPECT_EQ(n_feat, 121u);  // 30 Hz over 4 s
  fs::remove_all(base);
}

TEST(VidSim, BadScenarioExitsNonZero) {
  const fs::path dir = fs::temp_directory_path() / ("vid_sim_bad_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "bad.yaml") << "name: x\nvehicle:\n  mas_kg: 3\n";
  const std::string cmd = program() + " --scenario " + (dir / "bad.yaml").string() + " --out " +
                          (dir / "out").string() + " 2>" + (dir / "err.txt").string();
  EXPECT_NE(std::system(cmd.c_str()), 0);
  std::ifstream in(dir / "err.txt");
  std::string line;
  std::getline(in, line);
  EXPECT_NE(line.find("bad.yaml"), std::string::npos) << line;
  EXPECT_NE(line.find("vehicle.mas_kg"), std::string::npos) << line;
  fs::remove_all(dir);
}

}  // namespace
