#include "io/sensor_yaml.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "io/number_format.h"

namespace vid::io {
namespace {

std::string matrix_data(const Eigen::Matrix4d& m) {
  std::vector<double> v;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) v.push_back(m(r, c));
  return format_list(v);
}

std::vector<double> to_vec(const Eigen::Vector4d& v) { return {v[0], v[1], v[2], v[3]}; }

void check_sensor_type(const YamlMap& y, const std::string& expected) {
  if (!y.has("sensor_type")) return;
  const std::string t = y.get_string("sensor_type");
  if (t != expected) y.fail("sensor_type", "expected '" + expected + "', got '" + t + "'");
}

void require_positive(const YamlMap& y, const std::string& key, double v) {
  if (!(v > 0.0)) y.fail(key, "must be positive, got " + format_double(v));
}
void require_non_negative(const YamlMap& y, const std::string& key, double v) {
  if (v < 0.0) y.fail(key, "must not be negative, got " + format_double(v));
}

}  // namespace

bool parse_distortion_model(const std::string& name, DistortionModel* model) {
  if (name == "radial-tangential" || name == "radtan") {
    *model = DistortionModel::kRadTan;
  } else if (name == "equidistant" || name == "equi") {
    *model = DistortionModel::kEquidistant;
  } else if (name == "none") {
    *model = DistortionModel::kNone;
  } else {
    return false;
  }
  return true;
}

std::string euroc_name(DistortionModel model) {
  switch (model) {
    case DistortionModel::kRadTan: return "radial-tangential";
    case DistortionModel::kEquidistant: return "equidistant";
    case DistortionModel::kNone: return "none";
  }
  return "none";
}

std::string kalibr_name(DistortionModel model) {
  return model == DistortionModel::kRadTan ? "radtan" : euroc_name(model);
}

Eigen::Isometry3d get_rigid_transform(const YamlMap& map, const std::string& key) {
  const Eigen::Matrix4d m = map.get_matrix4(key);
  const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
  if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 || R.determinant() < 0.0) {
    map.fail(key, "rotation part is not a rotation matrix (R^T R != I or det < 0)");
  }
  if (m.row(3) != Eigen::RowVector4d(0, 0, 0, 1)) map.fail(key, "last row must be [0, 0, 0, 1]");
  Eigen::Isometry3d T;
  T.matrix() = m;
  return T;
}

CameraCalib load_camera_yaml(const std::filesystem::path& path, int cam_id) {
  const YamlMap y = YamlMap::load_file(path);
  CameraCalib cam;
  cam.cam_id = cam_id;
  check_sensor_type(y, "camera");
  y.accept("comment");
  cam.T_IC = get_rigid_transform(y, "T_BS");
  cam.rate_hz = y.get_double("rate_hz", cam.rate_hz);
  require_positive(y, "rate_hz", cam.rate_hz);
  const std::vector<int> res = y.get_ints("resolution", 2);
  if (res[0] <= 0 || res[1] <= 0) y.fail("resolution", "width and height must be positive");
  cam.width = res[0];
  cam.height = res[1];
  const std::string model = y.get_string("camera_model", "pinhole");
  if (model != "pinhole") y.fail("camera_model", "only 'pinhole' is supported, got '" + model + "'");
  const std::vector<double> k = y.get_doubles("intrinsics", 4);
  if (!(k[0] > 0.0 && k[1] > 0.0)) y.fail("intrinsics", "focal lengths fu, fv must be positive");
  cam.intrinsics = Eigen::Vector4d(k[0], k[1], k[2], k[3]);
  const std::string dist = y.get_string("distortion_model");
  if (!parse_distortion_model(dist, &cam.distortion)) {
    y.fail("distortion_model", "expected radial-tangential, radtan or equidistant, got '" + dist + "'");
  }
  const std::vector<double> d = y.get_doubles("distortion_coefficients", 4);
  cam.distortion_coeffs = Eigen::Vector4d(d[0], d[1], d[2], d[3]);
  cam.timeshift_cam_imu_s = y.get_double("timeshift_cam_imu", 0.0);
  y.check_unknown();
  return cam;
}

