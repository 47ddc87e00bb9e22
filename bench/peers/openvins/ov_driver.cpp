// ov_driver: runs OpenVINS (ov_msckf::VioManager, commit 6948812) on a VID-MSCKF dataset folder.
//
// SPDX-License-Identifier: GPL-3.0-or-later
// This program links OpenVINS, which is GPL-3; the program as a whole is therefore distributed
// under the GNU General Public License v3 (or later). It is a benchmark tool only: it is not part
// of the VID-MSCKF build, libraries or binaries (see bench/peers/README.md).
// What it does (details: bench/peers/README.md):
//   * reads DATASET/mav0/{imu0,cam0,cam1} (docs/formats.md section 1: CSV + PNG + sensor.yaml),
//   * writes OpenVINS's estimator_config.yaml / kalibr_imu_chain.yaml / kalibr_imucam_chain.yaml
//     from our calibration into OUT/ov_config/ (--set key=value overrides estimator keys),
//   * feeds VioManager in time order: every IMU sample up to and including the first one at or
//     after the frame's IMU-clock time (camera time + t_off), then the (stereo) frame,
//   * writes OUT/trajectory_tum.txt (p_WI, q_WI at every updated frame), OUT/timing.csv (per
//     frame wall ms from "decoded images in memory" to "state read back", plus the features used
//     in that update) and OUT/summary.json (counts, median/p95/mean ms, peak RSS),
//   * with --est-time-offset: estimates the camera-IMU time offset online and writes
//     OUT/time_offset.csv (per frame: the estimate and its sigma),
//   * with --init-groundtruth: initializes from DATASET/mav0/state_groundtruth_estimate0 as
//     OpenVINS's own ros1_serial_msckf does with its path_gt (for flights without a still start),
//   * with --start S: drops the IMU samples and frames of the first S seconds of the data (as
//     vid_run --start), for mid-flight starts (with --set init_dyn_use=true: its dynamic
//     initializer).
// Images are decoded before the timer starts, as vid_run's timing.total excludes decoding.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/yaml.h>

#include "core/VioManager.h"
#include "core/VioManagerOptions.h"
#include "state/State.h"
#include "state/StateHelper.h"
#include "types/IMU.h"
#include "utils/dataset_reader.h"
#include "utils/opencv_yaml_parse.h"
#include "utils/print.h"
#include "utils/sensor_data.h"

#define PEER_DRIVER_NAME "ov_driver"
#include "../driver_common.h"

namespace fs = std::filesystem;
using namespace peers;

