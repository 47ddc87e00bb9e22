// See sim_system.h.
#include "sim_system.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <unistd.h>

#include "consistency.h"
#include "geometry/so3.h"
#include "vid_system/metrics.h"
#include "vid_system/system.h"
#include "vio_core/initializer.h"
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

namespace {

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// FNV-1a 64: a stable fingerprint of a file's bytes (not security, only "did it change").
std::string fingerprint(const std::string& bytes) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ULL;
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

constexpr const char* kMadeBy = "made_by.txt";

}  // namespace

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
  const std::filesystem::path scenario_src = std::filesystem::path(VID_SOURCE_DIR) / "config" / "sim" / (preset + ".yaml");
  const std::filesystem::path sim = std::filesystem::path(VID_BINARY_DIR) / "bin" / "vid_sim";
  std::string yaml = read_file(scenario_src);
  if (noise_free) {
    // The preset with every sensor noise off (its top-level `noise: true` switched off).
    const auto at = yaml.find("\nnoise: true");
    if (at == std::string::npos) throw std::runtime_error("no 'noise: true' line in " + scenario_src.string());
    yaml.replace(at, 12, "\nnoise: false");
  }
  // What made the folder (docs/testing.md "Cached inputs"): the simulator binary, the scenario
  // as simulated, seed and duration. A folder made by anything else is regenerated, never reused.
  std::string key = "vid_sim " + fingerprint(read_file(sim)) + "\nscenario " + scenario_src.string() + " " +
                    fingerprint(yaml) + "\nseed " + std::to_string(seed) + "\nduration_s " +
                    std::to_string(duration_s) + "\nnoise_free " + (noise_free ? "1" : "0") + "\n";
  if (std::filesystem::exists(out / "mav0" / "feat0" / "data.csv")) {
    std::string made_by;
    if (std::filesystem::exists(out / kMadeBy)) made_by = read_file(out / kMadeBy);
    if (made_by == key) return out;
    std::printf("[cache] %s was made by another simulator or scenario: regenerating\n", out.c_str());
    // Move it aside first: a parallel test that already checked it never sees a half-removed folder.
    const std::filesystem::path stale = out.string() + ".stale" + std::to_string(::getpid());
    std::error_code ec;
    std::filesystem::rename(out, stale, ec);
    std::filesystem::remove_all(stale, ec);
  }
  // Generate next to the target and rename, so that tests running in parallel never see a
  // half-written folder (the loser of the race removes its copy).
  const std::filesystem::path tmp = out.string() + ".tmp" + std::to_string(::getpid());
  std::filesystem::remove_all(tmp);
  std::filesystem::create_directories(tmp);
  const std::filesystem::path scenario = tmp.string() + ".yaml";
  std::ofstream(scenario) << yaml;  // the scenario's relative paths: none in the presets used here
  std::string cmd = sim.string() + " --scenario " + (noise_free ? scenario : scenario_src).string() + " --out " +
                    tmp.string() + " --seed " + std::to_string(seed) + " --features-only --quiet";
  if (duration_s > 0) cmd += " --duration " + std::to_string(duration_s);
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("failed: " + cmd);
  std::ofstream(tmp / kMadeBy) << key;
  std::error_code ec;
  std::filesystem::rename(tmp, out, ec);
  if (ec) std::filesystem::remove_all(tmp);
  std::filesystem::remove(scenario);
  if (!std::filesystem::exists(out / "mav0" / "feat0" / "data.csv")) {
    throw std::runtime_error("no feature-level dataset at " + out.string());
  }
  return out;
}