ImuNoise load_imu_yaml(const std::filesystem::path& path) {
  const YamlMap y = YamlMap::load_file(path);
  ImuNoise imu;
  check_sensor_type(y, "imu");
  y.accept("comment");
  if (y.has("T_BS")) imu.T_BS = get_rigid_transform(y, "T_BS");
  imu.rate_hz = y.get_double("rate_hz");
  require_positive(y, "rate_hz", imu.rate_hz);
  imu.gyro_noise_density = y.get_double("gyroscope_noise_density");
  imu.gyro_random_walk = y.get_double("gyroscope_random_walk");
  imu.accel_noise_density = y.get_double("accelerometer_noise_density");
  imu.accel_random_walk = y.get_double("accelerometer_random_walk");
  for (const char* k : {"gyroscope_noise_density", "gyroscope_random_walk", "accelerometer_noise_density",
                        "accelerometer_random_walk"}) {
    require_non_negative(y, k, y.get_double(k));
  }
  y.check_unknown();
  return imu;
}

RotorSensor load_rotor_yaml(const std::filesystem::path& path) {
  const YamlMap y = YamlMap::load_file(path);
  RotorSensor r;
  check_sensor_type(y, "rotor_speed");
  y.accept("comment");
  r.unit = y.get_string("unit");
  if (r.unit != "rpm" && r.unit != "rad/s") y.fail("unit", "expected 'rpm' or 'rad/s', got '" + r.unit + "'");
  r.count = y.get_int("count");
  if (r.count <= 0) y.fail("count", "must be a positive number of rotors, got " + std::to_string(r.count));
  r.rate_hz = y.get_double("rate_hz");
  require_positive(y, "rate_hz", r.rate_hz);
  r.noise_density = y.get_double("noise_density", r.noise_density);
  require_non_negative(y, "noise_density", r.noise_density);
  y.check_unknown();
  return r;
}

VehicleParams load_vehicle_yaml(const std::filesystem::path& path) {
  const YamlMap y = YamlMap::load_file(path);
  VehicleParams v;
  v.mass_kg = y.get_double("mass_kg");
  require_positive(y, "mass_kg", v.mass_kg);
  v.gravity = y.get_double("gravity", v.gravity);
  require_positive(y, "gravity", v.gravity);
  if (y.has("rotor_thrust_coefficients")) {
    v.rotor_thrust_coefficients = y.get_doubles("rotor_thrust_coefficients");
    for (double k : v.rotor_thrust_coefficients) require_positive(y, "rotor_thrust_coefficients", k);
  }
  if (y.has("linear_drag")) {
    const std::vector<double> d = y.get_doubles("linear_drag");
    if (d.size() != 3) y.fail("linear_drag", "needs 3 values [D_x, D_y, D_z] (1/s), got " + std::to_string(d.size()));
    for (double k : d) require_non_negative(y, "linear_drag", k);
    v.linear_drag = Eigen::Vector3d(d[0], d[1], d[2]);
  }
  if (y.has("thrust_axis")) {
    const std::vector<double> a = y.get_doubles("thrust_axis");
    if (a.size() != 3) y.fail("thrust_axis", "needs 3 values (a direction in the IMU frame), got " + std::to_string(a.size()));
    const Eigen::Vector3d axis(a[0], a[1], a[2]);
    if (!(axis.norm() > 0.0) || !(axis.z() > 0.0))
      y.fail("thrust_axis", "must point up in the IMU frame (z > 0); a z-down IMU needs its frame converted");
    v.thrust_axis_I = axis.normalized();
  }
  y.check_unknown();
  return v;
}

std::string to_yaml(const CameraCalib& cam) {
  std::ostringstream os;
  os << "# General sensor definitions.\n"
     << "sensor_type: camera\n"
     << "comment: cam" << cam.cam_id << " (written by vid_io)\n\n"
     << "# Sensor extrinsics wrt. the body-frame (T_IC: pose of the camera in the IMU frame).\n"
     << "T_BS:\n  cols: 4\n  rows: 4\n  data: " << matrix_data(cam.T_IC.matrix()) << "\n\n"
     << "# Camera specific definitions.\n"
     << "rate_hz: " << format_double(cam.rate_hz) << "\n"
     << "resolution: [" << cam.width << ", " << cam.height << "]\n"
     << "camera_model: pinhole\n"
     << "intrinsics: " << format_list(to_vec(cam.intrinsics)) << " #fu, fv, cu, cv\n"
     << "distortion_model: " << euroc_name(cam.distortion) << "\n"
     << "distortion_coefficients: " << format_list(to_vec(cam.distortion_coeffs)) << "\n";
  if (cam.timeshift_cam_imu_s != 0.0) {
    os << "timeshift_cam_imu: " << format_double(cam.timeshift_cam_imu_s) << "  # [s] t_imu = t_cam + shift\n";
  }
  return os.str();
}

