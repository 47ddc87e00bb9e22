// vidfusion_driver: runs VID-Fusion (commit 25c6771: their feature tracker and vid_estimator,
// built without ROS) on a VID-MSCKF dataset folder.
//
// SPDX-License-Identifier: GPL-3.0-or-later
// This program links VID-Fusion, which is GPL-3; the program as a whole is therefore distributed
// under the GNU General Public License v3 (or later). It is a benchmark tool only: it is not part
// of the VID-MSCKF build, libraries or binaries (see bench/peers/README.md).
//
// What it does (details: bench/peers/README.md "vidfusion_driver"):
//   * reads DATASET/mav0/{imu0,cam0,rotor0 (or thrust0),vehicle.yaml} (docs/formats.md §1),
//   * writes their config file (OpenCV YAML, the keys of their config/rotors_sim/sim_config.yaml)
//     from our calibration into OUT/vf_config/config.yaml; both their readParameters() read it,
//   * per cam0 image: their feature tracker as their feature_tracker node runs it, then, for
//     every published feature frame, what their vid_estimator node does (getMeasurements +
//     process_measurements_at_imu_rate + Estimator::processImage), synchronously in one thread,
//     with the control input of their dynamic_model node: collective_thrust = sum_i k_i n_i^2 / m
//     [m/s^2] at the rotor-speed timestamps,
//   * writes OUT/trajectory_tum.txt (p_WI, q_WI), OUT/force.csv (our force.csv columns: the
//     external force per unit mass, body and world, m/s^2), OUT/timing.csv (per-frame wall ms
//     from "decoded image in memory" to "state out") and OUT/summary.json.
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
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/yaml.h>

#include "estimator.h"
#include "ft_bridge.h"
#include "parameters.h"

#define PEER_DRIVER_NAME "vidfusion_driver"
#include "../driver_common.h"

namespace fs = std::filesystem;
using namespace peers;

// Their estimator.cpp declares these extern (their node defines them; the ground-truth
// orientation it would hold is stored by IntegrationBase but not used).
Eigen::Quaterniond q_gt0 = Eigen::Quaterniond::Identity(), q_gt = Eigen::Quaterniond::Identity();

// Static storage, as in their node: Estimator's constructor (clearState) deletes
// pre_integrations[i] when non-null and the force accumulators are never initialised; a
// global object is zero-initialised first.
Estimator estimator;

namespace {

double sec(int64_t ns) { return 1e-9 * static_cast<double>(ns); }

struct Imu {
  double t;
  Eigen::Vector3d a, w;
};
struct Control {
  double t;
  double collective_thrust;  // [m/s^2], mass-normalised, body z
};

void usage() {
  std::cout << "vidfusion_driver --dataset DIR --out DIR [--freq HZ] [--vio] [--set key=value]...\n"
               "                 [--log-level debug|info|warn|error]\n"
               "Runs VID-Fusion (GPL-3) on a VID-MSCKF dataset folder; see bench/peers/README.md.\n"
               "  --freq HZ   their feature_tracker 'freq' (publish rate); default: the camera rate\n"
               "  --vio       use_vid 0 (their VINS-Mono mode, no thrust input)\n"
               "  --set k=v   replace/add a key of the generated config (their yaml keys)\n";
}

}  // namespace

