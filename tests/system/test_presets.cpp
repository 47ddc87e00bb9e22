/// Every preset in config/ resolves through vid_run's config resolution, with the values the
/// preset documents (EuRoC's published calibration, VID-Dataset's, the simulator's noise).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>

#include "io/errors.h"
#include "io/strict_yaml.h"
#include "vid_system/config.h"

namespace vid::system {
namespace {

namespace fs = std::filesystem;
const fs::path kConfig = fs::path(VID_SOURCE_DIR) / "config";

// Kalibr's own output files, unchanged, as a preset (issue #25): the cameras come from
// camchain-imucam.yaml, the IMU noise of imu.yaml reaches the estimator's parameters.
TEST(Presets, KalibrFilesAsTheyAreFormAPreset) {
  const SystemConfig cfg = resolve_config(fs::path(VID_TEST_DATA_DIR) / "kalibr_preset", io::DatasetCalibration{});
  ASSERT_EQ(cfg.cameras.size(), 2u);
  EXPECT_EQ(cfg.cameras[0].distortion, DistortionModel::kEquidistant);
  EXPECT_EQ(cfg.cameras[1].timeshift_cam_imu_s, -0.0027683686292743195);
  EXPECT_EQ(cfg.estimator.accel_noise_density, 0.0028);
  EXPECT_EQ(cfg.estimator.gyro_random_walk, 2.2e-05);
  EXPECT_EQ(cfg.estimator.imu_rate_hz, 200.0);
  EXPECT_NE(cfg.sources.at("cameras").find("camchain-imucam.yaml"), std::string::npos);
  EXPECT_NE(cfg.sources.at("imu").find("imu.yaml"), std::string::npos);
}

TEST(Presets, EurocIsImuModeWithPublishedCalibration) {
  const SystemConfig cfg = resolve_config(kConfig / "euroc", io::DatasetCalibration{});
  ASSERT_TRUE(cfg.preset_mode.has_value());
  EXPECT_EQ(*cfg.preset_mode, PropagationMode::kImu);
  EXPECT_DOUBLE_EQ(cfg.estimator.init_sigma_time_offset, 0.005);  // real data: t_d online (#23, docs/notes/time-offset.md)
  ASSERT_EQ(cfg.cameras.size(), 2u);
  const CameraCalib& c0 = cfg.cameras[0];
  const CameraCalib& c1 = cfg.cameras[1];
  EXPECT_EQ(c0.width, 752);
  EXPECT_EQ(c0.height, 480);
  EXPECT_DOUBLE_EQ(c0.intrinsics[0], 458.654);
  EXPECT_DOUBLE_EQ(c0.intrinsics[1], 457.296);
  EXPECT_DOUBLE_EQ(c0.intrinsics[2], 367.215);
  EXPECT_DOUBLE_EQ(c0.intrinsics[3], 248.375);
  EXPECT_EQ(c0.distortion, DistortionModel::kRadTan);
  ASSERT_EQ(c0.distortion_coeffs.size(), 4);
  EXPECT_DOUBLE_EQ(c0.distortion_coeffs[0], -0.28340811);
  EXPECT_DOUBLE_EQ(c0.distortion_coeffs[3], 1.76187114e-05);
  EXPECT_DOUBLE_EQ(c1.intrinsics[0], 457.587);
  EXPECT_DOUBLE_EQ(c1.intrinsics[3], 255.238);
  EXPECT_DOUBLE_EQ(c1.distortion_coeffs[1], 0.07451284);
  EXPECT_DOUBLE_EQ(c1.distortion_coeffs[3], -3.55590700e-05);

  // T_IC must equal EuRoC's camN/sensor.yaml T_BS (the file stores the inverse, T_cam_imu).
  Eigen::Matrix4d T_BS0, T_BS1;
  T_BS0 << 0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975, 0.999557249008, 0.0149672133247,
      0.025715529948, -0.064676986768, -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949, 0, 0, 0,
      1;
  T_BS1 << 0.0125552670891, -0.999755099723, 0.0182237714554, -0.0198435579556, 0.999598781151, 0.0130119051815,
      0.0251588363115, 0.0453689425024, -0.0253898008918, 0.0179005838253, 0.999517347078, 0.00786212447038, 0, 0, 0,
      1;
  EXPECT_LT((c0.T_IC.matrix() - T_BS0).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT((c1.T_IC.matrix() - T_BS1).cwiseAbs().maxCoeff(), 1e-10);
  // EuRoC's stereo baseline is 0.110 m.
  EXPECT_NEAR((c0.T_IC.translation() - c1.T_IC.translation()).norm(), 0.11008, 1e-4);

  ASSERT_TRUE(cfg.imu.has_value());
  EXPECT_DOUBLE_EQ(cfg.estimator.gyro_noise_density, 1.6968e-04);
  EXPECT_DOUBLE_EQ(cfg.estimator.gyro_random_walk, 1.9393e-05);
  EXPECT_DOUBLE_EQ(cfg.estimator.accel_noise_density, 2.0e-3);
  EXPECT_DOUBLE_EQ(cfg.estimator.accel_random_walk, 3.0e-3);
  EXPECT_DOUBLE_EQ(cfg.estimator.imu_rate_hz, 200.0);
  EXPECT_FALSE(cfg.vehicle.has_value());
  EXPECT_EQ(cfg.frontend.num_features, 200);
  EXPECT_NE(cfg.sources.at("frontend"), "defaults");
}

TEST(Presets, VidDatasetIsDynamicsModeWithPublishedCalibration) {
  const SystemConfig cfg = resolve_config(kConfig / "vid_dataset", io::DatasetCalibration{});
  ASSERT_TRUE(cfg.preset_mode.has_value());
  EXPECT_EQ(*cfg.preset_mode, PropagationMode::kDynamics);
  ASSERT_EQ(cfg.cameras.size(), 2u);
  EXPECT_DOUBLE_EQ(cfg.cameras[0].intrinsics[0], 382.59014892578125);
  EXPECT_DOUBLE_EQ(cfg.cameras[0].intrinsics[2], 323.421142578125);
  Eigen::Matrix3d R_IC;
  R_IC << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  EXPECT_LT((cfg.cameras[0].T_IC.rotation() - R_IC).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((cfg.cameras[0].T_IC.translation() - Eigen::Vector3d(0.18875, 0.00175, 0.0555)).norm(), 1e-12);
  EXPECT_NEAR((cfg.cameras[0].T_IC.translation() - cfg.cameras[1].T_IC.translation()).norm(), 0.05, 1e-12);
  ASSERT_TRUE(cfg.vehicle.has_value());
  EXPECT_DOUBLE_EQ(cfg.vehicle->mass_kg, 3.1015);
  ASSERT_EQ(cfg.vehicle->rotor_thrust_coefficients.size(), 4u);
  EXPECT_DOUBLE_EQ(cfg.vehicle->rotor_thrust_coefficients[1], 2.8190e-7);
  ASSERT_TRUE(cfg.rotor.has_value());
  EXPECT_DOUBLE_EQ(cfg.estimator.gyro_noise_density, 0.001);
  EXPECT_DOUBLE_EQ(cfg.estimator.accel_noise_density, 0.100);
  EXPECT_DOUBLE_EQ(cfg.estimator.imu_rate_hz, 400.0);
  EXPECT_DOUBLE_EQ(cfg.estimator.init_sigma_time_offset, 0.005);  // real data: t_d online (#23, docs/notes/time-offset.md)
  EXPECT_NE(cfg.sources.at("frontend"), "defaults");
}

TEST(Presets, SimMatchesTheSimulatorNoiseAndLeavesModeToTheData) {
  const SystemConfig cfg = resolve_config(kConfig / "sim", io::DatasetCalibration{});
  EXPECT_FALSE(cfg.preset_mode.has_value());  // euroc_like (no rotor) must run in imu mode
  EXPECT_TRUE(cfg.cameras.empty());           // cameras come from the simulated folder
  EXPECT_NE(cfg.sources.at("estimator"), "defaults");
  EXPECT_NE(cfg.sources.at("frontend"), "defaults");
  for (const char* scenario : {"vid17_like.yaml", "vid18_like.yaml", "vid_loaded.yaml", "hover.yaml"}) {
    SCOPED_TRACE(scenario);
    const io::YamlMap imu = io::YamlMap::load_file(kConfig / "sim" / scenario).get_map("imu");
    EXPECT_DOUBLE_EQ(cfg.estimator.gyro_noise_density, imu.get_double("gyroscope_noise_density"));
    EXPECT_DOUBLE_EQ(cfg.estimator.gyro_random_walk, imu.get_double("gyroscope_random_walk"));
    EXPECT_DOUBLE_EQ(cfg.estimator.accel_noise_density, imu.get_double("accelerometer_noise_density"));
    EXPECT_DOUBLE_EQ(cfg.estimator.accel_random_walk, imu.get_double("accelerometer_random_walk"));
    EXPECT_DOUBLE_EQ(cfg.estimator.imu_rate_hz, imu.get_double("rate_hz"));
  }
}

TEST(Presets, DatasetImuCalibrationOverridesPresetNoise) {
  io::DatasetCalibration ds;
  ImuNoise imu;
  imu.gyro_noise_density = 0.123;
  imu.gyro_random_walk = 0.0123;
  imu.accel_noise_density = 0.456;
  imu.accel_random_walk = 0.0456;
  imu.rate_hz = 250.0;
  ds.imu = imu;
  const SystemConfig cfg = resolve_config(kConfig / "sim", ds);
  EXPECT_DOUBLE_EQ(cfg.estimator.gyro_noise_density, 0.123);
  EXPECT_DOUBLE_EQ(cfg.estimator.accel_random_walk, 0.0456);
  EXPECT_DOUBLE_EQ(cfg.estimator.imu_rate_hz, 250.0);
}

// One fact, one file (issue #50): the IMU calibration owns the noise, vehicle.yaml gravity. A
// preset's estimator.yaml value they replace with another is reported, one line per key naming
// both files; an equal value or a key the preset does not set is not.
TEST(Presets, EstimatorValuesReplacedByCalibrationFilesAreReported) {
  const fs::path dir = fs::temp_directory_path() / "vid_run_test_preset_override";
  fs::create_directories(dir);
  std::ofstream(dir / "estimator.yaml") << "accel_noise_density: 0.1\ngyro_noise_density: 0.5\ngravity: 9.81\n";
  io::DatasetCalibration ds;
  ImuNoise imu;
  imu.accel_noise_density = 0.025;
  imu.gyro_noise_density = 0.5;
  ds.imu = imu;
  VehicleParams vehicle;
  vehicle.gravity = 9.80665;
  ds.vehicle = vehicle;
  const SystemConfig cfg = resolve_config(dir, ds);
  EXPECT_DOUBLE_EQ(cfg.estimator.accel_noise_density, 0.025);
  EXPECT_DOUBLE_EQ(cfg.estimator.gravity, 9.80665);
  ASSERT_EQ(cfg.overrides.size(), 2u);
  EXPECT_NE(cfg.overrides[0].find("accel_noise_density 0.1 is replaced by dataset imu0/sensor.yaml's 0.025"),
            std::string::npos) << cfg.overrides[0];
  EXPECT_NE(cfg.overrides[0].find((dir / "estimator.yaml").string()), std::string::npos) << cfg.overrides[0];
  EXPECT_NE(cfg.overrides[1].find("gravity 9.81 is replaced by dataset vehicle.yaml's 9.80665"), std::string::npos)
      << cfg.overrides[1];
  // The shipped presets set none of what the calibration files own.
  // (gravity 9.81 is theirs where a dataset may have no vehicle.yaml: here it differs, 9.80665.)
  for (const char* preset : {"sim", "euroc", "vid_dataset"})
    for (const std::string& line : resolve_config(kConfig / preset, ds).overrides)
      EXPECT_NE(line.find(": gravity 9.81 is replaced"), std::string::npos) << preset << ": " << line;
  fs::remove_all(dir);
}

TEST(Presets, EstimatorFileWithoutModeKeyLeavesModeOpen) {
  const fs::path dir = fs::temp_directory_path() / "vid_run_test_preset_nomode";
  fs::create_directories(dir);
  std::ofstream(dir / "estimator.yaml") << "window_size: 7\n";
  const SystemConfig cfg = resolve_config(dir / "estimator.yaml", io::DatasetCalibration{});
  EXPECT_FALSE(cfg.preset_mode.has_value());
  EXPECT_EQ(cfg.estimator.window_size, 7);
  std::ofstream(dir / "estimator.yaml") << "mode: imu\n";
  EXPECT_EQ(resolve_config(dir, io::DatasetCalibration{}).preset_mode, PropagationMode::kImu);
  fs::remove_all(dir);
}

TEST(Presets, BadPresetPathsAreConfigErrors) {
  EXPECT_THROW(resolve_config(kConfig / "no_such_preset", io::DatasetCalibration{}), io::ConfigError);
  // A folder without any preset file (e.g. a mistyped parent folder) is refused, not ignored.
  const fs::path empty = fs::temp_directory_path() / "vid_run_test_preset_empty";
  fs::create_directories(empty);
  try {
    resolve_config(empty, io::DatasetCalibration{});
    ADD_FAILURE() << "no exception";
  } catch (const io::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("not a preset"), std::string::npos) << e.what();
  }
  fs::remove_all(empty);
  // Unknown keys in a preset name file and key.
  const fs::path dir = fs::temp_directory_path() / "vid_run_test_preset_typo";
  fs::create_directories(dir);
  std::ofstream(dir / "estimator.yaml") << "windw_size: 7\n";
  try {
    resolve_config(dir, io::DatasetCalibration{});
    ADD_FAILURE() << "no exception";
  } catch (const io::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("windw_size"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace vid::system
