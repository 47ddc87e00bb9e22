/// @file test_kalibr_files.cpp
/// @brief Kalibr's own files load unchanged from a preset folder (tests/data/kalibr_preset:
/// camchain-imucam.yaml and imu.yaml as kalibr_calibrate_imu_camera writes them) and survive
/// file -> loader -> Kalibr writer -> loader; OpenVINS' variants of the two files load too,
/// and values the estimator cannot honour are errors naming file, line and key (issue #25).

#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include "io/kalibr.h"
#include "io_test_util.h"

namespace vid::io::test {
namespace {

const std::filesystem::path kPreset = std::filesystem::path(VID_TEST_DATA_DIR) / "kalibr_preset";

/// @brief Row r of a Kalibr matrix key in the file itself, read with plain yaml-cpp.
Eigen::Matrix4d file_matrix(const std::string& cam, const std::string& key) {
  const YAML::Node n = YAML::LoadFile((kPreset / "camchain-imucam.yaml").string())[cam][key];
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = n[r][c].as<double>();
  return m;
}

TEST(KalibrFiles, LoadUnchangedFromPresetFolder) {
  const std::vector<CameraCalib> cams = load_kalibr_imucam(kPreset / "camchain-imucam.yaml");
  ASSERT_EQ(cams.size(), 2u);
  EXPECT_EQ(cams[0].distortion, DistortionModel::kEquidistant);
  EXPECT_EQ(cams[1].distortion, DistortionModel::kRadTan);
  EXPECT_EQ(cams[0].intrinsics, Eigen::Vector4d(380.81042871360756, 380.81194179427075, 510.29465304840727,
                                                514.3304630538506));
  EXPECT_EQ(cams[1].distortion_coeffs, Eigen::Vector4d(-0.28368365, 0.07451284, -0.00010473, -3.5559e-05));
  EXPECT_EQ(cams[0].width, 1024);
  EXPECT_EQ(cams[1].height, 1024);
  EXPECT_EQ(cams[0].timeshift_cam_imu_s, -0.0027634424425245596);
  EXPECT_EQ(cams[1].timeshift_cam_imu_s, -0.0027683686292743195);
  for (int i = 0; i < 2; ++i) {
    const Eigen::Matrix4d T_CI = file_matrix("cam" + std::to_string(i), "T_cam_imu");
    EXPECT_TRUE((cams[i].T_IC.matrix() * T_CI).isApprox(Eigen::Matrix4d::Identity(), 1e-15)) << i;
  }
  // T_cn_cnm1 is checked as a rigid transform; it agrees with the two T_cam_imu.
  const Eigen::Matrix4d T_c1c0 = (cams[1].T_IC.inverse() * cams[0].T_IC).matrix();
  EXPECT_TRUE(T_c1c0.isApprox(file_matrix("cam1", "T_cn_cnm1"), 1e-12));

  const ImuNoise imu = load_kalibr_imu(kPreset / "imu.yaml");
  EXPECT_EQ(imu.accel_noise_density, 0.0028);
  EXPECT_EQ(imu.accel_random_walk, 0.00086);
  EXPECT_EQ(imu.gyro_noise_density, 0.00016);
  EXPECT_EQ(imu.gyro_random_walk, 2.2e-05);
  EXPECT_EQ(imu.rate_hz, 200.0);
  EXPECT_TRUE(imu.T_BS.matrix().isIdentity(0.0));
}

TEST(KalibrFiles, RoundTripThroughTheKalibrWriter) {
  ScratchDir dir;
  const std::vector<CameraCalib> cams = load_kalibr_imucam(kPreset / "camchain-imucam.yaml");
  write_text(dir.path() / "camchain-imucam.yaml", to_kalibr_imucam_yaml(cams));
  const std::vector<CameraCalib> back = load_kalibr_imucam(dir.path() / "camchain-imucam.yaml");
  ASSERT_EQ(back.size(), cams.size());
  for (std::size_t i = 0; i < cams.size(); ++i) {
    EXPECT_EQ(back[i].cam_id, cams[i].cam_id);
    EXPECT_EQ(back[i].width, cams[i].width);
    EXPECT_EQ(back[i].height, cams[i].height);
    EXPECT_EQ(back[i].intrinsics, cams[i].intrinsics);
    EXPECT_EQ(back[i].distortion, cams[i].distortion);
    EXPECT_EQ(back[i].distortion_coeffs, cams[i].distortion_coeffs);
    EXPECT_EQ(back[i].timeshift_cam_imu_s, cams[i].timeshift_cam_imu_s);
    EXPECT_EQ(back[i].rate_hz, cams[i].rate_hz);
    // One exact matrix inversion each way: equal to rounding.
    EXPECT_TRUE(back[i].T_IC.matrix().isApprox(cams[i].T_IC.matrix(), 1e-15)) << i;
  }
  const ImuNoise imu = load_kalibr_imu(kPreset / "imu.yaml");
  write_text(dir.path() / "imu.yaml", to_kalibr_imu_yaml(imu));
  const ImuNoise imu2 = load_kalibr_imu(dir.path() / "imu.yaml");
  EXPECT_EQ(imu2.accel_noise_density, imu.accel_noise_density);
  EXPECT_EQ(imu2.accel_random_walk, imu.accel_random_walk);
  EXPECT_EQ(imu2.gyro_noise_density, imu.gyro_noise_density);
  EXPECT_EQ(imu2.gyro_random_walk, imu.gyro_random_walk);
  EXPECT_EQ(imu2.rate_hz, imu.rate_hz);
  EXPECT_EQ(imu2.T_BS.matrix(), imu.T_BS.matrix());
  // The written files are Kalibr's layout again: a second pass writes the same text.
  EXPECT_EQ(to_kalibr_imu_yaml(imu2), to_kalibr_imu_yaml(imu));
}

// OpenVINS ships its configs as kalibr_imu_chain.yaml / kalibr_imucam_chain.yaml: the camera
// pose as T_imu_cam (T_IC), no timeshift, the IMU with model "kalibr" and identity intrinsics.
const char* const kOpenVinsImucam = R"(%YAML:1.0

cam0:
  T_imu_cam: #rotation from camera to IMU R_CtoI, position of camera in IMU p_CinI
    - [0.0, 0.0, 1.0, 0.18875]
    - [-1.0, 0.0, 0.0, 0.00175]
    - [0.0, -1.0, 0.0, 0.0555]
    - [0.0, 0.0, 0.0, 1.0]
  cam_overlaps: [1]
  camera_model: pinhole
  distortion_coeffs: [0.0, 0.0, 0.0, 0.0]
  distortion_model: radtan
  intrinsics: [382.59, 382.59, 323.42, 242.07] #fu, fv, cu, cv
  resolution: [640, 480]
  rostopic: /cam0/image_raw
)";

const char* const kOpenVinsImu = R"(%YAML:1.0

imu0:
  T_i_b:
    - [1.0, 0.0, 0.0, 0.0]
    - [0.0, 1.0, 0.0, 0.0]
    - [0.0, 0.0, 1.0, 0.0]
    - [0.0, 0.0, 0.0, 1.0]
  accelerometer_noise_density: 2.0000e-3
  accelerometer_random_walk: 3.0000e-3
  gyroscope_noise_density: 1.6968e-04
  gyroscope_random_walk: 1.9393e-05
  rostopic: /imu0
  time_offset: 0.0
  update_rate: 200.0
  model: "kalibr"
  Tw:
    - [ 1.0, 0.0, 0.0 ]
    - [ 0.0, 1.0, 0.0 ]
    - [ 0.0, 0.0, 1.0 ]
  R_IMUtoGYRO:
    - [ 1.0, 0.0, 0.0 ]
    - [ 0.0, 1.0, 0.0 ]
    - [ 0.0, 0.0, 1.0 ]
  Ta:
    - [ 1.0, 0.0, 0.0 ]
    - [ 0.0, 1.0, 0.0 ]
    - [ 0.0, 0.0, 1.0 ]
  R_IMUtoACC:
    - [ 1.0, 0.0, 0.0 ]
    - [ 0.0, 1.0, 0.0 ]
    - [ 0.0, 0.0, 1.0 ]
  Tg:
    - [ 0.0, 0.0, 0.0 ]
    - [ 0.0, 0.0, 0.0 ]
    - [ 0.0, 0.0, 0.0 ]
)";

