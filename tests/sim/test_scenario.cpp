/// @file test_scenario.cpp
/// @brief Scenario YAML: every preset loads; errors name the file and the key.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "io/errors.h"
#include "sim/scenario.h"

namespace vid::sim {
namespace {

std::string preset(const std::string& name) { return std::string(VID_SOURCE_DIR) + "/config/sim/" + name + ".yaml"; }

std::string error_of(const std::string& yaml, const std::string& name = "bad.yaml") {
  try {
    load_scenario_string(yaml, name);
  } catch (const io::ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Scenario, EveryPresetLoads) {
  // config/sim also holds other modules' settings (estimator.yaml, frontend.yaml): list the scenarios.
  for (const char* name : {"vid17_like", "vid18_like", "vid_loaded", "euroc_like", "hover", "checkerboard", "fast_yaw",
                           "wind_gusts", "spraying", "vid17_like_short", "vid18_like_short", "vid_loaded_short",
                           "euroc_like_short"}) {
    SCOPED_TRACE(name);
    const Scenario s = load_scenario(preset(name));
    EXPECT_EQ(s.name, name);
    EXPECT_GT(s.duration_s, 0.0);
    EXPECT_GE(s.groundtruth_rate_hz, 200.0);
    EXPECT_FALSE(s.cameras.cameras.empty());
  }
}

TEST(Scenario, Vid17LikeHasTheVidCalibration) {
  const Scenario s = load_scenario(preset("vid17_like"));
  EXPECT_DOUBLE_EQ(s.vehicle.mass_kg, 3.1015);
  ASSERT_EQ(s.vehicle.rotors.size(), 4u);
  EXPECT_DOUBLE_EQ(s.vehicle.rotors[1].thrust_coeff, 2.8190e-7);
  EXPECT_EQ(s.rotor_unit, "rpm");
  EXPECT_DOUBLE_EQ(s.imu.noise.rate_hz, 400.0);
  EXPECT_DOUBLE_EQ(s.imu.noise.accel_random_walk, 4.0e-3);
  ASSERT_EQ(s.cameras.cameras.size(), 2u);
  const CameraCalib& c0 = s.cameras.cameras[0];
  EXPECT_DOUBLE_EQ(c0.intrinsics[0], 382.59014892578125);
  // Camera optical axis (z_C) looks along the body x axis; camera x is body -y.
  EXPECT_NEAR((c0.T_IC.linear() * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitX()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((c0.T_IC.linear() * Eigen::Vector3d::UnitX() + Eigen::Vector3d::UnitY()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((c0.T_IC.translation() - Eigen::Vector3d(0.18875, 0.00175, 0.0555)).norm(), 0.0, 1e-12);
  // Stereo baseline 0.05 m along camera x.
  const Eigen::Vector3d b_C0 = c0.T_IC.inverse() * s.cameras.cameras[1].T_IC.translation();
  EXPECT_NEAR((b_C0 - Eigen::Vector3d(0.05, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_TRUE(s.environment.rope.enabled);
}

TEST(Scenario, UnknownTopLevelKeyNamesFileAndKey) {
  const std::string e = error_of("name: x\nduraton_s: 10\n", "my_scenario.yaml");
  EXPECT_NE(e.find("my_scenario.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("duraton_s"), std::string::npos) << e;
}

TEST(Scenario, UnknownNestedKeyNamesFullPath) {
  const std::string e = error_of("forces:\n  rope:\n    anchor: [0, 0, 0]\n    stifness_N_per_m: 3\n");
  EXPECT_NE(e.find("bad.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("forces.rope.stifness_N_per_m"), std::string::npos) << e;
  const std::string e2 = error_of("cameras:\n  list:\n    - T_imu_cam: [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]\n      focal: 3\n");
  EXPECT_NE(e2.find("cameras.list[0].focal"), std::string::npos) << e2;
}

TEST(Scenario, BadValuesNameTheKey) {
  EXPECT_NE(error_of("imu:\n  rate_hz: fast\n").find("imu.rate_hz"), std::string::npos);
  EXPECT_NE(error_of("vehicle:\n  mass_kg: -2\n").find("vehicle.mass_kg"), std::string::npos);
  EXPECT_NE(error_of("trajectory:\n  yaw: sideways\n").find("trajectory.yaw"), std::string::npos);
  EXPECT_NE(error_of("physics:\n  max_step_s: 0.01\n").find("physics.max_step_s"), std::string::npos);
  EXPECT_NE(error_of("cameras:\n  list:\n    - resolution: [640, 480]\n").find("T_imu_cam"), std::string::npos);
  EXPECT_NE(error_of("cameras:\n  list:\n    - T_cam_imu: [[2,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]\n")
                .find("cameras.list[0].T_cam_imu"),
            std::string::npos);
  EXPECT_NE(error_of("groundtruth:\n  rate_hz: 100\n").find("groundtruth.rate_hz"), std::string::npos);
  EXPECT_NE(error_of("vehicle: [1, 2]\n").find("vehicle"), std::string::npos);
}

TEST(Scenario, SyntaxErrorNamesFileAndLine) {
  const std::string e = error_of("name: x\nvehicle:\n  mass_kg: [1, 2\n", "broken.yaml");
  EXPECT_NE(e.find("broken.yaml:"), std::string::npos) << e;
}

TEST(Scenario, MissingFileIsAConfigError) {
  EXPECT_THROW(load_scenario("/nonexistent/scenario.yaml"), io::ConfigError);
}

TEST(Scenario, BaseFileIsMerged) {
  const auto dir = std::filesystem::temp_directory_path() / "vid_sim_test_base";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "child.yaml") << "base: " << preset("hover") << "\nduration_s: 7\nvehicle:\n  mass_kg: 2.0\n";
  const Scenario s = load_scenario(dir / "child.yaml");
  EXPECT_DOUBLE_EQ(s.duration_s, 7.0);
  EXPECT_DOUBLE_EQ(s.vehicle.mass_kg, 2.0);
  EXPECT_DOUBLE_EQ(s.vehicle.rotors[0].thrust_coeff, 2.6890e-7);  // from the base
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace vid::sim
