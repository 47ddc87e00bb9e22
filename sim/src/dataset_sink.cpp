#include "sim/dataset_sink.h"

#include <stdexcept>

namespace vid::sim {

DatasetSink::DatasetSink(const std::filesystem::path& root, const Scenario& sc,
                         std::unique_ptr<VisualOutput> visual, const Eigen::Matrix3d& R_GS)
    : writer_(root), visual_(std::move(visual)), R_GS_(R_GS) {
  ImuNoise imu = sc.imu.noise;
  writer_.write_imu_calibration(imu);
  for (const CameraCalib& c : sc.cameras.cameras) writer_.write_camera_calibration(c);
  if (sc.rotor.enabled) writer_.write_rotor_calibration(sc.rotor.sensor);
  writer_.write_vehicle(vehicle_params_of(sc));
}

DatasetSink::~DatasetSink() {
  try {
    finish();
  } catch (...) {  // destructors must not throw; finish() is called explicitly on success
  }
}

void DatasetSink::on_groundtruth(const GroundTruthSample& s) {
  GroundTruthSample g = s;  // biases are body-frame: unchanged
  g.T_WI.p = R_GS_ * s.T_WI.p;
  g.v_WI = R_GS_ * s.v_WI;
  g.T_WI.q = Eigen::Quaterniond(R_GS_ * s.T_WI.R()).normalized();
  writer_.write(g);
}

void DatasetSink::on_force(const ForceSample& s) {
  ForceSample f = s;
  f.f_W_N = R_GS_ * s.f_W_N;
  f.df_W_Nps = R_GS_ * s.df_W_Nps;
  writer_.write(f);
}

void DatasetSink::on_phase(const PhaseSample& s) {
  if (!phase_.is_open()) {
    const std::filesystem::path dir = writer_.mav0() / "phase0";
    std::filesystem::create_directories(dir);
    phase_.open(dir / "data.csv");
    if (!phase_) throw io::DatasetError((dir / "data.csv").string() + ": cannot create");
    phase_ << "#timestamp [ns],phase\n";
  }
  phase_ << s.t_ns << ',' << static_cast<int>(s.phase) << '\n';
  if (!phase_) throw io::DatasetError((writer_.mav0() / "phase0" / "data.csv").string() + ": write failed");
}

void DatasetSink::on_time_offset(TimeNs t_ns, double offset_s) {
  const std::filesystem::path file = writer_.mav0() / "time_offset0" / "data.csv";
  if (!time_offset_.is_open()) {
    std::filesystem::create_directories(file.parent_path());
    time_offset_.open(file);
    if (!time_offset_) throw io::DatasetError(file.string() + ": cannot create");
    time_offset_ << "#timestamp [ns],time_offset [s]\n";
    time_offset_.precision(17);
  }
  time_offset_ << t_ns << ',' << offset_s << '\n';
  if (!time_offset_) throw io::DatasetError(file.string() + ": write failed");
}

void DatasetSink::on_camera_trigger(TimeNs t_ns, std::uint64_t frame_index, const Eigen::Isometry3d& T_WI,
                                    const BodyMotion& motion) {
  if (visual_) visual_->on_camera(t_ns, frame_index, T_WI, motion, writer_);
  ++frames_;
}

void DatasetSink::finish() {
  if (finished_) return;
  finished_ = true;
  if (visual_) visual_->finish(writer_, R_GS_);
  writer_.close();
  if (phase_.is_open()) phase_.close();
  if (time_offset_.is_open()) time_offset_.close();
}

}  // namespace vid::sim
