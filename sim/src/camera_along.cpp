/// @file camera_along.cpp
/// @brief Camera streams along a recorded trajectory (camera_along.h).

#include "sim/camera_along.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "io/dataset_writer.h"
#include "io/errors.h"
#include "sim/dataset_sink.h"

namespace vid::sim {

namespace fs = std::filesystem;

std::vector<TimeNs> camera_times_along(const PoseTrack& track, double rate_hz) {
  if (!(rate_hz > 0.0)) throw std::invalid_argument("camera rate must be > 0");
  std::vector<TimeNs> times;
  for (std::uint64_t k = 0;; ++k) {
    const TimeNs t = track.start_ns() + static_cast<TimeNs>(std::llround(static_cast<long double>(k) * 1e9L / rate_hz));
    if (t > track.end_ns()) break;
    times.push_back(t);
  }
  return times;
}

std::vector<fs::path> camera_stream_paths(const Scenario& sc, const fs::path& root) {
  const fs::path mav0 = root / "mav0";
  std::vector<fs::path> paths;
  for (const CameraCalib& c : sc.cameras.cameras) paths.push_back(mav0 / ("cam" + std::to_string(c.cam_id)));
  paths.push_back(mav0 / "feat0");
  paths.push_back(mav0 / "landmarks.csv");
  return paths;
}

std::uint64_t write_camera_along(const Scenario& sc, const PoseTrack& track, const fs::path& root, bool overwrite,
                                 const std::function<void(std::uint64_t, std::uint64_t)>& progress) {
  const CamerasConfig& cams = sc.cameras;
  if (cams.cameras.empty() || (!cams.images && !cams.features))
    throw io::ConfigError(sc.file + ": key 'cameras': no camera output (needs cameras.list and images or features)");
  if (cams.time_offset_s != 0.0 || cams.time_offset_jitter_s != 0.0)
    throw io::ConfigError(sc.file + ": key 'cameras.time_offset_s': a camera clock offset is not simulated along a "
                          "recorded trajectory (set time_offset_s and time_offset_jitter_s to 0)");
  std::string existing;
  for (const fs::path& p : camera_stream_paths(sc, root)) {
    std::error_code ec;
    if (fs::exists(fs::symlink_status(p, ec))) existing += (existing.empty() ? "" : ", ") + p.string();
  }
  if (!existing.empty()) {
    if (!overwrite) throw std::runtime_error("camera stream(s) already exist: " + existing + " (--overwrite replaces them)");
    for (const fs::path& p : camera_stream_paths(sc, root)) fs::remove_all(p);
  }

  std::unique_ptr<VisualOutput> visual = make_visual_output(sc);
  io::DatasetWriter writer(root);
  for (const CameraCalib& c : cams.cameras) writer.write_camera_calibration(c);
  const std::vector<TimeNs> times = camera_times_along(track, cams.rate_hz);
  for (std::size_t k = 0; k < times.size(); ++k) {
    visual->on_camera(times[k], k, track.pose(times[k]), track.motion(times[k]), writer);
    if (progress) progress(k + 1, times.size());
  }
  visual->finish(writer, Eigen::Matrix3d::Identity());  // landmarks in the track's world
  writer.close();
  return times.size();
}

}  // namespace vid::sim