namespace {

struct Camera {
  std::vector<double> T_BS;  // 16, row-major, pose of camera in IMU (T_IC)
  std::vector<int> resolution;
  std::vector<double> intrinsics, distortion;
  std::string distortion_model;  // radtan | equidistant
  double timeshift_cam_imu = 0;  // [s] Kalibr: t_imu = t_cam + shift (0 when absent)
};

Camera read_camera(const fs::path &yaml) {
  YAML::Node n = load_yaml(yaml);
  Camera c;
  c.T_BS = req<std::vector<double>>(n["T_BS"], "data", yaml);
  if (c.T_BS.size() != 16) die(yaml.string() + ": T_BS.data needs 16 numbers");
  c.resolution = req<std::vector<int>>(n, "resolution", yaml);
  c.intrinsics = req<std::vector<double>>(n, "intrinsics", yaml);
  c.distortion = req<std::vector<double>>(n, "distortion_coefficients", yaml);
  std::string m = req<std::string>(n, "distortion_model", yaml);
  if (m == "radial-tangential" || m == "radtan")
    c.distortion_model = "radtan";
  else if (m == "equidistant" || m == "equi")
    c.distortion_model = "equidistant";
  else
    die(yaml.string() + ": unsupported distortion_model " + m);
  std::string model = n["camera_model"] ? n["camera_model"].as<std::string>() : "pinhole";
  if (model != "pinhole") die(yaml.string() + ": camera_model must be pinhole");
  if (n["timeshift_cam_imu"]) c.timeshift_cam_imu = n["timeshift_cam_imu"].as<double>();
  return c;
}

std::string vec(const std::vector<double> &v) {
  std::ostringstream o;
  o.precision(17);
  o << "[";
  for (size_t i = 0; i < v.size(); ++i) o << (i ? ", " : "") << v[i];
  o << "]";
  return o.str();
}

// Estimator settings: OpenVINS's own config/euroc_mav/estimator_config.yaml (read from the
// unpacked tarball, --base-config) with these keys replaced or added: the budget (same as ours,
// config/sim), one thread, and the documented changes below.
std::vector<std::pair<std::string, std::string>> estimator_changes() {
  return {
      {"verbosity", "\"WARNING\""},
      // Calibration is exact in our simulated folders and VID-MSCKF does not estimate it
      // online either; estimating it would only add states (cost) and noise.
      {"calib_cam_extrinsics", "false"},
      {"calib_cam_intrinsics", "false"},
      {"calib_cam_timeoffset", "false"},
      {"calib_imu_intrinsics", "false"},
      {"calib_imu_g_sensitivity", "false"},
      {"max_clones", "11"},
      {"max_msckf_in_update", "60"},
      // Initialization from the still start (sequences hover for start_delay_s = 1 s): with
      // zero-velocity updates on, OpenVINS's static initializer does not wait for a jerk and
      // initializes as soon as the IMU window is still (accelerometer spread below
      // init_imu_thresh and image disparity below init_max_disparity). ZUPT is used only
      // until the vehicle first moves (zupt_only_at_beginning), disparity-based.
      {"try_zupt", "true"},
      {"zupt_chi2_multipler", "0"},
      {"zupt_max_disparity", "0.5"},
      {"zupt_only_at_beginning", "true"},
      {"init_window_time", "1.0"},  // two 0.5 s halves: gravity from 0.5 s, as ours (init_window_s)
      {"init_imu_thresh", "4.5"},   // ours: init_accel_std_max 4.5 m/s^2 (noisy VID accelerometer)
      {"num_pts", "150"},
      {"grid_x", "8"},
      {"grid_y", "6"},
      {"min_px_dist", "12"},
      {"fast_threshold", "20"},
      {"num_opencv_threads", "0"},  // serial: one core for both estimators
      {"multi_threading_pubs", "false"},
      {"multi_threading_subs", "false"},
      {"histogram_method", "\"NONE\""},  // ours: equalization none (rendered images)
      // Triangulation limits (ov_core FeatureInitializerOptions; defaults 40 / 10000, not in
      // the EuRoC file): set from the camera baseline below.
      {"fi_max_baseline", "40"},
      {"fi_max_cond_number", "10000"},
      {"relative_config_imu", "\"kalibr_imu_chain.yaml\""},
      {"relative_config_imucam", "\"kalibr_imucam_chain.yaml\""},
  };
}

// The base file with keys replaced ("key: value  # comment" lines) or appended.
std::string merge_config(const fs::path &base, const std::vector<std::pair<std::string, std::string>> &kv) {
  std::ifstream f(base);
  if (!f) die("cannot open OpenVINS base config " + base.string());
  std::ostringstream out;
  std::string line;
  std::map<std::string, bool> used;
  while (std::getline(f, line)) {
    size_t c = line.find(':');
    std::string key = c == std::string::npos ? "" : line.substr(0, c);
    bool plain = !key.empty() && key.find_first_not_of("abcdefghijklmnopqrstuvwxyz_0123456789") == std::string::npos;
    auto it = std::find_if(kv.begin(), kv.end(), [&](const auto &p) { return p.first == key; });
    if (plain && it != kv.end()) {
      out << key << ": " << it->second << "  # set by ov_driver\n";
      used[key] = true;
    } else {
      out << line << "\n";
    }
  }
  out << "\n# added by ov_driver\n";
  for (const auto &p : kv)
    if (!used.count(p.first)) out << p.first << ": " << p.second << "\n";
  return out.str();
}

void usage() {
  std::cout << "ov_driver --dataset DIR --out DIR [--cams 1|2] [--num-pts N] [--clones N]\n"
               "          [--max-msckf N] [--max-slam N] [--set key=value]... [--verbosity LEVEL]\n"
               "          [--base-config OPENVINS_ESTIMATOR_CONFIG.yaml] [--est-time-offset] [--init-groundtruth]\n"
               "          [--start SECONDS]\n"
               "Runs OpenVINS (GPL-3) on a VID-MSCKF dataset folder; see bench/peers/README.md.\n";
}

}  // namespace

