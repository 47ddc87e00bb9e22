#include "io/kalibr.h"

#include <sstream>

#include <yaml-cpp/yaml.h>

#include "io/number_format.h"
#include "io/sensor_yaml.h"
#include "io/strict_yaml.h"

namespace vid::io {
namespace {

// Kalibr stores inverses of our transforms. Use the exact matrix inverse (not the rigid R^T
// shortcut) so that file -> struct -> file returns the printed numbers to ~1e-16 even when
// the file's rotation is orthonormal to only ~1e-9.
Eigen::Isometry3d exact_inverse(const Eigen::Isometry3d& T) {
  Eigen::Isometry3d inv;
  inv.matrix() = T.matrix().inverse();
  inv.matrix().row(3) = Eigen::RowVector4d(0, 0, 0, 1);
  return inv;
}

std::string kalibr_matrix(const Eigen::Matrix4d& m, const std::string& indent) {
  std::string out;
  for (int r = 0; r < 4; ++r) {
    out += indent + "- " + format_list({m(r, 0), m(r, 1), m(r, 2), m(r, 3)}) + "\n";
  }
  return out;
}

// OpenVINS' IMU intrinsics (3x3): accepted only at the value that changes nothing.
void require_matrix3(const YamlMap& y, const char* key, const Eigen::Matrix3d& expected) {
  if (!y.has(key)) return;
  const YAML::Node n = y.get_raw(key);
  Eigen::Matrix3d m;
  try {
    if (!n.IsSequence() || n.size() != 3) throw YAML::Exception(YAML::Mark(), "");
    for (int r = 0; r < 3; ++r) {
      if (!n[r].IsSequence() || n[r].size() != 3) throw YAML::Exception(YAML::Mark(), "");
      for (int c = 0; c < 3; ++c) m(r, c) = n[r][c].as<double>();
    }
  } catch (const YAML::Exception&) {
    y.fail(key, "expected a 3x3 matrix (3 rows of 3 numbers)");
  }
  if ((m - expected).cwiseAbs().maxCoeff() > 1e-9)
    y.fail(key, std::string("IMU intrinsics are not modelled: must be ") +
                    (expected.isZero() ? "zero" : "the identity"));
}

ImuNoise imu_from_map(const YamlMap& y) {
  ImuNoise imu;
  imu.accel_noise_density = y.get_double("accelerometer_noise_density");
  imu.accel_random_walk = y.get_double("accelerometer_random_walk");
  imu.gyro_noise_density = y.get_double("gyroscope_noise_density");
  imu.gyro_random_walk = y.get_double("gyroscope_random_walk");
  for (const char* k : {"accelerometer_noise_density", "accelerometer_random_walk", "gyroscope_noise_density",
                        "gyroscope_random_walk"}) {
    if (y.get_double(k) < 0.0) y.fail(k, "must not be negative");
  }
  imu.rate_hz = y.get_double("update_rate");
  if (!(imu.rate_hz > 0.0)) y.fail("update_rate", "must be positive");
  if (y.has("T_i_b")) imu.T_BS = exact_inverse(get_rigid_transform(y, "T_i_b"));
  // The estimator models a calibrated IMU: Kalibr's "calibrated" model (OpenVINS calls it
  // "kalibr" or "rpng" and adds the intrinsic matrices, which must then be the identity / zero).
  // A value that would change the measurements is an error, not silently dropped.
  const std::string model = y.get_string("model", "calibrated");
  if (model != "calibrated" && model != "kalibr" && model != "rpng")
    y.fail("model", "only a calibrated IMU is modelled (Kalibr --imu-models calibrated), got '" + model + "'");
  for (const char* k : {"Tw", "Ta", "R_IMUtoGYRO", "R_IMUtoACC"}) require_matrix3(y, k, Eigen::Matrix3d::Identity());
  require_matrix3(y, "Tg", Eigen::Matrix3d::Zero());
  if (y.get_double("time_offset", 0.0) != 0.0)
    y.fail("time_offset", "must be 0 (the IMU is the time reference; Kalibr's timeshift_cam_imu carries the offset)");
  y.accept("rostopic");
  y.check_unknown();
  return imu;
}

}  // namespace

ImuNoise load_kalibr_imu(const std::filesystem::path& path) {
  const YamlMap root = YamlMap::load_file(path);
  if (root.has("imu0")) {
    const ImuNoise imu = imu_from_map(root.get_map("imu0"));
    root.check_unknown();
    return imu;
  }
  return imu_from_map(root);
}

std::vector<CameraCalib> load_kalibr_imucam(const std::filesystem::path& path) {
  const YamlMap root = YamlMap::load_file(path);
  std::vector<CameraCalib> cams;
  for (int id = 0; root.has("cam" + std::to_string(id)); ++id) {
    const YamlMap y = root.get_map("cam" + std::to_string(id));
    CameraCalib cam;
    cam.cam_id = id;
    // Kalibr's T_cam_imu is T_CI; OpenVINS' files may give T_imu_cam (= T_IC) instead.
    if (y.has("T_cam_imu") && y.has("T_imu_cam"))
      y.fail("T_imu_cam", "give T_cam_imu (Kalibr) or T_imu_cam (OpenVINS), not both");
    cam.T_IC = y.has("T_imu_cam") ? get_rigid_transform(y, "T_imu_cam")
                                  : exact_inverse(get_rigid_transform(y, "T_cam_imu"));
    const std::string model = y.get_string("camera_model", "pinhole");
    if (model != "pinhole") y.fail("camera_model", "only 'pinhole' is supported, got '" + model + "'");
    const std::vector<double> k = y.get_doubles("intrinsics", 4);
    if (!(k[0] > 0.0 && k[1] > 0.0)) y.fail("intrinsics", "focal lengths fu, fv must be positive");
    cam.intrinsics = Eigen::Vector4d(k[0], k[1], k[2], k[3]);
    const std::string dist = y.get_string("distortion_model");
    if (!parse_distortion_model(dist, &cam.distortion) || dist == "radial-tangential") {
      y.fail("distortion_model", "expected radtan or equidistant, got '" + dist + "'");
    }
    const std::vector<double> d = y.get_doubles("distortion_coeffs", 4);
    cam.distortion_coeffs = Eigen::Vector4d(d[0], d[1], d[2], d[3]);
    const std::vector<int> res = y.get_ints("resolution", 2);
    if (res[0] <= 0 || res[1] <= 0) y.fail("resolution", "width and height must be positive");
    cam.width = res[0];
    cam.height = res[1];
    cam.timeshift_cam_imu_s = y.get_double("timeshift_cam_imu", 0.0);
    if (y.has("rate_hz")) cam.rate_hz = y.get_double("rate_hz");  // not Kalibr; written by to_kalibr_imucam_yaml
    if (y.has("T_cn_cnm1")) get_rigid_transform(y, "T_cn_cnm1");  // validated; derivable from T_cam_imu
    for (const char* key : {"cam_overlaps", "rostopic"}) y.accept(key);
    y.check_unknown();
    cams.push_back(cam);
  }
  if (cams.empty()) throw ConfigError(path.string() + ": missing required key 'cam0'");
  root.check_unknown();
  return cams;
}

std::string to_kalibr_imu_yaml(const ImuNoise& imu) {
  std::ostringstream os;
  os << "imu0:\n"
     << "  T_i_b:\n" << kalibr_matrix(exact_inverse(imu.T_BS).matrix(), "  ")
     << "  accelerometer_noise_density: " << format_double(imu.accel_noise_density) << "\n"
     << "  accelerometer_random_walk: " << format_double(imu.accel_random_walk) << "\n"
     << "  gyroscope_noise_density: " << format_double(imu.gyro_noise_density) << "\n"
     << "  gyroscope_random_walk: " << format_double(imu.gyro_random_walk) << "\n"
     << "  model: calibrated\n"
     << "  rostopic: /imu0\n"
     << "  time_offset: 0.0\n"
     << "  update_rate: " << format_double(imu.rate_hz) << "\n";
  return os.str();
}

std::string to_kalibr_imucam_yaml(const std::vector<CameraCalib>& cams) {
  std::ostringstream os;
  for (std::size_t i = 0; i < cams.size(); ++i) {
    const CameraCalib& c = cams[i];
    os << "cam" << i << ":\n"
       << "  T_cam_imu:\n" << kalibr_matrix(exact_inverse(c.T_IC).matrix(), "  ");
    if (i > 0) {
      const Eigen::Isometry3d T_cn_cnm1 = exact_inverse(c.T_IC) * cams[i - 1].T_IC;
      os << "  T_cn_cnm1:\n" << kalibr_matrix(T_cn_cnm1.matrix(), "  ");
    }
    os << "  camera_model: pinhole\n"
       << "  distortion_coeffs: "
       << format_list({c.distortion_coeffs[0], c.distortion_coeffs[1], c.distortion_coeffs[2], c.distortion_coeffs[3]})
       << "\n"
       << "  distortion_model: " << kalibr_name(c.distortion) << "\n"
       << "  intrinsics: " << format_list({c.intrinsics[0], c.intrinsics[1], c.intrinsics[2], c.intrinsics[3]}) << "\n"
       << "  resolution: [" << c.width << ", " << c.height << "]\n"
       << "  rostopic: /cam" << i << "/image_raw\n"
       << "  timeshift_cam_imu: " << format_double(c.timeshift_cam_imu_s) << "\n"
       << "  rate_hz: " << format_double(c.rate_hz) << "\n";
  }
  return os.str();
}

}  // namespace vid::io
