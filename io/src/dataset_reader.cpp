#include "io/dataset_reader.h"

#include <set>

#include "io/number_format.h"
#include "io/sensor_yaml.h"
#include "stream_cursors.h"

namespace vid::io {
namespace fs = std::filesystem;

namespace {

const char* const kStreamNames[] = {"imu0",   "cam0",  "cam1",  "feat0", "rotor0",
                                    "thrust0", "force0", "mass0", "state_groundtruth_estimate0"};
constexpr int kMaxCameras = 8;

bool is_dir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}
bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

/// SEQ or SEQ/mav0 -> the folder holding the sensor folders.
fs::path resolve_mav0(const fs::path& root) {
  if (!is_dir(root)) throw DatasetError(root.string() + ": no such dataset folder");
  if (is_dir(root / "mav0")) return fs::absolute(root / "mav0");
  for (const char* s : kStreamNames) {
    if (is_dir(root / s)) return fs::absolute(root);
  }
  throw DatasetError(root.string() + ": not a dataset folder (no mav0/, imu0/, cam0/ or feat0/ inside)");
}

void require_file(const fs::path& p, const std::string& why) {
  if (!is_file(p)) throw DatasetError(p.string() + ": missing file (required " + why + ")");
}

Eigen::Vector3d vec3(const CsvReader& c, std::size_t first, const char* const names[3]) {
  return Eigen::Vector3d(c.get_double(first, names[0]), c.get_double(first + 1, names[1]),
                         c.get_double(first + 2, names[2]));
}

}  // namespace

struct DatasetReader::Impl {
  fs::path mav0;
  ReaderOptions options;
  DatasetCalibration calib;
  std::set<std::string> present;
  std::vector<std::unique_ptr<detail::Cursor>> cursors;  // in tie-break order

  void load_calibration();
  void open_streams();
};

void DatasetReader::Impl::load_calibration() {
  if (is_file(mav0 / "imu0" / "sensor.yaml")) calib.imu = load_imu_yaml(mav0 / "imu0" / "sensor.yaml");
  const bool has_feat = present.count("feat0") > 0;
  for (int id = 0; id < kMaxCameras; ++id) {
    const std::string cam = "cam" + std::to_string(id);
    const fs::path yaml = mav0 / cam / "sensor.yaml";
    if (present.count(cam)) require_file(yaml, "for " + cam + "/data.csv");
    if (is_file(yaml)) calib.cameras.push_back(load_camera_yaml(yaml, id));
  }
  if (has_feat && calib.cameras.empty()) require_file(mav0 / "cam0" / "sensor.yaml", "for feat0/data.csv");
  if (present.count("rotor0")) require_file(mav0 / "rotor0" / "sensor.yaml", "for rotor0/data.csv");
  if (is_file(mav0 / "rotor0" / "sensor.yaml")) calib.rotor = load_rotor_yaml(mav0 / "rotor0" / "sensor.yaml");
  if (is_file(mav0 / "vehicle.yaml")) {
    calib.vehicle = load_vehicle_yaml(mav0 / "vehicle.yaml");
    const auto& k = calib.vehicle->rotor_thrust_coefficients;
    if (calib.rotor && !k.empty() && static_cast<int>(k.size()) != calib.rotor->count) {
      throw ConfigError((mav0 / "vehicle.yaml").string() + ": key 'rotor_thrust_coefficients': " +
                        std::to_string(k.size()) + " coefficients but rotor0/sensor.yaml has count " +
                        std::to_string(calib.rotor->count));
    }
  }
}

