#include "io/dataset_writer.h"

#include <cmath>
#include <fstream>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "io/number_format.h"
#include "io/sensor_yaml.h"

namespace vid::io {
namespace fs = std::filesystem;

namespace {

const char* const kImuHeader =
    "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
    "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]";
const char* const kGtHeader =
    "#timestamp,p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z [],"
    "v_RS_R_x [m s^-1],v_RS_R_y [m s^-1],v_RS_R_z [m s^-1],"
    "b_w_RS_S_x [rad s^-1],b_w_RS_S_y [rad s^-1],b_w_RS_S_z [rad s^-1],"
    "b_a_RS_S_x [m s^-2],b_a_RS_S_y [m s^-2],b_a_RS_S_z [m s^-2]";

/// One data.csv being written: header on creation, strictly increasing timestamps, finite
/// numbers only, flushed after every row.
class CsvOut {
 public:
  CsvOut(const fs::path& path, const std::string& header) : path_(path) {
    std::error_code ec;
    fs::create_directories(path.parent_path(), ec);
    out_.open(path, std::ios::binary | std::ios::trunc);
    if (!out_) throw DatasetError(path.string() + ": cannot create file");
    out_ << header << '\n';
  }
  /// Check that @p t is after the previous record's timestamp and remember it.
  void check_time(TimeNs t) {
    if (t < 0) throw DatasetError(path_.string() + ": cannot write negative timestamp " + std::to_string(t));
    if (records_ > 0 && t <= last_) {
      throw DatasetError(path_.string() + ": cannot write timestamp " + std::to_string(t) +
                         ": not after the previous row's " + std::to_string(last_));
    }
    last_ = t;
    ++records_;
  }
  /// Start a row text at @p t (no order check: rows of one feature frame share it).
  void start_row(TimeNs t) { line_ = std::to_string(t); }
  /// Check order and start a row.
  void begin(TimeNs t) {
    check_time(t);
    start_row(t);
  }
  void add(double v) {
    if (!std::isfinite(v)) {
      throw DatasetError(path_.string() + ": refusing to write a non-finite value at timestamp " + std::to_string(last_));
    }
    line_ += ',';
    line_ += format_double(v);
  }
  void add_text(const std::string& s) {
    line_ += ',';
    line_ += s;
  }
  void add(const Eigen::Vector3d& v) {
    for (int i = 0; i < 3; ++i) add(v[i]);
  }
  /// Write the row and flush.
  void end() {
    out_ << line_ << '\n';
    out_.flush();
    if (!out_) throw DatasetError(path_.string() + ": write failed");
  }
  void close() { out_.close(); }

 private:
  fs::path path_;
  std::ofstream out_;
  std::string line_;
  TimeNs last_ = 0;
  std::size_t records_ = 0;
};

}  // namespace

struct DatasetWriter::Impl {
  fs::path mav0;
  std::map<std::string, std::unique_ptr<CsvOut>> files;
  std::size_t rotor_count = 0;
  int force_rate = -1;  ///< force0 with rate columns: -1 not yet known, 0 no, 1 yes
  bool closed = false;

