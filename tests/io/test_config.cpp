/// @file test_config.cpp
/// @brief Strict YAML helper, Kalibr imu / imucam chains, EuRoC sensor files and reader
/// options: values, error messages (file, line, key) and print -> load round trips (the
/// estimator's settings: tests/vio_core/test_estimator_params_yaml.cpp).

#include <gtest/gtest.h>

#include <sstream>

#include "io/kalibr.h"
#include "io/reader_options_yaml.h"
#include "io/sensor_yaml.h"
#include "io/strict_yaml.h"
#include "io_test_util.h"

namespace vid::io::test {
namespace {

TEST(StrictYaml, MessagesNameFileLineAndKeyPath) {
  const YamlMap y = YamlMap::load_string("a:\n  b: 1\n  c: x\nd: [1, 2]\ne: 3\n", "cfg.yaml");
  const YamlMap a = y.get_map("a");
  EXPECT_EQ(a.get_int("b"), 1);
  EXPECT_EQ(config_error([&] { a.get_double("c"); }), "cfg.yaml:3: key 'a.c': expected a number, got 'x'");
  EXPECT_EQ(config_error([&] { a.get_double("zz"); }), "cfg.yaml: missing required key 'a.zz'");
  EXPECT_EQ(config_error([&] { y.get_doubles("d", 3); }), "cfg.yaml:4: key 'd': expected 3 numbers, got 2");
  EXPECT_EQ(config_error([&] { y.get_string("d"); }), "cfg.yaml:4: key 'd': expected a string, got a sequence");
  EXPECT_EQ(config_error([&] { y.check_unknown(); }), "cfg.yaml:5: unknown key 'e'");
  EXPECT_EQ(y.get_double("e", 0.0), 3.0);
  EXPECT_EQ(config_error([&] { y.check_unknown(); }), "");
  EXPECT_EQ(config_error([&] { a.check_unknown(); }), "");  // 'c' was read (and failed), so known
  EXPECT_EQ(config_error([&] { y.get_bool("e", false); }), "cfg.yaml:5: key 'e': expected true or false, got '3'");
  EXPECT_EQ(config_error([&] { YamlMap::load_string("- 1\n- 2\n", "list.yaml"); }),
            "list.yaml: empty file or not a YAML mapping");
  EXPECT_NE(config_error([&] { YamlMap::load_string("a: [1\nb: 2\n", "bad.yaml"); }).find("bad.yaml:"),
            std::string::npos);
  EXPECT_EQ(config_error([&] { YamlMap::load_file("/nonexistent/x.yaml"); }), "/nonexistent/x.yaml: missing file");
  EXPECT_EQ(config_error([&] { YamlMap::load_string("x: .nan\n", "n.yaml").get_double("x"); }),
            "n.yaml:1: key 'x': expected a finite number, got '.nan'");
}

// Kalibr's output format for the imu chain (as written by kalibr_calibrate_imu_camera).
const char* const kKalibrImu = R"(%YAML:1.0
imu0:
  T_i_b:
    - [1.0, 0.0, 0.0, 0.1]
    - [0.0, 1.0, 0.0, 0.0]
    - [0.0, 0.0, 1.0, 0.0]
    - [0.0, 0.0, 0.0, 1.0]
  accelerometer_noise_density: 2.0000e-03
  accelerometer_random_walk: 3.0000e-03
  gyroscope_noise_density: 1.6968e-04
  gyroscope_random_walk: 1.9393e-05
  model: calibrated
  rostopic: /imu0
  time_offset: 0.0
  update_rate: 200.0
)";

// EuRoC's camchain-imucam in Kalibr's layout.
const char* const kKalibrImucam = R"(cam0:
  T_cam_imu:
  - [0.0148655429818, 0.999557249008, -0.0257744366974, 0.0652229095355]
  - [-0.999880929698, 0.0149672133247, 0.00375618835797, -0.0207063854096]
  - [0.00414029679422, 0.025715529948, 0.999660727178, -0.0080546129139]
  - [0.0, 0.0, 0.0, 1.0]
  cam_overlaps: [1]
  camera_model: pinhole
  distortion_coeffs: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]
  distortion_model: radtan
  intrinsics: [458.654, 457.296, 367.215, 248.375]
  resolution: [752, 480]
  rostopic: /cam0/image_raw
  timeshift_cam_imu: 0.0