std::string to_yaml(const ImuNoise& imu) {
  std::ostringstream os;
  os << "#Default imu sensor yaml file\n"
     << "sensor_type: imu\n"
     << "comment: imu0 (written by vid_io)\n\n"
     << "# Sensor extrinsics wrt. the body-frame.\n"
     << "T_BS:\n  cols: 4\n  rows: 4\n  data: " << matrix_data(imu.T_BS.matrix()) << "\n"
     << "rate_hz: " << format_double(imu.rate_hz) << "\n\n"
     << "# inertial sensor noise model parameters (static)\n"
     << "gyroscope_noise_density: " << format_double(imu.gyro_noise_density) << "     # [ rad / s / sqrt(Hz) ]\n"
     << "gyroscope_random_walk: " << format_double(imu.gyro_random_walk) << "       # [ rad / s^2 / sqrt(Hz) ]\n"
     << "accelerometer_noise_density: " << format_double(imu.accel_noise_density) << "  # [ m / s^2 / sqrt(Hz) ]\n"
     << "accelerometer_random_walk: " << format_double(imu.accel_random_walk) << "    # [ m / s^3 / sqrt(Hz) ]\n";
  return os.str();
}

std::string to_yaml(const RotorSensor& rotor) {
  std::ostringstream os;
  os << "sensor_type: rotor_speed\n"
     << "unit: " << rotor.unit << "\n"
     << "count: " << rotor.count << "\n"
     << "rate_hz: " << format_double(rotor.rate_hz) << "\n"
     << "noise_density: " << format_double(rotor.noise_density) << "  # unit / sqrt(Hz)\n";
  return os.str();
}

std::string to_yaml(const VehicleParams& vehicle) {
  std::ostringstream os;
  os << "mass_kg: " << format_double(vehicle.mass_kg) << "\n"
     << "gravity: " << format_double(vehicle.gravity) << "  # magnitude, m/s^2\n";
  if (!vehicle.rotor_thrust_coefficients.empty()) {
    os << "rotor_thrust_coefficients: " << format_list(vehicle.rotor_thrust_coefficients) << "  # N / unit^2\n";
  }
  if (!vehicle.linear_drag.isZero(0.0)) {
    os << "linear_drag: " << format_list({vehicle.linear_drag.x(), vehicle.linear_drag.y(), vehicle.linear_drag.z()})
       << "  # 1/s, mass-normalized body drag F_I = -diag(D) v_I\n";
  }
  if (vehicle.thrust_axis_I != Eigen::Vector3d::UnitZ()) {
    const Eigen::Vector3d& a = vehicle.thrust_axis_I;
    os << "thrust_axis: " << format_list({a.x(), a.y(), a.z()}) << "  # unit vector in the IMU frame\n";
  }
  return os.str();
}

void write_text_file(const std::filesystem::path& path, const std::string& text) {
  std::error_code ec;
  std::filesystem::create_directories(path.parent_path(), ec);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw DatasetError(path.string() + ": cannot create file");
  out << text;
  out.flush();
  if (!out) throw DatasetError(path.string() + ": write failed");
}

}  // namespace vid::io

namespace vid {
std::ostream& operator<<(std::ostream& os, const CameraCalib& cam) { return os << io::to_yaml(cam); }
std::ostream& operator<<(std::ostream& os, const ImuNoise& imu) { return os << io::to_yaml(imu); }
std::ostream& operator<<(std::ostream& os, const RotorSensor& rotor) { return os << io::to_yaml(rotor); }
std::ostream& operator<<(std::ostream& os, const VehicleParams& vehicle) { return os << io::to_yaml(vehicle); }
}  // namespace vid