system::SystemParams sim_params(const io::DatasetCalibration& cal, PropagationMode mode) {
  system::SystemParams sp;
  sp.mode_source = "sim_params";
  sp.features = system::FeatureSource::kFeat0;
  sp.truth_vehicle = cal.vehicle;
  system::SystemConfig& cfg = sp.config;
  cfg.cameras = cal.cameras;
  cfg.imu = cal.imu;
  cfg.rotor = cal.rotor;
  EstimatorParams& p = cfg.estimator;
  p.mode = mode;
  p.init_mode = InitMode::kGroundTruth;
  // The ideal simulator's force model (exact thrust, smooth rope forces): the estimator's
  // defaults before they became a real vehicle's (0.3, 1.0; docs/notes/real-sensors.md); the
  // figures these tests hold were measured with it.
  p.force_random_walk = 0.02;
  p.force_rate_random_walk = 0.3;
  if (cal.imu) {
    p.gyro_noise_density = cal.imu->gyro_noise_density;
    p.gyro_random_walk = cal.imu->gyro_random_walk;
    p.accel_noise_density = cal.imu->accel_noise_density;
    p.accel_random_walk = cal.imu->accel_random_walk;
    p.imu_rate_hz = cal.imu->rate_hz;
  }
  if (!cal.vehicle) throw std::runtime_error("dataset has no vehicle.yaml");
  cfg.vehicle = *cal.vehicle;
  const VehicleParams& vehicle = *cfg.vehicle;
  p.gravity = vehicle.gravity;
  if (cal.rotor) {
    // thrust noise density from the rotor-speed noise at hover speed
    const double k_mean = [&] {
      double s = 0;
      for (double k : vehicle.rotor_thrust_coefficients) s += k;
      return s / vehicle.rotor_thrust_coefficients.size();
    }();
    const int count = static_cast<int>(vehicle.rotor_thrust_coefficients.size());
    const double n_hover = std::sqrt(vehicle.mass_kg * p.gravity / (count * k_mean));
    RotorSample hover;
    hover.speeds.assign(count, n_hover);
    p.thrust_noise_density = collective_thrust_sigma(hover, vehicle, cal.rotor->noise_density) / vehicle.mass_kg;
  }
  // The presets simulate features with pixel_noise_sigma 0.5 px (config/sim/README.md); with
  // 0.5 the per-feature 95% chi2 gate rejects ~5% (consistent), with 1.0 only ~0.03%.
  if (!cal.cameras.empty()) p.pixel_noise_px = 0.5;
  return sp;
}

namespace {

io::DatasetReader open_features(const std::filesystem::path& folder) {
  io::ReaderOptions opt;
  opt.read_images = false;
  return io::DatasetReader(folder, opt);
}

}  // namespace

SimMetrics run_on_dataset(const std::filesystem::path& folder, PropagationMode mode, bool noise_free) {
  system::SystemParams params = sim_params(open_features(folder).calibration(), mode);
  if (noise_free) set_noise_free_params(params.config.estimator);
  return run_on_dataset(folder, params);
}