std::string edited(std::string text, const std::string& from, const std::string& to) {
  text.replace(text.find(from), from.size(), to);
  return text;
}

TEST(KalibrFiles, OpenVinsChainsLoad) {
  ScratchDir dir;
  write_text(dir.path() / "kalibr_imucam_chain.yaml", kOpenVinsImucam);
  const std::vector<CameraCalib> cams = load_kalibr_imucam(dir.path() / "kalibr_imucam_chain.yaml");
  ASSERT_EQ(cams.size(), 1u);
  EXPECT_EQ(cams[0].T_IC.translation(), Eigen::Vector3d(0.18875, 0.00175, 0.0555));  // taken as it is
  EXPECT_EQ(cams[0].timeshift_cam_imu_s, 0.0);
  write_text(dir.path() / "kalibr_imu_chain.yaml", kOpenVinsImu);
  EXPECT_EQ(load_kalibr_imu(dir.path() / "kalibr_imu_chain.yaml").gyro_random_walk, 1.9393e-05);
}

TEST(KalibrFiles, ValuesTheEstimatorCannotHonourAreErrors) {
  ScratchDir dir;
  const auto p = dir.path() / "f.yaml";
  auto imu_error = [&](const std::string& text) {
    write_text(p, text);
    return config_error([&] { load_kalibr_imu(p); });
  };
  EXPECT_EQ(imu_error(edited(kOpenVinsImu, "model: \"kalibr\"", "model: scale-misalignment")),
            p.string() + ":16: key 'imu0.model': only a calibrated IMU is modelled (Kalibr --imu-models "
                         "calibrated), got 'scale-misalignment'");
  EXPECT_EQ(imu_error(edited(kOpenVinsImu, "Ta:\n    - [ 1.0, 0.0, 0.0 ]", "Ta:\n    - [ 1.01, 0.0, 0.0 ]")),
            p.string() + ":26: key 'imu0.Ta': IMU intrinsics are not modelled: must be the identity");
  EXPECT_EQ(imu_error(edited(kOpenVinsImu, "Tg:\n    - [ 0.0, 0.0, 0.0 ]", "Tg:\n    - [ 0.0, 0.0, 0.001 ]")),
            p.string() + ":34: key 'imu0.Tg': IMU intrinsics are not modelled: must be zero");
  EXPECT_EQ(imu_error(edited(kOpenVinsImu, "Tw:\n    - [ 1.0, 0.0, 0.0 ]", "Tw:\n    - [ 1.0, 0.0 ]")),
            p.string() + ":18: key 'imu0.Tw': expected a 3x3 matrix (3 rows of 3 numbers)");
  EXPECT_EQ(imu_error(edited(kOpenVinsImu, "time_offset: 0.0", "time_offset: 0.004")),
            p.string() + ":14: key 'imu0.time_offset': must be 0 (the IMU is the time reference; Kalibr's "
                         "timeshift_cam_imu carries the offset)");
  write_text(p, edited(kOpenVinsImucam, "  cam_overlaps", "  T_cam_imu: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], "
                                                          "[0, 0, 0, 1]]\n  cam_overlaps"));
  EXPECT_EQ(config_error([&] { load_kalibr_imucam(p); }),
            p.string() + ":5: key 'cam0.T_imu_cam': give T_cam_imu (Kalibr) or T_imu_cam (OpenVINS), not both");
  write_text(p, edited(kOpenVinsImucam, "T_imu_cam:", "T_imucam:"));
  EXPECT_EQ(config_error([&] { load_kalibr_imucam(p); }), p.string() + ": missing required key 'cam0.T_cam_imu'");
}

}  // namespace
}  // namespace vid::io::test