  CsvOut& file(const std::string& stream, const std::string& header) {
    if (closed) throw DatasetError(mav0.string() + ": writer already closed (cannot write " + stream + ")");
    auto it = files.find(stream);
    if (it == files.end()) {
      it = files.emplace(stream, std::make_unique<CsvOut>(mav0 / stream / "data.csv", header)).first;
    }
    return *it->second;
  }
};

DatasetWriter::DatasetWriter(const fs::path& root) : impl_(std::make_unique<Impl>()) {
  impl_->mav0 = root / "mav0";
  std::error_code ec;
  fs::create_directories(impl_->mav0, ec);
  if (ec) throw DatasetError(impl_->mav0.string() + ": cannot create folder: " + ec.message());
}

DatasetWriter::~DatasetWriter() {
  try {
    close();
  } catch (...) {  // destructors must not throw; close() explicitly to see errors
  }
}

void DatasetWriter::write_imu_calibration(const ImuNoise& imu) {
  write_text_file(impl_->mav0 / "imu0" / "sensor.yaml", to_yaml(imu));
}
void DatasetWriter::write_camera_calibration(const CameraCalib& cam) {
  write_text_file(impl_->mav0 / ("cam" + std::to_string(cam.cam_id)) / "sensor.yaml", to_yaml(cam));
}
void DatasetWriter::write_rotor_calibration(const RotorSensor& rotor) {
  write_text_file(impl_->mav0 / "rotor0" / "sensor.yaml", to_yaml(rotor));
}
void DatasetWriter::write_vehicle(const VehicleParams& vehicle) {
  write_text_file(impl_->mav0 / "vehicle.yaml", to_yaml(vehicle));
}

void DatasetWriter::write(const ImuSample& s) {
  CsvOut& f = impl_->file("imu0", kImuHeader);
  f.begin(s.t_ns);
  f.add(s.gyro_I);
  f.add(s.accel_I);
  f.end();
}

void DatasetWriter::write(const RotorSample& s) {
  if (s.speeds.empty()) throw DatasetError((impl_->mav0 / "rotor0/data.csv").string() + ": rotor sample without speeds");
  if (impl_->rotor_count == 0) impl_->rotor_count = s.speeds.size();
  if (s.speeds.size() != impl_->rotor_count) {
    throw DatasetError((impl_->mav0 / "rotor0/data.csv").string() + ": rotor sample at " + std::to_string(s.t_ns) +
                       " has " + std::to_string(s.speeds.size()) + " speeds, earlier rows have " +
                       std::to_string(impl_->rotor_count));
  }
  std::string header = "#timestamp [ns]";
  for (std::size_t i = 0; i < s.speeds.size(); ++i) header += ",n_" + std::to_string(i + 1);
  CsvOut& f = impl_->file("rotor0", header);
  f.begin(s.t_ns);
  for (double n : s.speeds) f.add(n);
  f.end();
}

void DatasetWriter::write(const ThrustSample& s) {
  CsvOut& f = impl_->file("thrust0", "#timestamp [ns],thrust [N]");
  f.begin(s.t_ns);
  f.add(s.thrust_N);
  f.end();
}

void DatasetWriter::write(const ForceSample& s) {
  // The rate columns are written when the first sample has them (a stream never mixes).
  if (impl_->force_rate < 0) impl_->force_rate = s.has_rate ? 1 : 0;
  if (s.has_rate != (impl_->force_rate == 1)) {
    throw DatasetError((impl_->mav0 / "force0/data.csv").string() + ": force sample at " + std::to_string(s.t_ns) +
                       (s.has_rate ? " has" : " lacks") + " a force rate, earlier rows do not");
  }
  CsvOut& f = impl_->file("force0", s.has_rate ? "#timestamp [ns],f_x [N],f_y [N],f_z [N],"
                                                 "dFx/dt [N s^-1],dFy/dt [N s^-1],dFz/dt [N s^-1]"
                                               : "#timestamp [ns],f_x [N],f_y [N],f_z [N]");
  f.begin(s.t_ns);
  f.add(s.f_W_N);
  if (s.has_rate) f.add(s.df_W_Nps);
  f.end();
}

void DatasetWriter::write(const MassSample& s) {
  CsvOut& f = impl_->file("mass0", "#timestamp [ns],mass [kg]");
  f.begin(s.t_ns);
  f.add(s.mass_kg);
  f.end();
}

void DatasetWriter::write(const GroundTruthSample& s) {
  CsvOut& f = impl_->file("state_groundtruth_estimate0", kGtHeader);
  f.begin(s.t_ns);
  f.add(s.T_WI.p);
  f.add(s.T_WI.q.w());
  f.add(s.T_WI.q.x());
  f.add(s.T_WI.q.y());
  f.add(s.T_WI.q.z());
  f.add(s.v_WI);
  f.add(s.b_g);
  f.add(s.b_a);
  f.end();
}

void DatasetWriter::write(const FeatureFrame& frame) {
  CsvOut& f = impl_->file("feat0", "#timestamp [ns],cam_id,feature_id,u [px],v [px]");
  // One row per observation; the order check applies to the frame, rows share its stamp.
  f.check_time(frame.t_ns);
  for (const FeatureObservation& o : frame.observations) {
    f.start_row(frame.t_ns);
    f.add_text(std::to_string(o.cam_id));
    f.add_text(std::to_string(o.feature_id));
    f.add(o.uv[0]);
    f.add(o.uv[1]);
    f.end();
  }
}

void DatasetWriter::write_image(int cam_id, TimeNs t_ns, const cv::Mat& gray8) {
  const std::string cam = "cam" + std::to_string(cam_id);
  const fs::path png = impl_->mav0 / cam / "data" / (std::to_string(t_ns) + ".png");
  if (gray8.empty() || gray8.type() != CV_8UC1) {
    throw DatasetError(png.string() + ": image must be a non-empty 8-bit grayscale cv::Mat (CV_8UC1)");
  }
  CsvOut& f = impl_->file(cam, "#timestamp [ns],filename");
  f.begin(t_ns);
  std::error_code ec;
  fs::create_directories(png.parent_path(), ec);
  if (!cv::imwrite(png.string(), gray8)) throw DatasetError(png.string() + ": cannot write PNG");
  f.add_text(png.filename().string());
  f.end();
}

void DatasetWriter::close() {
  for (auto& [name, f] : impl_->files) f->close();
  impl_->files.clear();
  impl_->closed = true;
}

const fs::path& DatasetWriter::mav0() const { return impl_->mav0; }

}  // namespace vid::io
