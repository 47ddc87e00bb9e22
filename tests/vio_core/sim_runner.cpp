// See sim_runner.h.
#include "sim_runner.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <stdexcept>
#include <vector>

#include "frontend/camera_model.h"
#include "io/dataset_reader.h"
#include "vio_core/pipeline.h"
#include "vio_core/so3.h"
#include "vio_core/thrust.h"

namespace vid::test {

std::filesystem::path ensure_sim_dataset(const std::string& preset, int seed) {
  const std::filesystem::path out = std::filesystem::path(VID_BINARY_DIR) / "vio_core_sim" /
                                    (preset + "_seed" + std::to_string(seed));
  if (std::filesystem::exists(out / "mav0" / "feat0" / "data.csv")) return out;
  std::filesystem::create_directories(out);
  const std::string cmd = std::string(VID_BINARY_DIR) + "/bin/vid_sim --scenario " + VID_SOURCE_DIR +
                          "/config/sim/" + preset + ".yaml --out " + out.string() + " --seed " +
                          std::to_string(seed) + " --features-only --quiet";
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("failed: " + cmd);
  return out;
}

namespace {

// 4-DoF (yaw + translation) alignment, then RMSE of positions.
double ate_posyaw(const std::vector<Eigen::Vector3d>& est, const std::vector<Eigen::Vector3d>& gt) {
  const std::size_t n = est.size();
  Eigen::Vector3d me = Eigen::Vector3d::Zero(), mg = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    me += est[i] / n;
    mg += gt[i] / n;
  }
  double a = 0, b = 0;  // maximize sum gt_c . Rz(yaw) est_c over yaw
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d e = est[i] - me, g = gt[i] - mg;
    a += e.x() * g.x() + e.y() * g.y();
    b += e.x() * g.y() - e.y() * g.x();
  }
  const double yaw = std::atan2(b, a);
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) sum += (Rz * (est[i] - me) + mg - gt[i]).squaredNorm();
  return std::sqrt(sum / n);
}

}  // namespace