cam1:
  T_cam_imu:
  - [0.0125552670891, 0.999755099723, -0.0182237714554, -0.0198435579556]
  - [-0.999598781151, 0.0130119051815, 0.0251588363115, 0.0453689425024]
  - [0.0253898008918, 0.0179005838253, 0.999517347078, 0.00786212447038]
  - [0.0, 0.0, 0.0, 1.0]
  T_cn_cnm1:
  - [0.999997256477, 0.002312067192, 0.000376008102, -0.110073808127]
  - [-0.002317135723, 0.999898048507, 0.014089835846, 0.000399121547]
  - [-0.000343393121, -0.014090668452, 0.999900662638, -0.000853702503]
  - [0.0, 0.0, 0.0, 1.0]
  cam_overlaps: [0]
  camera_model: pinhole
  distortion_coeffs: [0.2, 0.1, -0.05, 0.01]
  distortion_model: equidistant
  intrinsics: [457.587, 456.134, 379.999, 255.238]
  resolution: [752, 480]
  rostopic: /cam1/image_raw
  timeshift_cam_imu: -0.0012
)";

TEST(Kalibr, ImuChainLoads) {
  ScratchDir dir;
  write_text(dir.path() / "imu.yaml", kKalibrImu);
  const ImuNoise imu = load_kalibr_imu(dir.path() / "imu.yaml");
  EXPECT_EQ(imu.accel_noise_density, 2.0e-3);
  EXPECT_EQ(imu.accel_random_walk, 3.0e-3);
  EXPECT_EQ(imu.gyro_noise_density, 1.6968e-4);
  EXPECT_EQ(imu.gyro_random_walk, 1.9393e-5);
  EXPECT_EQ(imu.rate_hz, 200.0);
  EXPECT_EQ(imu.T_BS.translation(), Eigen::Vector3d(-0.1, 0, 0));  // T_BS = T_i_b^-1
  // Kalibr's flat input form (no imu0:) loads as well.
  write_text(dir.path() / "flat.yaml",
             "rostopic: /imu0\nupdate_rate: 400\naccelerometer_noise_density: 0.1\n"
             "accelerometer_random_walk: 0.004\ngyroscope_noise_density: 0.001\ngyroscope_random_walk: 3.5e-5\n");
  EXPECT_EQ(load_kalibr_imu(dir.path() / "flat.yaml").rate_hz, 400.0);
}

TEST(Kalibr, ImuChainErrors) {
  ScratchDir dir;
  std::string bad = kKalibrImu;
  bad.replace(bad.find("  model:"), 8, "  modle:");
  write_text(dir.path() / "typo.yaml", bad);
  EXPECT_EQ(config_error([&] { load_kalibr_imu(dir.path() / "typo.yaml"); }),
            (dir.path() / "typo.yaml").string() + ":12: unknown key 'imu0.modle'");
  std::string missing = kKalibrImu;
  missing.erase(missing.find("  update_rate"));
  write_text(dir.path() / "missing.yaml", missing);
  EXPECT_EQ(config_error([&] { load_kalibr_imu(dir.path() / "missing.yaml"); }),
            (dir.path() / "missing.yaml").string() + ": missing required key 'imu0.update_rate'");
}

