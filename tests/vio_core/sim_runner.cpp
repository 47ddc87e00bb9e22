// See sim_runner.h.
#include "sim_runner.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <unistd.h>

#include "consistency.h"
#include "frontend/camera_model.h"
#include "geometry/so3.h"
#include "io/dataset_reader.h"
#include "vio_core/initializer.h"
#include "vio_core/pipeline.h"
#include "vio_core/thrust.h"

namespace vid::test {

void set_noise_free_params(EstimatorParams& p) {
  // Small positive densities keep P well conditioned on exact data.
  p.gyro_noise_density = 1e-5;
  p.accel_noise_density = 1e-4;
  p.thrust_noise_density = 1e-4;
  p.gyro_random_walk = 1e-6;
  p.accel_random_walk = 1e-5;
  p.pixel_noise_px = 0.01;
}

std::filesystem::path ensure_sim_dataset(const std::string& preset, int seed, double duration_s,
                                         bool noise_free) {
  std::string dur;  // built stepwise: GCC 12 warns (-Wrestrict) on "_" + std::to_string(..)
  if (duration_s > 0) {
    dur += '_';
    dur += std::to_string(static_cast<int>(duration_s));
    dur += 's';
  }
  const std::filesystem::path out = std::filesystem::path(VID_BINARY_DIR) / "vio_core_sim" /
                                    (preset + dur + (noise_free ? "_exact" : "") + "_seed" + std::to_string(seed));
  if (std::filesystem::exists(out / "mav0" / "feat0" / "data.csv")) return out;
  // Generate next to the target and rename, so that tests running in parallel never see a
  // half-written folder (the loser of the race removes its copy).
  const std::filesystem::path tmp = out.string() + ".tmp" + std::to_string(::getpid());
  std::filesystem::remove_all(tmp);
  std::filesystem::create_directories(tmp);
  std::filesystem::path scenario = std::filesystem::path(VID_SOURCE_DIR) / "config" / "sim" / (preset + ".yaml");
  if (noise_free) {
    // The preset with every sensor noise off (its top-level `noise: true` switched off).
    std::ifstream in(scenario);
    std::stringstream text;
    text << in.rdbuf();
    std::string yaml = text.str();
    const auto at = yaml.find("\nnoise: true");
    if (at == std::string::npos) throw std::runtime_error("no 'noise: true' line in " + scenario.string());
    yaml.replace(at, 12, "\nnoise: false");
    scenario = tmp.string() + ".yaml";
    std::ofstream(scenario) << yaml;
  }
  std::string cmd = std::string(VID_BINARY_DIR) + "/bin/vid_sim --scenario " + scenario.string() + " --out " +
                    tmp.string() + " --seed " + std::to_string(seed) + " --features-only --quiet";
  if (duration_s > 0) cmd += " --duration " + std::to_string(duration_s);
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("failed: " + cmd);
  std::error_code ec;
  std::filesystem::rename(tmp, out, ec);
  if (ec) std::filesystem::remove_all(tmp);
  if (noise_free) std::filesystem::remove(tmp.string() + ".yaml");
  if (!std::filesystem::exists(out / "mav0" / "feat0" / "data.csv")) {
    throw std::runtime_error("no feature-level dataset at " + out.string());
  }
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

// Normalized undistorted coordinates of every observation of a feature-level frame.
void undistort(const std::vector<std::unique_ptr<CameraModel>>& models, FeatureFrame& f) {
  for (FeatureObservation& o : f.observations) {
    if (o.cam_id >= 0 && o.cam_id < static_cast<int>(models.size())) {
      o.has_norm = models[o.cam_id]->undistort(o.uv, &o.uv_norm);
    }
  }
}

// The pipeline configuration used on simulator folders: the folder's own IMU, rotor and
// vehicle calibration, ground-truth initialization, estimator defaults otherwise; diagnosis
// overrides from the environment (vio_core_diag_sim).
PipelineConfig sim_config(const io::DatasetCalibration& cal, PropagationMode mode,
                          std::vector<std::unique_ptr<CameraModel>>* models) {
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
  if (!cal.vehicle) throw std::runtime_error("dataset has no vehicle.yaml");
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
  for (const CameraCalib& c : cal.cameras) models->push_back(CameraModel::create(c));
  // The presets simulate features with pixel_noise_sigma 0.5 px (config/sim/README.md); with
  // 0.5 the per-feature 95% chi2 gate rejects ~5% (consistent), with 1.0 only ~0.03%.
  if (!cal.cameras.empty()) p.pixel_noise_px = 0.5;
  if (const char* px = std::getenv("VIO_CORE_PIXEL_NOISE")) p.pixel_noise_px = std::atof(px);
  if (std::getenv("VIO_CORE_NO_FEJ")) p.use_fej = false;
  if (std::getenv("VIO_CORE_NOISE_FREE")) set_noise_free_params(p);
  if (const char* ws = std::getenv("VIO_CORE_WINDOW")) p.window_size = std::atoi(ws);
  if (const char* sb = std::getenv("VIO_CORE_INIT_SIGMA_BA")) p.init_sigma_accel_bias = std::atof(sb);
  if (const char* fr = std::getenv("VIO_CORE_FORCE_RATE_RW")) p.force_rate_random_walk = std::atof(fr);
  if (const char* ff = std::getenv("VIO_CORE_FORCE_FRAME")) p.force_frame = force_frame_from_string(ff);

  return pc;
}

}  // namespace

SimMetrics run_on_dataset(const std::filesystem::path& folder, PropagationMode mode, bool noise_free) {
  io::ReaderOptions opt;
  opt.read_images = false;
  io::DatasetReader reader(folder, opt);
  std::vector<std::unique_ptr<CameraModel>> models;
  PipelineConfig pc = sim_config(reader.calibration(), mode, &models);
  if (noise_free) set_noise_free_params(pc.params);
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
      undistort(models, *f);
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
      m.pos_err_max_m = std::max(m.pos_err_max_m, (e->x.p_WI - g.p_WI).norm());
      m.theta_err_max_rad = std::max(m.theta_err_max_rad, so3::boxminus(e->x.q_WI, g.q_WI).norm());
    }
  }
  if (dump) std::fclose(dump);
  m.ate_posyaw_m = pe.size() > 10 ? ate_posyaw(pe, pg) : 1e9;
  double sum = 0;
  long n = 0;
  for (const ForceSample& f : forces) {
    if (const EstimateOutput* e = nearest(f.t_ns)) {
      const Eigen::Vector3d F_W = e->F_ext_W;
      const double err2 = (F_W - f.f_W_N / pc.vehicle.mass_kg).squaredNorm();
      sum += err2;
      ++n;
      if (f.t_ns - forces.front().t_ns >= 5'000'000'000LL) {
        m.force_err_max_after5_W = std::max(m.force_err_max_after5_W, std::sqrt(err2));
      }
    }
  }
  m.force_rmse_W = n ? std::sqrt(sum / n) : 1e9;
  return m;
}