int main(int argc, char **argv) {
  fs::path dataset, out;
  std::map<std::string, std::string> overrides;
  int freq = -1;
  bool vio = false;
  std::string level = "warn";
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) die("missing value after " + a);
      return argv[++i];
    };
    if (a == "--dataset") dataset = next();
    else if (a == "--out") out = next();
    else if (a == "--freq") freq = std::stoi(next());
    else if (a == "--vio") vio = true;
    else if (a == "--log-level") level = next();
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
  const std::map<std::string, int> levels{{"debug", 0}, {"info", 1}, {"warn", 2}, {"error", 3}, {"silent", 5}};
  if (!levels.count(level)) die("unknown --log-level " + level);
  ros::console::g_level = levels.at(level);
  dataset = dataset_root(dataset);
  fs::create_directories(out / "vf_config");

  // ---------------------------------------------------------------- calibration -> their config
  const fs::path imu_yaml = dataset / "imu0" / "sensor.yaml", cam_yaml = dataset / "cam0" / "sensor.yaml",
                 veh_yaml = dataset / "vehicle.yaml";
  YAML::Node imu = load_yaml(imu_yaml), cam = load_yaml(cam_yaml);
  std::vector<double> T_BS = req<std::vector<double>>(cam["T_BS"], "data", cam_yaml);
  if (T_BS.size() != 16) die(cam_yaml.string() + ": T_BS.data needs 16 numbers");
  std::vector<int> res = req<std::vector<int>>(cam, "resolution", cam_yaml);
  std::vector<double> K = req<std::vector<double>>(cam, "intrinsics", cam_yaml);
  std::vector<double> D = req<std::vector<double>>(cam, "distortion_coefficients", cam_yaml);
  std::string dmodel = req<std::string>(cam, "distortion_model", cam_yaml);
  if (dmodel != "radial-tangential" && dmodel != "radtan") die(cam_yaml.string() + ": only radial-tangential is mapped");
  if (D.size() < 4) die(cam_yaml.string() + ": need 4 distortion coefficients");
  const double cam_rate = cam["rate_hz"] ? cam["rate_hz"].as<double>() : 30.0;
  // Kalibr-style timeshift_cam_imu (t_imu = t_cam + shift) if present = their td
  // ("readed image clock + td = real image clock (IMU clock)"); our presets have none.
  const double td = cam["timeshift_cam_imu"] ? cam["timeshift_cam_imu"].as<double>() : 0.0;
  const double imu_rate = req<double>(imu, "rate_hz", imu_yaml);
  // Their acc_n/gyr_n/acc_w/gyr_w are per-sample standard deviations (VINS-Mono's
  // IntegrationBase adds n^2 per IMU step for the measurement noise and w^2 dt^2 for the bias
  // random walk); from our continuous densities: sigma_d = density * sqrt(rate).
  const double sq = std::sqrt(imu_rate);
  double acc_n = req<double>(imu, "accelerometer_noise_density", imu_yaml) * sq;
  const double gyr_n = req<double>(imu, "gyroscope_noise_density", imu_yaml) * sq;
  const double acc_w = req<double>(imu, "accelerometer_random_walk", imu_yaml) * sq;
  const double gyr_w = req<double>(imu, "gyroscope_random_walk", imu_yaml) * sq;
  YAML::Node veh = load_yaml(veh_yaml);
  const double mass = req<double>(veh, "mass_kg", veh_yaml);
  const double gravity = veh["gravity"] ? veh["gravity"].as<double>() : 9.81;
  std::vector<double> k_rotor;
  if (veh["rotor_thrust_coefficients"]) k_rotor = veh["rotor_thrust_coefficients"].as<std::vector<double>>();
  if (freq < 0) freq = static_cast<int>(std::lround(cam_rate));

  std::vector<std::pair<std::string, std::string>> cfg = {
      {"use_vid", vio ? "0" : "1"},
      {"imu_topic", "\"/imu0\""},
      {"image_topic", "\"/cam0/image_raw\""},
      {"control_topic", "\"/thrust\""},
      {"output_path", "\"" + out.string() + "\""},
      {"model_type", "PINHOLE"},
      {"camera_name", "camera"},
      {"image_width", std::to_string(res.at(0))},
      {"image_height", std::to_string(res.at(1))},
      // Calibration is exact in our simulated folders, and VID-MSCKF does not estimate it:
      // fixed extrinsics and time offset (as the OpenVINS driver).
      {"estimate_extrinsic", "0"},
      // Feature budget = ours (config/sim/frontend.yaml: 150 features, 12 px apart, no
      // equalization on the rendered images); every image published (freq = camera rate).
      {"max_cnt", "150"},
      {"min_dist", "12"},
      {"freq", std::to_string(freq)},
      {"F_threshold", "1.0"},
      {"show_track", "0"},
      {"equalize", "0"},
      {"fisheye", "0"},
      // Their sim_config.yaml values.
      {"max_solver_time", "0.04"},
      {"max_num_iterations", "8"},
      {"keyframe_parallax", "10.0"},
      {"g_norm", std::to_string(gravity)},
      {"control_thrust_z_n", "0.5"},
      {"control_thrust_x_y_n", "0.5"},
      {"scale_thrust_input", "1"},
      {"force_wo_rotor_drag", "0"},
      {"k_d_x", "0.33"},
      {"k_d_y", "0.33"},
      {"loop_closure", "0"},
      {"estimate_td", "0"},
      {"td", std::to_string(td)},
      {"rolling_shutter", "0"},
      {"rolling_shutter_tr", "0"},
  };
  auto set = [&](const std::string &k, const std::string &v) { set_key(cfg, k, v); };
  std::ostringstream num;
  num.precision(17);
  auto fmt = [&](double x) {
    num.str("");
    num << x;
    return num.str();
  };
  set("gyr_n", fmt(gyr_n));
  set("acc_w", fmt(acc_w));
  set("gyr_w", fmt(gyr_w));
  // acc_n is a 3x1 matrix in their file: --set acc_n=X gives X on all three axes.
  if (overrides.count("acc_n")) {
    acc_n = std::stod(overrides.at("acc_n"));
    overrides.erase("acc_n");
  }
  for (auto &kv : overrides) set(kv.first, kv.second);
  const fs::path cfg_path = out / "vf_config" / "config.yaml";
  {
    std::ofstream f(cfg_path);
    f.precision(17);
    f << "%YAML:1.0\n# written by vidfusion_driver from " << dataset.string() << "\n";
    for (auto &kv : cfg) f << kv.first << ": " << kv.second << "\n";
    f << "distortion_parameters:\n   k1: " << D[0] << "\n   k2: " << D[1] << "\n   p1: " << D[2] << "\n   p2: " << D[3]
      << "\nprojection_parameters:\n   fx: " << K[0] << "\n   fy: " << K[1] << "\n   cx: " << K[2] << "\n   cy: " << K[3]
      << "\n";
    // T_BS = pose of the camera in the IMU frame: rotation camera -> IMU (imu^R_cam) and the
    // camera position in the IMU frame (imu^T_cam), what their extrinsicRotation/Translation hold.
    f << "extrinsicRotation: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [";
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) f << (r || c ? ", " : "") << T_BS[4 * r + c];
    f << "]\nextrinsicTranslation: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [" << T_BS[3] << ", "
      << T_BS[7] << ", " << T_BS[11] << "]\n";
    f << "acc_n: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [" << acc_n << ", " << acc_n << ", "
        << acc_n << "]\n";
  }

  // ---------------------------------------------------------------- their parameters
  const std::string vins_folder = std::string(VF_SRC_DIR) + "/";
  vf::tracker_init(cfg_path.string(), vins_folder);
  ros::NodeHandle::set("config_file", cfg_path.string());
  {
    ros::NodeHandle n("~");
    readParameters(n);
  }
  estimator.setParameter();

  // ---------------------------------------------------------------- data
  std::vector<Imu> imus;
  for (const ImuSample &s : read_imu(dataset / "imu0" / "data.csv")) imus.push_back({sec(s.ns), s.a, s.w});
  // Control input as their dynamic_model node makes it from the rotor speeds:
  // collective_thrust = (sum_i k_i n_i^2) / mass, with our k_i [N/unit^2] in the rotor unit.
  std::vector<Control> ctrl;
  std::string control_source;
  if (fs::exists(dataset / "rotor0" / "data.csv")) {
    for (const Row &r : read_rows(dataset / "rotor0" / "data.csv", 2)) {
      if (k_rotor.size() != r.v.size()) die("vehicle.yaml rotor_thrust_coefficients does not match rotor0 columns");
      double T = 0;
      for (size_t i = 0; i < r.v.size(); ++i) T += k_rotor[i] * r.v[i] * r.v[i];
      ctrl.push_back({sec(r.ns), T / mass});
    }
    control_source = "rotor0";
  } else if (fs::exists(dataset / "thrust0" / "data.csv")) {
    for (const Row &r : read_rows(dataset / "thrust0" / "data.csv", 2)) ctrl.push_back({sec(r.ns), r.v[0] / mass});
    control_source = "thrust0";
  } else if (!vio) {
    die("no rotor0/ or thrust0/ in " + dataset.string() + " (use --vio for their VINS-Mono mode)");
  }
  auto frames = read_frames(dataset / "cam0" / "data.csv");
  if (imus.empty() || frames.empty()) die("no IMU or no camera frames");

  // ---------------------------------------------------------------- run
  std::ofstream traj(out / "trajectory_tum.txt"), force(out / "force.csv"), timing(out / "timing.csv");
  force << "#timestamp [ns],fb_x [m s^-2],fb_y [m s^-2],fb_z [m s^-2],fw_x [m s^-2],fw_y [m s^-2],"
           "fw_z [m s^-2],sigma_x [m s^-2],sigma_y [m s^-2],sigma_z [m s^-2]\n";
  timing << "#timestamp [ns],total [ms],initialized,published,features,tracker [ms],estimator [ms],frame_count\n";

  // their node's state
  size_t imu_i = 0, ctl_i = 0;
  bool beginning = true;
  double current_time = -1, last_Fz = 0;
  const bool use_vid = USE_VID != 0;

  std::vector<double> ms_all, ms_init;
  size_t n_frames = 0, n_published = 0, n_est = 0, n_init_frames = 0, n_thrown = 0, n_reboots = 0;
  double first_init_s = -1;
  bool was_nonlinear = false;
  const auto wall0 = std::chrono::steady_clock::now();
  std::vector<vf::TrackedPoint> pts;

  for (size_t fi = 0; fi < frames.size(); ++fi) {
    const int64_t t_ns = frames[fi].first;
    const double t_img = sec(t_ns);
    cv::Mat img = cv::imread((dataset / "cam0" / "data" / frames[fi].second).string(), cv::IMREAD_GRAYSCALE);
    if (img.empty()) die("cannot read image " + frames[fi].second);

    const auto t0 = std::chrono::steady_clock::now();
    const bool published = vf::tracker_process(img, t_img, pts);
    const auto t1 = std::chrono::steady_clock::now();
    bool processed = false;
    if (published) {
      ++n_published;
      // ---- getMeasurements(): the feature frame at t_img needs IMU (and control) after t_img + td
      const double img_t = t_img + estimator.td;
      bool stop = imus.back().t <= img_t || (use_vid && (ctrl.empty() || ctrl.back().t <= img_t));
      if (!stop && use_vid && beginning) {
        while (imu_i < imus.size() && imus[imu_i].t < ctrl[ctl_i].t) ++imu_i;  // "throw IMUs"
        beginning = false;
      }
      if (!stop && !(imus[imu_i].t < img_t)) {
        ++n_thrown;  // "throw img, only should happen at the beginning"
      } else if (!stop) {
        size_t k = imu_i;
        while (imus[k].t < img_t) ++k;  // IMUs [imu_i, k] (k is kept for the next frame)
        size_t m = ctl_i;
        if (use_vid)
          while (ctrl[m].t < img_t) ++m;
        // ---- process_measurements_at_imu_rate()
        double dx = 0, dy = 0, dz = 0, rx = 0, ry = 0, rz = 0, Fz = last_Fz;
        size_t cit = ctl_i;
        const size_t cend = m + 1;
        const double begin_t = imus[imu_i].t;
        double end_t = begin_t;
        for (size_t ii = imu_i; ii <= k; ++ii) {
          const Imu &s = imus[ii];
          const double t = s.t;
          end_t = t;
          if (t <= img_t) {
            if (current_time < 0) current_time = t;
            const double dt = t - current_time;
            current_time = t;
            dx = s.a.x(), dy = s.a.y(), dz = s.a.z(), rx = s.w.x(), ry = s.w.y(), rz = s.w.z();
            if (use_vid && cit != cend) {
              while (cit + 1 != cend && ctrl[cit + 1].t < current_time) ++cit;
              Fz = SCALE_THRUST_INPUT * ctrl[cit].collective_thrust;
              ++cit;
            }
            estimator.processIMUandThrust(dt, Eigen::Vector3d(dx, dy, dz), Eigen::Vector3d(rx, ry, rz), Fz);
          } else {
            const double dt_1 = img_t - current_time, dt_2 = t - img_t;
            current_time = img_t;
            const double w1 = dt_2 / (dt_1 + dt_2), w2 = dt_1 / (dt_1 + dt_2);
            dx = w1 * dx + w2 * s.a.x();
            dy = w1 * dy + w2 * s.a.y();
            dz = w1 * dz + w2 * s.a.z();
            rx = w1 * rx + w2 * s.w.x();
            ry = w1 * ry + w2 * s.w.y();
            rz = w1 * rz + w2 * s.w.z();
            if (use_vid && cit != cend) {
              while (cit + 1 != cend && ctrl[cit + 1].t < img_t) ++cit;
              Fz = SCALE_THRUST_INPUT * ctrl[cit].collective_thrust;
              ++cit;
            }
            estimator.processIMUandThrust(dt_1, Eigen::Vector3d(dx, dy, dz), Eigen::Vector3d(rx, ry, rz), Fz);
          }
          last_Fz = Fz;
        }
        if (use_vid) {
          estimator.sum_dt_preintegration_force += end_t - begin_t;
          estimator.Fexts[estimator.frame_count] = estimator.Fexts_temp / estimator.sum_dt_preintegration_force;
          estimator.Fz_avg_vector.at(estimator.frame_count) = estimator.Fz_avg / estimator.sum_dt_preintegration_force;
        }
        imu_i = k;
        if (use_vid) ctl_i = m;
        // ---- the feature message (their node sends floats: PointCloud / ChannelFloat32)
        std::map<int, std::vector<std::pair<int, Eigen::Matrix<double, 7, 1>>>> image;
        for (const auto &p : pts) {
          const int v = static_cast<int>(static_cast<float>(p.id) + 0.5);
          Eigen::Matrix<double, 7, 1> xyz_uv_velocity;
          xyz_uv_velocity << static_cast<float>(p.x), static_cast<float>(p.y), 1.0, static_cast<float>(p.u),
              static_cast<float>(p.v), static_cast<float>(p.vx), static_cast<float>(p.vy);
          image[v / NUM_OF_CAM].emplace_back(v % NUM_OF_CAM, xyz_uv_velocity);
        }
        std_msgs::Header header;
        header.stamp = ros::Time(t_img);
        header.frame_id = "world";
        estimator.processImage(image, header);
        processed = true;
        ++n_est;
      }
    }
    const bool init = estimator.solver_flag == Estimator::SolverFlag::NON_LINEAR;
    Eigen::Vector3d p, fb, fw;
    Eigen::Quaterniond q;
    if (processed && init) {
      p = estimator.Ps[WINDOW_SIZE];
      q = Eigen::Quaterniond(estimator.Rs[WINDOW_SIZE]).normalized();
      fb = estimator.Fexts[WINDOW_SIZE];
      fw = estimator.Rs[WINDOW_SIZE] * fb;  // as their pubOdometry: "pub fext in world frame"
    }
    const auto t2 = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(t2 - t0).count();
    const double ms_ft = std::chrono::duration<double, std::milli>(t1 - t0).count();
    ++n_frames;
    ms_all.push_back(ms);
    if (processed && was_nonlinear && !init) ++n_reboots;  // their failureDetection() restarted it
    if (processed) was_nonlinear = init;
    timing << t_ns << "," << ms << "," << (init ? 1 : 0) << "," << (processed ? 1 : 0) << "," << pts.size() << ","
           << ms_ft << "," << (ms - ms_ft) << "," << estimator.frame_count << "\n";
    if (init) {
      ++n_init_frames;
      ms_init.push_back(ms);
      if (first_init_s < 0) first_init_s = t_img - sec(frames[0].first);
    }
    if (processed && init) {
      if (!p.allFinite() || !fb.allFinite()) {
        std::cerr << "vidfusion_driver: non-finite state at " << t_ns << "\n";
        break;
      }
      // State time = image time + td on the IMU clock (td = 0 here).
      const int64_t ts = t_ns + static_cast<int64_t>(std::llround(estimator.td * 1e9));
      traj << tum_line(ts, p, q);
      char line[512];
      // Their estimator reports no covariance: the sigma columns are 0 ("not estimated"; our
      // loaders reject non-finite values). Scoring uses the values only.
      std::snprintf(line, sizeof line, "%lld,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,0,0,0\n", static_cast<long long>(ts),
                    fb.x(), fb.y(), fb.z(), fw.x(), fw.y(), fw.z());
      force << line;
    }
  }
  traj.flush();
  force.flush();
  timing.flush();
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();

  const struct rusage ru = self_rusage();
  std::ofstream js(out / "summary.json");
  js.precision(6);
  js << "{\n  \"estimator\": \"vid-fusion-25c6771\",\n  \"use_vid\": " << (use_vid ? "true" : "false")
     << ",\n  \"control_source\": \"" << control_source << "\",\n  \"mass_kg\": " << mass
     << ",\n  \"frames\": " << n_frames << ",\n  \"frames_published\": " << n_published
     << ",\n  \"frames_estimated\": " << n_est << ",\n  \"frames_thrown\": " << n_thrown
     << ",\n  \"frames_initialized\": " << n_init_frames << ",\n  \"reboots\": " << n_reboots
     << ",\n  \"init_after_s\": " << first_init_s << ",\n  \"ms_per_frame\": {\"median\": " << percentile(ms_all, 0.5)
     << ", \"p95\": " << percentile(ms_all, 0.95) << ", \"mean\": " << mean(ms_all) << "},\n"
     << "  \"ms_per_initialized_frame\": {\"median\": " << percentile(ms_init, 0.5) << ", \"p95\": " << percentile(ms_init, 0.95)
     << ", \"mean\": " << mean(ms_init) << "},\n";
  write_summary_resources(js, wall_s, ru);
  std::cerr << "vidfusion_driver: " << n_frames << " frames, initialized after " << first_init_s << " s, "
            << n_init_frames << " initialized, " << n_reboots << " reboots, median " << percentile(ms_init, 0.5)
            << " ms, peak RSS " << ru.ru_maxrss / 1024 << " MB\n";
  return n_init_frames > 0 ? 0 : 2;
}