TEST(Kalibr, ImucamChainLoadsAndInvertsTCamImu) {
  ScratchDir dir;
  write_text(dir.path() / "camchain.yaml", kKalibrImucam);
  const auto cams = load_kalibr_imucam(dir.path() / "camchain.yaml");
  ASSERT_EQ(cams.size(), 2u);
  EXPECT_EQ(cams[0].cam_id, 0);
  EXPECT_EQ(cams[1].cam_id, 1);
  // cam0's T_cam_imu is the inverse of EuRoC's cam0 T_BS (0.0148655, -0.99988, ...; t = -0.02164, -0.06468, 0.00981).
  EXPECT_NEAR(cams[0].T_IC(0, 1), -0.999880929698, 1e-12);
  EXPECT_NEAR(cams[0].T_IC.translation().x(), -0.0216401454975, 1e-6);
  EXPECT_NEAR(cams[0].T_IC.translation().y(), -0.064676986768, 1e-6);
  EXPECT_EQ(cams[0].distortion, DistortionModel::kRadTan);
  EXPECT_EQ(cams[1].distortion, DistortionModel::kEquidistant);
  EXPECT_EQ(cams[1].timeshift_cam_imu_s, -0.0012);
  EXPECT_EQ(cams[1].intrinsics[3], 255.238);
  EXPECT_EQ(cams[0].width, 752);
  // Stereo baseline of EuRoC is about 0.11 m.
  EXPECT_NEAR((cams[0].T_IC.translation() - cams[1].T_IC.translation()).norm(), 0.110, 0.001);
}

TEST(Kalibr, ImucamChainErrors) {
  ScratchDir dir;
  const auto p = dir.path() / "camchain.yaml";
  auto with = [&](const std::string& from, const std::string& to) {
    std::string s = kKalibrImucam;
    s.replace(s.find(from), from.size(), to);
    write_text(p, s);
    return config_error([&] { load_kalibr_imucam(p); });
  };
  EXPECT_EQ(with("distortion_model: radtan", "distortion_model: fov"),
            p.string() + ":10: key 'cam0.distortion_model': expected radtan or equidistant, got 'fov'");
  EXPECT_EQ(with("camera_model: pinhole", "camera_model: omni"),
            p.string() + ":8: key 'cam0.camera_model': only 'pinhole' is supported, got 'omni'");
  EXPECT_EQ(with("  resolution: [752, 480]\n  rostopic: /cam0", "  resolution: [752]\n  rostopic: /cam0"),
            p.string() + ":12: key 'cam0.resolution': expected 2 integers, got 1");
  EXPECT_EQ(with("  timeshift_cam_imu: 0.0\n", "  timeshift_cam_imu: 0.0\n  focal: 1\n"),
            p.string() + ":15: unknown key 'cam0.focal'");
  EXPECT_EQ(with("cam1:", "cam2:"), p.string() + ":15: unknown key 'cam2'");
  EXPECT_EQ(with("  intrinsics: [458.654, 457.296, 367.215, 248.375]\n", ""),
            p.string() + ": missing required key 'cam0.intrinsics'");
}

TEST(ConfigRoundTrip, KalibrChains) {
  ScratchDir dir;
  write_text(dir.path() / "camchain.yaml", kKalibrImucam);
  const auto cams = load_kalibr_imucam(dir.path() / "camchain.yaml");
  write_text(dir.path() / "out.yaml", to_kalibr_imucam_yaml(cams));
  const auto back = load_kalibr_imucam(dir.path() / "out.yaml");
  ASSERT_EQ(back.size(), cams.size());
  for (std::size_t i = 0; i < cams.size(); ++i) {
    EXPECT_TRUE(back[i].T_IC.matrix().isApprox(cams[i].T_IC.matrix(), 1e-14));
    EXPECT_EQ(back[i].intrinsics, cams[i].intrinsics);
    EXPECT_EQ(back[i].distortion, cams[i].distortion);
    EXPECT_EQ(back[i].distortion_coeffs, cams[i].distortion_coeffs);
    EXPECT_EQ(back[i].width, cams[i].width);
    EXPECT_EQ(back[i].timeshift_cam_imu_s, cams[i].timeshift_cam_imu_s);
    EXPECT_EQ(back[i].rate_hz, cams[i].rate_hz);
  }
  write_text(dir.path() / "imu.yaml", kKalibrImu);
  const ImuNoise imu = load_kalibr_imu(dir.path() / "imu.yaml");
  write_text(dir.path() / "imu_out.yaml", to_kalibr_imu_yaml(imu));
  const ImuNoise imu2 = load_kalibr_imu(dir.path() / "imu_out.yaml");
  EXPECT_EQ(imu2.accel_noise_density, imu.accel_noise_density);
  EXPECT_EQ(imu2.gyro_random_walk, imu.gyro_random_walk);
  EXPECT_EQ(imu2.rate_hz, imu.rate_hz);
  EXPECT_TRUE(imu2.T_BS.matrix().isApprox(imu.T_BS.matrix(), 1e-15));
}