void DatasetReader::Impl::open_streams() {
  using detail::make_row_cursor;
  const ReaderOptions& o = options;
  auto csv = [&](const std::string& s) { return mav0 / s / "data.csv"; };

  static const char* const kGyro[3] = {"w_RS_S_x [rad s^-1]", "w_RS_S_y [rad s^-1]", "w_RS_S_z [rad s^-1]"};
  static const char* const kAcc[3] = {"a_RS_S_x [m s^-2]", "a_RS_S_y [m s^-2]", "a_RS_S_z [m s^-2]"};
  cursors.push_back(make_row_cursor(csv("imu0"), "imu0", 7, [](const CsvReader& c, TimeNs t) -> Measurement {
    return ImuSample{t, vec3(c, 1, kGyro), vec3(c, 4, kAcc)};
  }, o));

  if (present.count("rotor0")) {
    const int n = calib.rotor->count;
    cursors.push_back(make_row_cursor(csv("rotor0"), "rotor0", 1 + n, [n](const CsvReader& c, TimeNs t) -> Measurement {
      RotorSample s{t, {}};
      for (int i = 0; i < n; ++i) s.speeds.push_back(c.get_double(1 + i, "n_" + std::to_string(i + 1)));
      return s;
    }, o));
  }
  if (present.count("thrust0")) {
    cursors.push_back(make_row_cursor(csv("thrust0"), "thrust0", 2, [](const CsvReader& c, TimeNs t) -> Measurement {
      const double thrust_N = c.get_double(1, "thrust [N]");
      // Collective thrust points along +z of the IMU frame (up): a negative value is a z-down frame.
      if (thrust_N < 0.0)
        c.fail("column 2 'thrust [N]': negative collective thrust " + format_double(thrust_N) +
               " (the thrust points along +z of the IMU frame, z up; a z-down frame needs its data converted)");
      return ThrustSample{t, thrust_N};
    }, o));
  }
  std::vector<int> cams;
  for (int id = 0; id < kMaxCameras; ++id) {
    if (present.count("cam" + std::to_string(id))) cams.push_back(id);
  }
  if (o.read_images && !cams.empty()) cursors.push_back(detail::make_camera_cursor(mav0, cams, o));
  if (o.read_features && present.count("feat0")) {
    std::set<int> calibrated;
    for (const auto& c : calib.cameras) calibrated.insert(c.cam_id);
    cursors.push_back(detail::make_feature_cursor(csv("feat0"), calibrated, o));
  }
  if (!o.read_groundtruth) return;
  if (present.count("force0")) {
    static const char* const kF[3] = {"f_x [N]", "f_y [N]", "f_z [N]"};
    static const char* const kDF[3] = {"dFx/dt [N s^-1]", "dFy/dt [N s^-1]", "dFz/dt [N s^-1]"};
    // 4 columns (force only) or 7 (plus its rate, simulator output since issue #17).
    cursors.push_back(make_row_cursor(csv("force0"), "force0", 4, [](const CsvReader& c, TimeNs t) -> Measurement {
      const bool rate = c.size() == 7;
      return ForceSample{t, vec3(c, 1, kF), rate ? vec3(c, 4, kDF) : Eigen::Vector3d::Zero(), rate};
    }, o, 7));
  }
  if (present.count("mass0")) {
    cursors.push_back(make_row_cursor(csv("mass0"), "mass0", 2, [](const CsvReader& c, TimeNs t) -> Measurement {
      const double m = c.get_double(1, "mass [kg]");
      if (!(m > 0.0)) c.fail("column 2 'mass [kg]': mass must be positive");
      return MassSample{t, m};
    }, o));
  }
  const std::string gt = "state_groundtruth_estimate0";
  if (present.count(gt)) {
    cursors.push_back(make_row_cursor(csv(gt), gt, 17, [](const CsvReader& c, TimeNs t) -> Measurement {
      static const char* const kP[3] = {"p_RS_R_x [m]", "p_RS_R_y [m]", "p_RS_R_z [m]"};
      static const char* const kV[3] = {"v_RS_R_x [m s^-1]", "v_RS_R_y [m s^-1]", "v_RS_R_z [m s^-1]"};
      static const char* const kBw[3] = {"b_w_RS_S_x [rad s^-1]", "b_w_RS_S_y [rad s^-1]", "b_w_RS_S_z [rad s^-1]"};
      static const char* const kBa[3] = {"b_a_RS_S_x [m s^-2]", "b_a_RS_S_y [m s^-2]", "b_a_RS_S_z [m s^-2]"};
      GroundTruthSample s;
      s.t_ns = t;
      s.T_WI.p = vec3(c, 1, kP);
      s.T_WI.q = Eigen::Quaterniond(c.get_double(4, "q_RS_w []"), c.get_double(5, "q_RS_x []"),
                                  c.get_double(6, "q_RS_y []"), c.get_double(7, "q_RS_z []"));
      const double norm = s.T_WI.q.norm();
      if (norm < 0.99 || norm > 1.01) c.fail("quaternion q_RS is not unit length (norm " + std::to_string(norm) + ")");
      s.v_WI = vec3(c, 8, kV);
      s.b_g = vec3(c, 11, kBw);
      s.b_a = vec3(c, 14, kBa);
      return s;
    }, o));
  }
}

DatasetReader::DatasetReader(const fs::path& root, ReaderOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->mav0 = resolve_mav0(root);
  impl_->options = options;
  for (const char* s : kStreamNames) {
    if (is_file(impl_->mav0 / s / "data.csv")) impl_->present.insert(s);
  }
  for (int id = 2; id < kMaxCameras; ++id) {
    const std::string cam = "cam" + std::to_string(id);
    if (is_file(impl_->mav0 / cam / "data.csv")) impl_->present.insert(cam);
  }
  require_file(impl_->mav0 / "imu0" / "data.csv", "in every dataset");
  impl_->load_calibration();
  impl_->open_streams();
}

DatasetReader::~DatasetReader() = default;

std::optional<Measurement> DatasetReader::next() {
  detail::Cursor* best = nullptr;
  for (auto& c : impl_->cursors) {  // strict '<' keeps the tie-break order of cursors
    if (!c->done() && (best == nullptr || c->head_time() < best->head_time())) best = c.get();
  }
  if (best == nullptr) return std::nullopt;
  return best->take();
}

const fs::path& DatasetReader::mav0() const { return impl_->mav0; }
const DatasetCalibration& DatasetReader::calibration() const { return impl_->calib; }
bool DatasetReader::has_stream(const std::string& name) const { return impl_->present.count(name) > 0; }

std::vector<StreamStats> DatasetReader::stats() const {
  std::vector<StreamStats> out;
  for (const auto& c : impl_->cursors) c->stats(&out);
  return out;
}

double DatasetReader::progress() const {
  std::uint64_t done = 0, total = 0;
  for (const auto& c : impl_->cursors) {
    done += c->bytes_read();
    total += c->bytes_total();
  }
  return total == 0 ? 1.0 : static_cast<double>(done) / static_cast<double>(total);
}

}  // namespace vid::io
