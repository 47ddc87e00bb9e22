/// @file test_determinism.cpp
/// @brief vid_sim is deterministic: the same seed gives a byte-identical folder, another seed
/// different noise (feature-only mode to keep it fast). Also checks the CLI error path.

#include <gtest/gtest.h>

#include <unistd.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
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

/// Rows of a CSV (header skipped) as numbers.
std::vector<std::vector<double>> csv_rows(const std::string& text) {
  std::vector<std::vector<double>> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<double> r;
    std::istringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) r.push_back(std::stod(cell));
    rows.push_back(r);
  }
  return rows;
}

double yaw_deg_of(double qw, double qx, double qy, double qz) {
  const Eigen::Matrix3d R = Eigen::Quaterniond(qw, qx, qy, qz).toRotationMatrix();
  return std::atan2(R(1, 0), R(0, 0)) * 180.0 / M_PI;
}

double wrap_deg(double a) { return std::remainder(a, 360.0); }

// The initial heading rotates every world-frame file about z and nothing else: body-frame
// sensor streams stay byte-identical, the first ground-truth heading is the requested one,
// positions, force and landmarks keep their norms in the horizontal plane (rotated, not moved),
// and 'random' is drawn from the seed.
TEST(VidSim, RealSensorPresetIsDeterministicAndShowsItsFaults) {
  // Every random stream of sensor_faults derives from the seed: same seed, same folder.
  const fs::path base = fs::temp_directory_path() / ("vid_sim_det_faults_" + std::to_string(::getpid()));
  fs::remove_all(base);
  const std::string common = "--scenario " + preset("vid17_real_sensors_short") + " --duration 3 --features-only";
  ASSERT_EQ(run(common + " --out " + (base / "a").string()), 0);
  ASSERT_EQ(run(common + " --out " + (base / "b").string()), 0);
  const auto a = read_tree(base / "a"), b = read_tree(base / "b");
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [name, content] : a) EXPECT_TRUE(content == b.at(name)) << name;
  // Lost rotor messages: fewer rows than 3 s at 100 Hz; the stamps 30 ms late.
  const std::string& rotor = a.at("mav0/rotor0/data.csv");
  EXPECT_LT(std::count(rotor.begin(), rotor.end(), '\n'), 1 + 300);
  const vid::sim::Scenario sc = vid::sim::load_scenario(preset("vid17_real_sensors_short"));
  const std::string first = rotor.substr(rotor.find('\n') + 1, rotor.find(',', rotor.find('\n')) - rotor.find('\n') - 1);
  const long long late_ns = std::stoll(first) - sc.start_time_ns;  // a true sample time + 30 ms
  EXPECT_GE(late_ns, 30'000'000);
  EXPECT_EQ((late_ns - 30'000'000) % 10'000'000, 0);
  fs::remove_all(base);
}

TEST(VidSim, InitialHeadingRotatesTheGroundTruthWorldOnly) {
  const fs::path base = fs::temp_directory_path() / ("vid_sim_heading_" + std::to_string(::getpid()));
  fs::remove_all(base);
  const std::string common = "--scenario " + preset("vid17_like_short") + " --duration 2 --features-only --seed 5";
  ASSERT_EQ(run(common + " --out " + (base / "a").string()), 0);
  ASSERT_EQ(run(common + " --initial-heading 165 --out " + (base / "b").string()), 0);
  ASSERT_EQ(run(common + " --initial-heading random --out " + (base / "r1").string()), 0);
  ASSERT_EQ(run(common + " --initial-heading random --out " + (base / "r2").string()), 0);
  const auto a = read_tree(base / "a"), b = read_tree(base / "b");
  for (const char* f : {"mav0/imu0/data.csv", "mav0/rotor0/data.csv", "mav0/feat0/data.csv", "mav0/mass0/data.csv"})
    EXPECT_TRUE(a.at(f) == b.at(f)) << f << " must not depend on the heading";
  const auto gt_a = csv_rows(a.at("mav0/state_groundtruth_estimate0/data.csv"));
  const auto gt_b = csv_rows(b.at("mav0/state_groundtruth_estimate0/data.csv"));
  ASSERT_EQ(gt_a.size(), gt_b.size());
  EXPECT_NEAR(wrap_deg(yaw_deg_of(gt_b[0][4], gt_b[0][5], gt_b[0][6], gt_b[0][7]) - 165.0), 0.0, 1e-6);
  const double dyaw = yaw_deg_of(gt_b[0][4], gt_b[0][5], gt_b[0][6], gt_b[0][7]) -
                      yaw_deg_of(gt_a[0][4], gt_a[0][5], gt_a[0][6], gt_a[0][7]);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(dyaw * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (std::size_t i = 0; i < gt_a.size(); i += 37) {
    const Eigen::Vector3d pa(gt_a[i][1], gt_a[i][2], gt_a[i][3]), pb(gt_b[i][1], gt_b[i][2], gt_b[i][3]);
    const Eigen::Vector3d va(gt_a[i][8], gt_a[i][9], gt_a[i][10]), vb(gt_b[i][8], gt_b[i][9], gt_b[i][10]);
    EXPECT_LT((R * pa - pb).norm(), 1e-9) << "row " << i;
    EXPECT_LT((R * va - vb).norm(), 1e-9) << "row " << i;
    for (int k = 11; k < 17; ++k) EXPECT_DOUBLE_EQ(gt_a[i][k], gt_b[i][k]) << "biases are body-frame";
    EXPECT_NEAR(wrap_deg(yaw_deg_of(gt_b[i][4], gt_b[i][5], gt_b[i][6], gt_b[i][7]) -
                         yaw_deg_of(gt_a[i][4], gt_a[i][5], gt_a[i][6], gt_a[i][7]) - dyaw), 0.0, 1e-6);
  }
  const auto f_a = csv_rows(a.at("mav0/force0/data.csv")), f_b = csv_rows(b.at("mav0/force0/data.csv"));
  ASSERT_EQ(f_a.size(), f_b.size());
  for (std::size_t i = 0; i < f_a.size(); i += 37)
    EXPECT_LT((R * Eigen::Vector3d(f_a[i][1], f_a[i][2], f_a[i][3]) - Eigen::Vector3d(f_b[i][1], f_b[i][2], f_b[i][3]))
                  .norm(),
              1e-9);
  const auto l_a = csv_rows(a.at("mav0/landmarks.csv")), l_b = csv_rows(b.at("mav0/landmarks.csv"));
  ASSERT_EQ(l_a.size(), l_b.size());
  ASSERT_FALSE(l_a.empty());
  for (std::size_t i = 0; i < l_a.size(); ++i)
    EXPECT_LT((R * Eigen::Vector3d(l_a[i][1], l_a[i][2], l_a[i][3]) - Eigen::Vector3d(l_b[i][1], l_b[i][2], l_b[i][3]))
                  .norm(),
              1e-9);
  // 'random' is a deterministic draw of the seed, and not the trajectory's own heading.
  const auto r1 = read_tree(base / "r1"), r2 = read_tree(base / "r2");
  EXPECT_TRUE(r1.at("mav0/state_groundtruth_estimate0/data.csv") == r2.at("mav0/state_groundtruth_estimate0/data.csv"));
  EXPECT_FALSE(r1.at("mav0/state_groundtruth_estimate0/data.csv") == a.at("mav0/state_groundtruth_estimate0/data.csv"));
  EXPECT_NE(run(common + " --initial-heading north --out " + (base / "bad").string()), 0);
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