TEST(ConfigRoundTrip, SensorFilesPrintThemselves) {
  ScratchDir dir;
  CameraCalib cam;
  cam.cam_id = 1;
  cam.intrinsics = Eigen::Vector4d(382.59014892578125, 382.59014892578125, 323.421142578125, 242.06617736816406);
  cam.distortion = DistortionModel::kEquidistant;
  cam.distortion_coeffs = Eigen::Vector4d(0.1, -1.0 / 3.0, 1e-9, 0.0);
  cam.T_IC.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  cam.T_IC.translation() = Eigen::Vector3d(0.18875, 0.00175, 0.0555);
  cam.timeshift_cam_imu_s = 0.0031;
  std::ostringstream os;
  os << cam;
  EXPECT_EQ(os.str(), to_yaml(cam));
  write_text(dir.path() / "cam.yaml", os.str());
  const CameraCalib c2 = load_camera_yaml(dir.path() / "cam.yaml", 1);
  EXPECT_EQ(c2.intrinsics, cam.intrinsics);
  EXPECT_EQ(c2.distortion_coeffs, cam.distortion_coeffs);
  EXPECT_EQ(c2.T_IC.matrix(), cam.T_IC.matrix());
  EXPECT_EQ(c2.timeshift_cam_imu_s, cam.timeshift_cam_imu_s);
  EXPECT_EQ(c2.distortion, cam.distortion);

  VehicleParams v;
  v.mass_kg = 3.1015;
  v.rotor_thrust_coefficients = {2.6890e-7, 2.8190e-7, 2.7263e-7, 2.7741e-7};
  write_text(dir.path() / "vehicle.yaml", to_yaml(v));
  const VehicleParams v2 = load_vehicle_yaml(dir.path() / "vehicle.yaml");
  EXPECT_EQ(v2.mass_kg, v.mass_kg);
  EXPECT_EQ(v2.gravity, v.gravity);
  EXPECT_EQ(v2.rotor_thrust_coefficients, v.rotor_thrust_coefficients);

  RotorSensor r;
  r.unit = "rad/s";
  r.count = 6;
  write_text(dir.path() / "rotor.yaml", to_yaml(r));
  const RotorSensor r2 = load_rotor_yaml(dir.path() / "rotor.yaml");
  EXPECT_EQ(r2.unit, r.unit);
  EXPECT_EQ(r2.count, 6);
  EXPECT_EQ(r2.noise_density, r.noise_density);
  write_text(dir.path() / "rotor_bad.yaml", "unit: rpm\ncount: 4\nrate_hz: 100\nunits: rpm\n");
  EXPECT_EQ(config_error([&] { load_rotor_yaml(dir.path() / "rotor_bad.yaml"); }),
            (dir.path() / "rotor_bad.yaml").string() + ":4: unknown key 'units'");
}

TEST(ReaderOptionsYaml, RoundTripAndStrictKeys) {
  ReaderOptions o;
  o.drop_bad_timestamps = true;
  o.read_images = false;
  std::ostringstream os;
  os << o;
  const ReaderOptions b = load_reader_options(YamlMap::load_string(os.str(), "r.yaml"));
  EXPECT_TRUE(b.drop_bad_timestamps);
  EXPECT_FALSE(b.skip_missing_images);
  EXPECT_FALSE(b.read_images);
  EXPECT_TRUE(b.read_features);
  EXPECT_TRUE(b.read_groundtruth);
  EXPECT_EQ(to_yaml(b), os.str());
  EXPECT_TRUE(b == o);
  EXPECT_FALSE(b == ReaderOptions{});
  EXPECT_EQ(config_error([] { load_reader_options(YamlMap::load_string("read_image: true\n", "r.yaml")); }),
            "r.yaml:1: unknown key 'read_image'");
}

}  // namespace
}  // namespace vid::io::test