SimMetrics run_on_dataset(const std::filesystem::path& folder, const system::SystemParams& params) {
  io::DatasetReader reader = open_features(folder);
  system::System sys(params);
  std::map<TimeNs, EstimateOutput> est;
  sys.on_estimate([&](const EstimateOutput& e) { est[e.t_ns] = e; });
  SimMetrics m;
  double frame_ms = 0;
  long frames = 0;
  sys.on_frame([&](const FrameTimings& f) {
    frame_ms += f.propagation_ms + f.accel_update_ms + f.msckf_update_ms + f.marginalization_ms;
    ++frames;
  });
  std::vector<GroundTruthSample> gt;
  std::vector<ForceSample> forces;
  while (auto meas = reader.next()) {
    if (auto* g = std::get_if<GroundTruthSample>(&*meas)) {
      gt.push_back(*g);
    } else if (auto* fs = std::get_if<ForceSample>(&*meas)) {
      forces.push_back(*fs);
    }
    sys.push(*meas);  // ground truth too: ground-truth initialization
  }
  sys.finish();
  const EstimatorCounters c = sys.counters();
  m.status = to_string(sys.status()) + (sys.status() == FilterStatus::kOk ? "" : ": " + sys.status_message());
  m.estimates = static_cast<long>(est.size());
  m.visual_updates = c.visual_updates;
  m.features_used = c.features_used;
  m.features_rejected = c.features_rejected;
  m.frames = c.frames;
  std::printf("  [%s] chi2 rejected %ld, too short %ld\n", to_string(params.config.estimator.mode).c_str(),
              c.features_rejected_chi2, c.features_too_short);
  m.obs_without_norm = c.observations_without_norm;
  m.accel_rejected = c.accel_rejected;
  m.mean_frame_ms = frames ? frame_ms / frames : 0.0;

  // Series for the library's metrics (system/metrics.h); estimates come at every IMU time.
  const double mass = params.config.vehicle->mass_kg;
  std::vector<const EstimateOutput*> e_at;
  system::Vec3Series e_p, e_F_W, g_p, g_F_W;
  for (const auto& [t, e] : est) {
    e_at.push_back(&e);
    e_p.t_ns.push_back(t);
    e_p.v.push_back(e.x.T_WI.p);
    e_F_W.t_ns.push_back(t);
    e_F_W.v.push_back(e.F_ext_W);
  }
  for (const GroundTruthSample& g : gt) {
    g_p.t_ns.push_back(g.t_ns);
    g_p.v.push_back(g.T_WI.p);
  }
  for (const ForceSample& f : forces) {
    g_F_W.t_ns.push_back(f.t_ns);
    g_F_W.v.push_back(f.f_W_N / mass);
  }
  const auto ate = system::ate_posyaw(e_p, g_p);
  m.ate_posyaw_m = ate && ate->pairs > 10 ? ate->rmse_m : 1e9;
  m.force_rmse_W = system::force_rmse(e_F_W, g_F_W).value_or(1e9);  // ground-truth init: no yaw gauge

  // Largest errors, estimate nearest to each truth sample within 3 ms.
  constexpr TimeNs kTol = 3'000'000;
  for (const auto& [ie, ig] : system::associate_nearest(e_p.t_ns, g_p.t_ns, kTol)) {
    const EstimateOutput& e = *e_at[ie];
    m.pos_err_max_m = std::max(m.pos_err_max_m, (e.x.T_WI.p - gt[ig].T_WI.p).norm());
    m.theta_err_max_rad = std::max(m.theta_err_max_rad, so3::boxminus(e.x.T_WI.q, gt[ig].T_WI.q).norm());
  }
  for (const auto& [ie, ig] : system::associate_nearest(e_F_W.t_ns, g_F_W.t_ns, kTol)) {
    if (g_F_W.t_ns[ig] - g_F_W.t_ns.front() >= 5'000'000'000LL)
      m.force_err_max_after5_W = std::max(m.force_err_max_after5_W, (e_F_W.v[ie] - g_F_W.v[ig]).norm());
  }
  return m;
}

NeesSeries nees_on_dataset(const std::filesystem::path& folder, PropagationMode mode, unsigned init_seed) {
  // First pass: ground truth and true force at the start (the initial estimate's centre).
  std::optional<GroundTruthSample> gt0;
  std::optional<ForceSample> f0;
  {
    io::DatasetReader first = open_features(folder);
    while (auto meas = first.next()) {
      if (auto* g = std::get_if<GroundTruthSample>(&*meas); g && !gt0) gt0 = *g;
      if (auto* f = std::get_if<ForceSample>(&*meas); f && !f0) f0 = *f;
      if (gt0 && f0) break;
    }
  }
  if (!gt0 || !f0) throw std::runtime_error("nees_on_dataset: no ground truth or force0 in " + folder.string());
  io::DatasetReader reader = open_features(folder);
  const system::SystemParams params = sim_params(reader.calibration(), mode);
  const EstimatorParams& p = params.config.estimator;
  const double mass = params.config.vehicle->mass_kg;

  // Initial estimate: truth perturbed by one draw from the initial covariance, so that the
  // NEES starts chi2-distributed instead of at zero.
  ImuState x0 = state_from_groundtruth(*gt0);
  if (mode == PropagationMode::kDynamics) {
    set_force_from_body(x0, p.force_frame, gt0->T_WI.q.conjugate() * (f0->f_W_N / mass));
  }
  const Eigen::MatrixXd P0 = initial_covariance(p, x0.T_WI.q);
  perturb_by_covariance(x0, P0, init_seed);

  system::System sys(params);
  sys.initialize(gt0->t_ns, x0, P0);
  std::map<TimeNs, EstimateOutput> est;
  sys.on_estimate([&](const EstimateOutput& e) { est[e.t_ns] = e; });
  std::vector<GroundTruthSample> gt;
  std::map<TimeNs, Eigen::Vector3d> force_W;
  while (auto meas = reader.next()) {
    if (auto* g = std::get_if<GroundTruthSample>(&*meas)) {
      if (gt.empty() || g->t_ns - gt.back().t_ns >= 100'000'000) gt.push_back(*g);  // 10 Hz
      continue;  // initialized above: the estimator does not need ground truth
    } else if (auto* fs = std::get_if<ForceSample>(&*meas)) {
      force_W[fs->t_ns] = fs->f_W_N / mass;
      continue;
    }
    sys.push(*meas);
  }
  sys.finish();
  NeesSeries out;
  out.status = to_string(sys.status());
  for (const GroundTruthSample& g : gt) {
    auto it = est.find(g.t_ns);  // estimates come at every IMU time; ground truth sits on them
    auto ft = force_W.find(g.t_ns);
    if (it == est.end() || ft == force_W.end()) continue;
    const EstimateOutput& e = it->second;
    const Eigen::Vector3d e_th = so3::boxminus(e.x.T_WI.q, g.T_WI.q);
    const Eigen::Vector3d e_p = e.x.T_WI.p - g.T_WI.p;
    out.t.push_back((g.t_ns - gt.front().t_ns) * 1e-9);
    out.theta.push_back(e_th.dot(e.cov_theta.ldlt().solve(e_th)));
    out.p.push_back(e_p.dot(e.cov_p.ldlt().solve(e_p)));
    if (mode == PropagationMode::kDynamics) {
      const Eigen::Vector3d e_F = e.F_ext_I - g.T_WI.q.conjugate() * ft->second;
      out.F.push_back(e_F.dot(e.cov_F_I.ldlt().solve(e_F)));
    } else {
      out.F.push_back(0.0);
    }
  }
  return out;
}

}  // namespace vid::test