NeesSeries nees_on_dataset(const std::filesystem::path& folder, PropagationMode mode, unsigned init_seed) {
  io::ReaderOptions opt;
  opt.read_images = false;
  std::vector<std::unique_ptr<CameraModel>> models;
  // First pass: ground truth and true force at the start (the initial estimate's centre).
  std::optional<GroundTruthSample> gt0;
  std::optional<ForceSample> f0;
  {
    io::DatasetReader first(folder, opt);
    while (auto meas = first.next()) {
      if (auto* g = std::get_if<GroundTruthSample>(&*meas); g && !gt0) gt0 = *g;
      if (auto* f = std::get_if<ForceSample>(&*meas); f && !f0) f0 = *f;
      if (gt0 && f0) break;
    }
  }
  if (!gt0 || !f0) throw std::runtime_error("nees_on_dataset: no ground truth or force0 in " + folder.string());
  io::DatasetReader reader(folder, opt);
  const PipelineConfig pc = sim_config(reader.calibration(), mode, &models);
  const double mass = pc.vehicle.mass_kg;

  // Initial estimate: truth perturbed by one draw from the initial covariance, so that the
  // NEES starts chi2-distributed instead of at zero.
  ImuState x0 = state_from_groundtruth(*gt0);
  if (mode == PropagationMode::kDynamics) {
    set_force_from_body(x0, pc.params.force_frame, gt0->q_WI.conjugate() * (f0->f_W_N / mass));
  }
  const Eigen::MatrixXd P0 = initial_covariance(pc.params, x0.q_WI);
  perturb_by_covariance(x0, P0, init_seed);

  Pipeline pipe(pc);
  pipe.initialize(gt0->t_ns, x0, P0);
  std::map<TimeNs, EstimateOutput> est;
  pipe.set_estimate_callback([&](const EstimateOutput& e) { est[e.t_ns] = e; });
  std::vector<GroundTruthSample> gt;
  std::map<TimeNs, Eigen::Vector3d> force_W;
  while (auto meas = reader.next()) {
    if (auto* f = std::get_if<FeatureFrame>(&*meas)) {
      undistort(models, *f);
    } else if (auto* g = std::get_if<GroundTruthSample>(&*meas)) {
      if (gt.empty() || g->t_ns - gt.back().t_ns >= 100'000'000) gt.push_back(*g);  // 10 Hz
      continue;  // initialized above: the pipeline does not need ground truth
    } else if (auto* fs = std::get_if<ForceSample>(&*meas)) {
      force_W[fs->t_ns] = fs->f_W_N / mass;
      continue;
    }
    pipe.push(*meas);
  }
  pipe.finish();
  NeesSeries out;
  out.status = to_string(pipe.status());
  for (const GroundTruthSample& g : gt) {
    auto it = est.find(g.t_ns);  // estimates come at every IMU time; ground truth sits on them
    auto ft = force_W.find(g.t_ns);
    if (it == est.end() || ft == force_W.end()) continue;
    const EstimateOutput& e = it->second;
    const Eigen::Vector3d e_th = so3::boxminus(e.x.q_WI, g.q_WI);
    const Eigen::Vector3d e_p = e.x.p_WI - g.p_WI;
    out.t.push_back((g.t_ns - gt.front().t_ns) * 1e-9);
    out.theta.push_back(e_th.dot(e.cov_theta.ldlt().solve(e_th)));
    out.p.push_back(e_p.dot(e.cov_p.ldlt().solve(e_p)));
    if (mode == PropagationMode::kDynamics) {
      const Eigen::Vector3d e_F = e.F_ext_I - g.q_WI.conjugate() * ft->second;
      out.F.push_back(e_F.dot(e.cov_F_I.ldlt().solve(e_F)));
    } else {
      out.F.push_back(0.0);
    }
  }
  return out;
}

}  // namespace vid::test