int main(int argc, char **argv) {
  fs::path dataset, out;
  fs::path base_config = OV_BASE_CONFIG;
  int cams = 2;
  std::map<std::string, std::string> overrides;
  std::string verbosity = "WARNING";
  bool est_time_offset = false;
  bool init_groundtruth = false;
  double start_s = 0.0;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) die("missing value after " + a);
      return argv[++i];
    };
    if (a == "--dataset") dataset = next();
    else if (a == "--out") out = next();
    else if (a == "--cams") cams = std::stoi(next());
    else if (a == "--num-pts") overrides["num_pts"] = next();
    else if (a == "--clones") overrides["max_clones"] = next();
    else if (a == "--max-msckf") overrides["max_msckf_in_update"] = next();
    else if (a == "--max-slam") overrides["max_slam"] = next();
    else if (a == "--verbosity") verbosity = next();
    else if (a == "--base-config") base_config = next();
    else if (a == "--est-time-offset") est_time_offset = true;
    else if (a == "--init-groundtruth") init_groundtruth = true;
    else if (a == "--start") start_s = std::stod(next());
    else if (a == "--set") parse_set(next(), overrides);
    else if (a == "-h" || a == "--help") {
      usage();
      return 0;
    } else
      die("unknown argument " + a);
  }
  if (dataset.empty() || out.empty()) {
    usage();
    return 1;
  }
  if (cams != 1 && cams != 2) die("--cams must be 1 or 2");
  dataset = dataset_root(dataset);
  fs::create_directories(out / "ov_config");

  // ---------------------------------------------------------------- calibration -> OV config
  const fs::path imu_yaml = dataset / "imu0" / "sensor.yaml";
  YAML::Node imu = load_yaml(imu_yaml);
  std::vector<Camera> cam;
  for (int c = 0; c < cams; ++c)
    cam.push_back(read_camera(dataset / ("cam" + std::to_string(c)) / "sensor.yaml"));

  {
    std::ofstream f(out / "ov_config" / "kalibr_imu_chain.yaml");
    f.precision(17);
    f << "%YAML:1.0\n\nimu0:\n  T_i_b:\n    - [1.0, 0.0, 0.0, 0.0]\n    - [0.0, 1.0, 0.0, 0.0]\n"
         "    - [0.0, 0.0, 1.0, 0.0]\n    - [0.0, 0.0, 0.0, 1.0]\n"
      << "  accelerometer_noise_density: " << req<double>(imu, "accelerometer_noise_density", imu_yaml) << "\n"
      << "  accelerometer_random_walk: " << req<double>(imu, "accelerometer_random_walk", imu_yaml) << "\n"
      << "  gyroscope_noise_density: " << req<double>(imu, "gyroscope_noise_density", imu_yaml) << "\n"
      << "  gyroscope_random_walk: " << req<double>(imu, "gyroscope_random_walk", imu_yaml) << "\n"
      << "  rostopic: /imu0\n  time_offset: 0.0\n"
      << "  update_rate: " << req<double>(imu, "rate_hz", imu_yaml) << "\n"
      << "  model: \"kalibr\"\n"
         "  Tw:\n    - [ 1.0, 0.0, 0.0 ]\n    - [ 0.0, 1.0, 0.0 ]\n    - [ 0.0, 0.0, 1.0 ]\n"
         "  R_IMUtoGYRO:\n    - [ 1.0, 0.0, 0.0 ]\n    - [ 0.0, 1.0, 0.0 ]\n    - [ 0.0, 0.0, 1.0 ]\n"
         "  Ta:\n    - [ 1.0, 0.0, 0.0 ]\n    - [ 0.0, 1.0, 0.0 ]\n    - [ 0.0, 0.0, 1.0 ]\n"
         "  R_IMUtoACC:\n    - [ 1.0, 0.0, 0.0 ]\n    - [ 0.0, 1.0, 0.0 ]\n    - [ 0.0, 0.0, 1.0 ]\n"
         "  Tg:\n    - [ 0.0, 0.0, 0.0 ]\n    - [ 0.0, 0.0, 0.0 ]\n    - [ 0.0, 0.0, 0.0 ]\n";
  }
  {
    std::ofstream f(out / "ov_config" / "kalibr_imucam_chain.yaml");
    f.precision(17);
    f << "%YAML:1.0\n\n";
    for (int c = 0; c < cams; ++c) {
      const Camera &k = cam[c];
      f << "cam" << c << ":\n  T_imu_cam:\n";
      for (int r = 0; r < 4; ++r)
        f << "    - " << vec({k.T_BS[4 * r], k.T_BS[4 * r + 1], k.T_BS[4 * r + 2], k.T_BS[4 * r + 3]}) << "\n";
      f << "  cam_overlaps: [" << (cams == 2 ? std::to_string(1 - c) : "") << "]\n"
        << "  camera_model: pinhole\n"
        << "  distortion_coeffs: " << vec(k.distortion) << "\n"
        << "  distortion_model: " << k.distortion_model << "\n"
        << "  intrinsics: " << vec(k.intrinsics) << "\n"
        << "  resolution: [" << k.resolution[0] << ", " << k.resolution[1] << "]\n"
        << "  timeshift_cam_imu: " << k.timeshift_cam_imu << "\n"
        << "  rostopic: /cam" << c << "/image_raw\n";
    }
  }
  auto est = estimator_changes();
  auto set = [&](const std::string &k, const std::string &v) { set_key(est, k, v); };
  set("max_cameras", std::to_string(cams));
  set("use_stereo", cams == 2 ? "true" : "false");
  set("verbosity", "\"" + verbosity + "\"");
  // Camera-IMU time offset. OpenVINS: calib_dt_CAMtoIMU with t_imu = t_cam + t_off (State.h,
  // Propagator: clones at t_cam + t_off on the IMU clock), read from cam0's timeshift_cam_imu;
  // Kalibr's and ours (docs/notes/time-offset.md): t_imu = t_cam + t_d. Same sign, so our
  // calibrated value is its starting value as it is. Estimated online only with
  // --est-time-offset (its initial sigma: 10 ms, State.cpp).
  if (est_time_offset) set("calib_cam_timeoffset", "true");
  if (cams == 2) {
    // fi_max_baseline bounds (mean depth / baseline of the observing poses). Scale OpenVINS's
    // EuRoC value (40 for a 0.11 m stereo pair) by the baseline ratio, so the same depth range
    // is accepted with our baseline; the condition-number bound likewise.
    Eigen::Vector3d p0(cam[0].T_BS[3], cam[0].T_BS[7], cam[0].T_BS[11]);
    Eigen::Vector3d p1(cam[1].T_BS[3], cam[1].T_BS[7], cam[1].T_BS[11]);
    double b = (p0 - p1).norm();
    double scale = std::max(1.0, 0.11 / std::max(b, 1e-3));
    set("fi_max_baseline", std::to_string(40.0 * scale));
    set("fi_max_cond_number", std::to_string(10000.0 * scale));
  }
  for (auto &kv : overrides) set(kv.first, kv.second);
  const fs::path est_yaml = out / "ov_config" / "estimator_config.yaml";
  {
    std::ofstream f(est_yaml);
    f << merge_config(base_config, est);
  }

  // ---------------------------------------------------------------- OpenVINS
  auto parser = std::make_shared<ov_core::YamlParser>(est_yaml.string());
  ov_core::Printer::setPrintLevel(verbosity);
  ov_msckf::VioManagerOptions params;
  params.print_and_load(parser);
  // fi_* keys are parsed by print_and_load_estimator -> featinit_options.print(parser).
  if (!parser->successful()) die("OpenVINS could not parse all parameters of " + est_yaml.string());
  auto sys = std::make_shared<ov_msckf::VioManager>(params);

  // ---------------------------------------------------------------- data
  std::vector<ImuSample> imu_data = read_imu(dataset / "imu0" / "data.csv");
  std::vector<std::vector<std::pair<int64_t, std::string>>> frames;
  for (int c = 0; c < cams; ++c) frames.push_back(read_frames(dataset / ("cam" + std::to_string(c)) / "data.csv"));
  if (imu_data.empty() || frames[0].empty()) die("no IMU or no camera frames");
  if (start_s > 0.0) {  // --start: from the data's first stamp, as vid_run
    const int64_t t_cut = std::min(imu_data.front().ns, frames[0].front().first) + std::llround(start_s * 1e9);
    imu_data.erase(imu_data.begin(), std::find_if(imu_data.begin(), imu_data.end(),
                                                  [&](const ImuSample &m) { return m.ns >= t_cut; }));
    for (auto &fr : frames)
      fr.erase(fr.begin(), std::find_if(fr.begin(), fr.end(), [&](const auto &f) { return f.first >= t_cut; }));
    if (imu_data.empty() || frames[0].empty()) die("--start " + std::to_string(start_s) + ": past the end of the data");
  }
  // --init-groundtruth: OpenVINS's own reader of the EuRoC ground-truth CSV (t [ns], p, q wxyz,
  // v, b_g, b_a), used as its ros1_serial_msckf uses it.
  std::map<double, Eigen::Matrix<double, 17, 1>> gt_states;
  if (init_groundtruth) {
    const fs::path gt = dataset / "state_groundtruth_estimate0" / "data.csv";
    if (!fs::exists(gt)) die(gt.string() + ": missing (needed by --init-groundtruth)");
    ov_core::DatasetReader::load_gt_file(gt.string(), gt_states);
  }

  std::ofstream traj(out / "trajectory_tum.txt");
  std::ofstream timing(out / "timing.csv");
  timing << "#timestamp [ns],total [ms],initialized,msckf_features,slam_features,clones\n";
  std::ofstream toff;
  if (est_time_offset) {
    toff.open(out / "time_offset.csv");
    toff << "#timestamp [ns],time_offset [s],sigma [s]\n";  // camera stamp; t_imu = t_cam + time_offset
  }
  std::vector<double> ms_all, ms_init;
  size_t imu_i = 0, n_frames = 0, n_skipped = 0, n_updated = 0;
  double first_init_s = -1;
  size_t sum_msckf = 0, sum_slam = 0;
  const auto wall0 = std::chrono::steady_clock::now();

  for (size_t fi = 0; fi < frames[0].size(); ++fi) {
    const int64_t t_ns = frames[0][fi].first;
    // Decode (outside the timer: vid_run's timing.total excludes decoding too).
    ov_core::CameraData msg;
    msg.timestamp = 1e-9 * static_cast<double>(t_ns);
    bool ok = true;
    for (int c = 0; c < cams; ++c) {
      // Stereo pairs share timestamps in our folders; find cam1's row with the same time.
      const auto &fr = frames[c];
      auto it = std::lower_bound(fr.begin(), fr.end(), std::make_pair(t_ns, std::string()));
      if (it == fr.end() || it->first != t_ns) {
        ok = false;
        break;
      }
      cv::Mat img = cv::imread((dataset / ("cam" + std::to_string(c)) / "data" / it->second).string(), cv::IMREAD_GRAYSCALE);
      if (img.empty()) {
        ok = false;
        break;
      }
      msg.sensor_ids.push_back(c);
      msg.images.push_back(img);
      msg.masks.push_back(cv::Mat::zeros(img.rows, img.cols, CV_8UC1));
    }
    if (!ok) {
      ++n_skipped;
      continue;
    }

    const auto t0 = std::chrono::steady_clock::now();
    // IMU up to and including the first sample at/after the frame's IMU-clock time t_cam +
    // t_off (the propagator needs to bracket it; t_off: the current estimate, 0 by default).
    const int64_t t_imu_ns = t_ns + std::llround(1e9 * sys->get_state()->_calib_dt_CAMtoIMU->value()(0));
    while (imu_i < imu_data.size()) {
      ov_core::ImuData m;
      m.timestamp = 1e-9 * static_cast<double>(imu_data[imu_i].ns);
      m.wm = imu_data[imu_i].w;
      m.am = imu_data[imu_i].a;
      sys->feed_measurement_imu(m);
      const bool past = imu_data[imu_i].ns >= t_imu_ns;
      ++imu_i;
      if (past) break;
    }
    // As ros1_serial_msckf: until the first update, (re)initialize from the ground-truth state
    // nearest the frame (within 0.1 s, its get_gt_state), then feed the frame.
    Eigen::Matrix<double, 17, 1> imustate;
    if (!gt_states.empty() && !sys->initialized() &&
        ov_core::DatasetReader::get_gt_state(msg.timestamp, imustate, gt_states))
      sys->initialize_with_gt(imustate);
    sys->feed_measurement_camera(msg);
    // Initialized = its static initializer has set the state. (VioManager::initialized() stays
    // false while the start-up zero-velocity updates hold the state, before the first MSCKF
    // update; those frames have a valid, updated state too.)
    bool init = sys->get_state()->_timestamp > 0;
    size_t n_msckf = 0, n_slam = 0, n_clones = 0;
    Eigen::Vector3d p;
    Eigen::Quaterniond q;
    double ts = -1, t_off = 0, t_off_sigma = 0;
    if (init) {
      auto st = sys->get_state();
      ts = st->_timestamp;  // camera clock; the IMU pose is at ts + t_off on the IMU clock
      t_off = st->_calib_dt_CAMtoIMU->value()(0);
      if (est_time_offset)
        t_off_sigma = std::sqrt(ov_msckf::StateHelper::get_marginal_covariance(st, {st->_calib_dt_CAMtoIMU})(0, 0));
      p = st->_imu->pos();
      Eigen::Matrix3d R_GtoI = st->_imu->Rot();  // JPL q_GtoI -> R_GtoI
      q = Eigen::Quaterniond(R_GtoI.transpose());
      n_msckf = sys->get_good_features_MSCKF().size();
      n_slam = st->_features_SLAM.size();
      n_clones = st->_clones_IMU.size();
    }
    const auto t1 = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    ++n_frames;
    ms_all.push_back(ms);
    timing << t_ns << "," << ms << "," << (init ? 1 : 0) << "," << n_msckf << "," << n_slam << "," << n_clones << "\n";
    if (init) {
      if (first_init_s < 0) first_init_s = 1e-9 * static_cast<double>(t_ns - frames[0][0].first);
      // Only frames at which the state reached this frame's time (an update happened).
      if (std::abs(ts - msg.timestamp) < 1e-6) {
        ++n_updated;
        ms_init.push_back(ms);
        sum_msckf += n_msckf;
        sum_slam += n_slam;
        // Stamped on the IMU clock (as the ground truth and OpenVINS's ROS odometry): t_cam + t_off.
        const int64_t tp_ns = t_ns + std::llround(1e9 * t_off);
        traj << tum_line(tp_ns, p, q);
      }
      if (est_time_offset) {
        char line[96];
        std::snprintf(line, sizeof line, "%lld,%.9g,%.6g\n", static_cast<long long>(t_ns), t_off, t_off_sigma);
        toff << line;
      }
    }
    if (!std::isfinite(p.x()) && init) {
      std::cerr << "ov_driver: non-finite state at " << t_ns << "\n";
      break;
    }
  }
  traj.flush();
  timing.flush();
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();

  const struct rusage ru = self_rusage();
  std::ofstream js(out / "summary.json");
  js.precision(6);
  js << "{\n  \"estimator\": \"openvins-6948812\",\n  \"cams\": " << cams << ",\n  \"frames\": " << n_frames
     << ",\n  \"frames_skipped\": " << n_skipped << ",\n  \"frames_updated\": " << n_updated
     << ",\n  \"init_after_s\": " << first_init_s << ",\n  \"ms_per_frame\": {\"median\": " << percentile(ms_all, 0.5)
     << ", \"p95\": " << percentile(ms_all, 0.95) << ", \"mean\": " << mean(ms_all) << "},\n"
     << "  \"ms_per_updated_frame\": {\"median\": " << percentile(ms_init, 0.5) << ", \"p95\": " << percentile(ms_init, 0.95)
     << ", \"mean\": " << mean(ms_init) << "},\n"
     << "  \"mean_msckf_features_per_update\": " << (n_updated ? double(sum_msckf) / n_updated : 0.0)
     << ",\n  \"mean_slam_features\": " << (n_updated ? double(sum_slam) / n_updated : 0.0) << ",\n";
  write_summary_resources(js, wall_s, ru);
  std::cerr << "ov_driver: " << n_frames << " frames, " << n_updated << " updated, median " << percentile(ms_init, 0.5)
            << " ms, peak RSS " << ru.ru_maxrss / 1024 << " MB, msckf feats/update "
            << (n_updated ? double(sum_msckf) / n_updated : 0.0) << "\n";
  return n_updated > 0 ? 0 : 2;
}
