#include "sim/dataset_sink.h"

#include <stdexcept>

namespace vid::sim {

DatasetSink::DatasetSink(const std::filesystem::path& root, const Scenario& sc,
                         std::unique_ptr<VisualOutput> visual)
    : writer_(root), visual_(std::move(visual)) {
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

void DatasetSink::on_camera(TimeNs t_ns, std::uint64_t frame_index, const Eigen::Isometry3d& T_WI) {
  if (visual_) visual_->on_camera(t_ns, frame_index, T_WI, writer_);
  ++frames_;
}

void DatasetSink::finish() {
  if (finished_) return;
  finished_ = true;
  if (visual_) visual_->finish(writer_);
  writer_.close();
}

}  // namespace vid::sim

#ifndef VID_SIM_HAS_RENDER
namespace vid::sim {
std::unique_ptr<VisualOutput> make_visual_output(const Scenario& sc) {
  if (sc.cameras.cameras.empty() || (!sc.cameras.images && !sc.cameras.features)) return nullptr;
  throw std::runtime_error(sc.file + ": cameras requested but vid_sim was built without the render module");
}
}  // namespace vid::sim
#endif