SimMetrics run_on_dataset(const std::filesystem::path& folder, PropagationMode mode) {
  io::ReaderOptions opt;
  opt.read_images = false;
  io::DatasetReader reader(folder, opt);
  const io::DatasetCalibration& cal = reader.calibration();
  PipelineConfig pc;
  EstimatorParams& p = pc.params;
  p.mode = mode;
  p.init_mode = InitMode::kGroundTruth;
  if (cal.imu) {
    p.gyro_noise_density = cal.imu->gyro_noise_density;
    p.gyro_random_walk = cal.imu->gyro_random_walk;
    p.accel_noise_density = cal.imu->accel_noise_density;
    p.accel_random_walk = cal.imu->accel_random_walk;
    p.imu_rate_hz = cal.imu->rate_hz;
  }
  if (!cal.vehicle) throw std::runtime_error("dataset has no vehicle.yaml: " + folder.string());
  pc.vehicle = *cal.vehicle;
  p.gravity = pc.vehicle.gravity;
  if (cal.rotor) {
    // thrust noise density from the rotor-speed noise at hover speed
    const double k_mean = [&] {
      double s = 0;
      for (double k : pc.vehicle.rotor_thrust_coefficients) s += k;
      return s / pc.vehicle.rotor_thrust_coefficients.size();
    }();
    const int count = static_cast<int>(pc.vehicle.rotor_thrust_coefficients.size());
    const double n_hover = std::sqrt(pc.vehicle.mass_kg * p.gravity / (count * k_mean));
    RotorSample hover;
    hover.speeds.assign(count, n_hover);
    p.thrust_noise_density =
        collective_thrust_sigma(hover, pc.vehicle, cal.rotor->noise_density) / pc.vehicle.mass_kg;
  }
  // Diagnosis only (vio_core_diag_sim): VIO_CORE_FORCE_RW, VIO_CORE_MAX_FEATURES,
  // VIO_CORE_NO_ACCEL, VIO_CORE_THRUST_NOISE, VIO_CORE_PIXEL_NOISE, VIO_CORE_NO_FEJ override params.
  if (const char* rw = std::getenv("VIO_CORE_FORCE_RW")) p.force_random_walk = std::atof(rw);
  if (const char* mf = std::getenv("VIO_CORE_MAX_FEATURES")) p.max_features_per_update = std::atoi(mf);
  if (std::getenv("VIO_CORE_NO_ACCEL")) p.accel_update = false;
  if (const char* tn = std::getenv("VIO_CORE_THRUST_NOISE")) p.thrust_noise_density = std::atof(tn);
  pc.cameras = cal.cameras;
  std::vector<std::unique_ptr<CameraModel>> models;
  for (const CameraCalib& c : cal.cameras) models.push_back(CameraModel::create(c));
  // The presets simulate features with pixel_noise_sigma 0.5 px (config/sim/README.md); with
  // 0.5 the per-feature 95% chi2 gate rejects ~5% (consistent), with 1.0 only ~0.03%.
  if (!cal.cameras.empty()) p.pixel_noise_px = 0.5;
  if (const char* px = std::getenv("VIO_CORE_PIXEL_NOISE")) p.pixel_noise_px = std::atof(px);
  if (std::getenv("VIO_CORE_NO_FEJ")) p.use_fej = false;
  if (const char* ws = std::getenv("VIO_CORE_WINDOW")) p.window_size = std::atoi(ws);
  if (const char* sb = std::getenv("VIO_CORE_INIT_SIGMA_BA")) p.init_sigma_accel_bias = std::atof(sb);
  if (const char* fr = std::getenv("VIO_CORE_FORCE_RATE_RW")) p.force_rate_random_walk = std::atof(fr);
  if (const char* ff = std::getenv("VIO_CORE_FORCE_FRAME")) p.force_frame = force_frame_from_string(ff);

  Pipeline pipe(pc);
  std::map<TimeNs, EstimateOutput> est;
  pipe.set_estimate_callback([&](const EstimateOutput& e) { est[e.t_ns] = e; });
  SimMetrics m;
  double frame_ms = 0;
  long frames = 0;
  pipe.set_frame_callback([&](const FrameTimings& f) {
    frame_ms += f.propagation_ms + f.accel_update_ms + f.msckf_update_ms + f.marginalization_ms;
    ++frames;
  });
  std::vector<GroundTruthSample> gt;
  std::vector<ForceSample> forces;
  while (auto meas = reader.next()) {
    if (auto* f = std::get_if<FeatureFrame>(&*meas)) {
      for (FeatureObservation& o : f->observations) {
        if (o.cam_id >= 0 && o.cam_id < static_cast<int>(models.size())) {
          o.has_norm = models[o.cam_id]->undistort(o.uv, &o.uv_norm);
        }
      }
    } else if (auto* g = std::get_if<GroundTruthSample>(&*meas)) {
      gt.push_back(*g);
    } else if (auto* fs = std::get_if<ForceSample>(&*meas)) {
      forces.push_back(*fs);
    }
    pipe.push(*meas);
  }
  pipe.finish();
  m.status = to_string(pipe.status()) + (pipe.status() == FilterStatus::kOk ? "" : ": " + pipe.status_message());
  m.estimates = static_cast<long>(est.size());
  m.visual_updates = pipe.counters().visual_updates;
  m.features_used = pipe.counters().features_used;
  m.features_rejected = pipe.counters().features_rejected;
  m.frames = pipe.counters().frames;
  std::printf("  [%s] chi2 rejected %ld, too short %ld\n", to_string(mode).c_str(), pipe.counters().features_rejected_chi2, pipe.counters().features_too_short);
  m.obs_without_norm = pipe.counters().observations_without_norm;
  m.accel_rejected = pipe.counters().accel_rejected;
  m.mean_frame_ms = frames ? frame_ms / frames : 0.0;

  auto nearest = [&](TimeNs t) -> const EstimateOutput* {
    auto it = est.lower_bound(t);
    const EstimateOutput* best = nullptr;
    TimeNs bd = 3'000'000;
    if (it != est.end() && it->first - t <= bd) {
      best = &it->second;
      bd = it->first - t;
    }
    if (it != est.begin()) {
      --it;
      if (t - it->first < bd) best = &it->second;
    }
    return best;
  };
  std::vector<Eigen::Vector3d> pe, pg;
  // Optional per-sample dump for diagnosis: VIO_CORE_SIM_DUMP=<file.csv>
  std::FILE* dump = std::getenv("VIO_CORE_SIM_DUMP") ? std::fopen((std::string(std::getenv("VIO_CORE_SIM_DUMP")) + "_" + to_string(mode) + ".csv").c_str(), "w") : nullptr;
  for (const GroundTruthSample& g : gt) {
    if (const EstimateOutput* e = nearest(g.t_ns)) {
      if (dump) {
        const Eigen::Vector3d dth = so3::boxminus(e->x.q_WI, g.q_WI);
        std::fprintf(dump, "%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.5f,%.5f,%.5f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n",
                     (g.t_ns - gt.front().t_ns) * 1e-9, e->x.p_WI.x(), e->x.p_WI.y(), e->x.p_WI.z(),
                     g.p_WI.x(), g.p_WI.y(), g.p_WI.z(), dth.x(), dth.y(), dth.z(),
                     (e->x.v_WI - g.v_WI).norm(), (e->x.b_a - g.b_a).norm(), e->F_ext_I.x(),
                     e->F_ext_I.y(), e->F_ext_I.z(), (e->x.b_g - g.b_g).norm());
        const Eigen::Vector3d F_W = e->F_ext_W;
        std::fprintf(dump, "F,%.6f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.6f,%.6f,%.6f,%.5f,%.5f,%.5f\n", (g.t_ns - gt.front().t_ns) * 1e-9, F_W.x(), F_W.y(), F_W.z(),
                     e->x.b_a.x() - g.b_a.x(), e->x.b_a.y() - g.b_a.y(), e->x.b_a.z() - g.b_a.z(),
                     e->sigma(0), e->sigma(1), e->sigma(2), e->sigma(12), e->sigma(13), e->sigma(14));
      }
      pe.push_back(e->x.p_WI);
      pg.push_back(g.p_WI);
    }
  }
  if (dump) std::fclose(dump);
  m.ate_posyaw_m = pe.size() > 10 ? ate_posyaw(pe, pg) : 1e9;
  double sum = 0;
  long n = 0;
  for (const ForceSample& f : forces) {
    if (const EstimateOutput* e = nearest(f.t_ns)) {
      const Eigen::Vector3d F_W = e->F_ext_W;
      sum += (F_W - f.f_W_N / pc.vehicle.mass_kg).squaredNorm();
      ++n;
    }
  }
  m.force_rmse_W = n ? std::sqrt(sum / n) : 1e9;
  return m;
}

}  // namespace vid::test
