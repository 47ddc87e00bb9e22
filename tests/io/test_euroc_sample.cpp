/// @file test_euroc_sample.cpp
/// @brief The hand-written sample in EuRoC's exact layout (tests/data/euroc_sample) loads.

#include <gtest/gtest.h>

#include "io/dataset_reader.h"
#include "io/sensor_yaml.h"
#include "io_test_util.h"

namespace vid::io::test {
namespace {

const std::filesystem::path kSample = std::filesystem::path(VID_TEST_DATA_DIR) / "euroc_sample";

TEST(EurocSample, LoadsAllStreamsInOrder) {
  DatasetReader reader(kSample);
  EXPECT_EQ(reader.mav0(), std::filesystem::absolute(kSample / "mav0"));
  std::size_t imu = 0, frames = 0, gt = 0;
  TimeNs last = 0;
  ImuSample first_imu;
  GroundTruthSample first_gt;
  while (auto m = reader.next()) {
    EXPECT_GE(stamp_of(*m), last);
    last = stamp_of(*m);
    if (auto* s = std::get_if<ImuSample>(&*m)) {
      if (imu++ == 0) first_imu = *s;
    } else if (auto* f = std::get_if<ImageFrame>(&*m)) {
      ++frames;
      ASSERT_EQ(f->images.size(), 1u);
      EXPECT_TRUE(std::filesystem::exists(f->images[0].path));
    } else if (auto* g = std::get_if<GroundTruthSample>(&*m)) {
      if (gt++ == 0) first_gt = *g;
    }
  }
  EXPECT_EQ(imu, 12u);
  EXPECT_EQ(frames, 2u);
  EXPECT_EQ(gt, 4u);
  EXPECT_EQ(first_imu.t_ns, 1403636579758555392);
  EXPECT_EQ(first_imu.gyro_I.x(), -0.099134701513277898);
  EXPECT_EQ(first_imu.accel_I.z(), -2.4026292499999999);
  EXPECT_EQ(first_gt.T_WI.p.x(), 4.688319);
  EXPECT_EQ(first_gt.T_WI.q.w(), 0.534108);  // EuRoC order w, x, y, z
  EXPECT_EQ(first_gt.T_WI.q.z(), -0.082152);
  EXPECT_EQ(first_gt.b_a.z(), 0.075593);
}

TEST(EurocSample, StatsOfASingleImageStream) {
  ScratchDir dir;
  std::filesystem::copy(kSample, dir.path(), std::filesystem::copy_options::recursive);
  write_text(dir.path() / "mav0/cam0/data.csv", "#timestamp [ns],filename\r\n1403636579813555456,1403636579813555456.png\r\n");
  DatasetReader reader(dir.path());
  while (reader.next()) {
  }
  for (const StreamStats& s : reader.stats()) {
    if (s.name != "cam0") continue;
    EXPECT_EQ(s.count, 1u);
    EXPECT_EQ(s.largest_gap_ns, 0);
    EXPECT_EQ(s.largest_gap_at_ns, 1403636579813555456);  // no gap: the first sample, not 0
  }
}

TEST(EurocSample, CalibrationFromSensorYaml) {
  DatasetReader reader(kSample / "mav0");
  const auto& c = reader.calibration();
  ASSERT_EQ(c.cameras.size(), 1u);
  const CameraCalib& cam = c.cameras[0];
  EXPECT_EQ(cam.width, 752);
  EXPECT_EQ(cam.height, 480);
  EXPECT_EQ(cam.intrinsics, Eigen::Vector4d(458.654, 457.296, 367.215, 248.375));
  EXPECT_EQ(cam.distortion, DistortionModel::kRadTan);
  EXPECT_EQ(cam.distortion_coeffs[3], 1.76187114e-05);
  EXPECT_EQ(cam.T_IC(0, 3), -0.0216401454975);
  EXPECT_EQ(cam.T_IC(1, 0), 0.999557249008);
  EXPECT_EQ(cam.rate_hz, 20.0);
  ASSERT_TRUE(c.imu.has_value());
  EXPECT_EQ(c.imu->gyro_noise_density, 1.6968e-04);
  EXPECT_EQ(c.imu->accel_random_walk, 3.0e-3);
  EXPECT_EQ(c.imu->rate_hz, 200.0);
  EXPECT_FALSE(c.rotor.has_value());
  EXPECT_FALSE(c.vehicle.has_value());
}

TEST(EurocSample, OpenCvYamlHeaderAccepted) {
  ScratchDir dir;
  const std::string yaml = read_text(kSample / "mav0/cam0/sensor.yaml");
  write_text(dir.path() / "cv.yaml", "%YAML:1.0\n" + yaml);
  const CameraCalib a = load_camera_yaml(kSample / "mav0/cam0/sensor.yaml", 0);
  const CameraCalib b = load_camera_yaml(dir.path() / "cv.yaml", 0);
  EXPECT_EQ(a.T_IC.matrix(), b.T_IC.matrix());
  EXPECT_EQ(a.intrinsics, b.intrinsics);
  // OpenCV FileStorage's matrix form (tag and dt) loads too; errors keep the file's line numbers.
  write_text(dir.path() / "cv2.yaml",
             "%YAML:1.0\nrate_hz: 100\ngyroscope_noise_density: 1e-3\ngyroscope_random_walk: 1e-5\n"
             "accelerometer_noise_density: 1e-2\naccelerometer_random_walk: 1e-4\n"
             "T_BS: !!opencv-matrix\n  rows: 4\n  cols: 4\n  dt: d\n"
             "  data: [1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\nbogus: 1\n");
  try {
    load_imu_yaml(dir.path() / "cv2.yaml");
    FAIL() << "unknown key accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), (dir.path() / "cv2.yaml").string() + ":12: unknown key 'bogus'");
  }
}

TEST(EurocSample, ExactEurocFileLayout) {
  // Guard the sample itself: EuRoC's header lines and CRLF endings are what make it a test.
  const std::string imu = read_text(kSample / "mav0/imu0/data.csv");
  EXPECT_EQ(imu.rfind("#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
                      "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\r\n", 0), 0u);
  EXPECT_EQ(read_text(kSample / "mav0/cam0/data.csv").rfind("#timestamp [ns],filename\r\n", 0), 0u);
  EXPECT_EQ(read_text(kSample / "mav0/state_groundtruth_estimate0/data.csv")
                .rfind("#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [],", 0),
            0u);
}

}  // namespace
}  // namespace vid::io::test
