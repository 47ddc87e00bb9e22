/// @file dynamic_initializer.cpp
/// @brief In-flight initialization (dynamic_initializer.h).
#include "vio_core/dynamic_initializer.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "geometry/so3.h"
#include "vio_core/mono_alignment.h"
#include "vio_core/zero_velocity.h"

namespace vid {
namespace {
// Inertial chi2 per degree of freedom beyond which the window is refused: residuals 30x the
// modelled noise.
constexpr double kMaxInertialChi2PerDof = 1000.0;
// Visual chi2 per degree of freedom of the frame positions beyond which the window is refused:
// residuals 10x the pixel noise. The gyro's rotations over the window are wrong (garbage samples
// inside it that the gyro-bias solve tried to absorb: 5e3 at the end of an IMU burst), not a
// mis-set pixel noise (0.01-1.6 on every accepted simulated and Blackbird window).
constexpr double kMaxVisualChi2PerDof = 100.0;
constexpr int kMaxFrames = 16;     // frames of the window used (evenly spaced): cost, not accuracy
constexpr int kMaxLandmarks = 120;  // cost: the dense system has 3 unknowns per landmark
constexpr int kWantedPerFrame = 40;  // tracks per frame the selection aims at
constexpr int kMinBearingsPerFrame = 6;
// Mono: the frames' structure carries the scale and the gyro bias from frame to frame, and thin
// windows fit the data with a wrong bias: fast_yaw (3 rad/s) at 9-10 bearings per frame took
// 0.05 rad/s of its yaw as a gyro bias and handed over tilts 5-9 degrees off at a 1.4 degree
// sigma. An accepted vid17_like window had 50 per frame.
constexpr int kMinBearingsPerFrameMono = 20;
// Relative sigma of a mono window's scale beyond which it is refused. The scale is seen only
// through the accelerometer, and its Gauss-Newton sigma is computed at the estimate: far from
// the truth (a window with too little acceleration, e.g. a straight cruise: any scale fits) the
// linearization claims more than the data hold (a constant-velocity window gave sigma_v 0.13 for
// a 0.81 m/s error). Within 25 % the local sigma held in the Monte-Carlo test.
constexpr double kMaxMonoScaleSigma = 0.25;
}  // namespace

DynamicInitializer::DynamicInitializer(const EstimatorParams& params, std::vector<CameraCalib> cameras)
    : params_(params), cameras_(std::move(cameras)) {}

void DynamicInitializer::reset() {
  imu_.clear();
  frames_.clear();
  reason_.clear();
  diag_ = DynamicInitDiagnostics{};
}

void DynamicInitializer::add_imu(TimeNs t, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel,
                                 const Eigen::Vector3d& T_m) {
  imu_.push_back({t, gyro, accel, T_m});
  const TimeNs keep = seconds_to_ns(window_s() + 0.5);
  while (imu_.size() > 2 && t - imu_.front().t > keep) imu_.pop_front();
}

std::optional<InitResult> DynamicInitializer::add_frame(const FeatureFrame& frame) {
  if (cameras_.empty()) {
    reason_ = "in-flight initialization needs a camera";
    return std::nullopt;
  }
  frames_.push_back(frame);
  const TimeNs span = seconds_to_ns(window_s());
  while (frames_.size() > 1 && frame.t_ns - frames_[1].t_ns >= span) frames_.pop_front();
  if (frame.t_ns - frames_.front().t_ns < span) return std::nullopt;
  if (imu_.empty() || imu_.front().t > frames_.front().t_ns || imu_.back().t < frame.t_ns) {
    reason_ = "IMU samples do not cover the window";
    return std::nullopt;
  }
  return try_window();
}

std::optional<double> DynamicInitializer::parallax_px(TimeNs t_from) const {
  // cam0 between the first frame at or after t_from and the newest, the gyro's rotation removed.
  auto old = std::find_if(frames_.begin(), frames_.end(), [&](const FeatureFrame& f) { return f.t_ns >= t_from; });
  if (old == frames_.end() || old->t_ns - t_from > 100'000'000 || frames_.back().t_ns <= old->t_ns) return std::nullopt;
  if (imu_.empty() || imu_.front().t > old->t_ns || imu_.back().t < frames_.back().t_ns) return std::nullopt;
  std::vector<align::ImuRow> rows;
  for (const ImuSample3& s : imu_) rows.push_back({s.t, s.w, s.a});
  const align::WindowIntegrals w = align::integrate_window(rows, {old->t_ns, frames_.back().t_ns});
  const CameraCalib& c0 = cameras_.front();
  const Eigen::Matrix3d R_IC = c0.T_IC.linear();
  const Eigen::Matrix3d R_new_old = R_IC.transpose() * w.R_Kk[0] * R_IC;
  std::unordered_map<std::uint64_t, Eigen::Vector2d> seen;
  for (const FeatureObservation& o : old->observations)
    if (o.has_norm && o.cam_id == c0.cam_id) seen[o.feature_id] = o.uv_norm;
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> pairs;
  for (const FeatureObservation& o : frames_.back().observations)
    if (auto it = seen.find(o.feature_id); o.has_norm && o.cam_id == c0.cam_id && it != seen.end())
      pairs.emplace_back(it->second, o.uv_norm);
  const WindowParallax px = rotation_compensated_parallax(pairs, R_new_old, 0.5 * (c0.intrinsics[0] + c0.intrinsics[1]));
  if (px.features < 10) return std::nullopt;
  return px.median_px;
}

std::vector<align::Track> DynamicInitializer::window_tracks(std::vector<int>* used) const {
  // Evenly spaced frames of the window, the last one always.
  const int n = static_cast<int>(frames_.size());
  const int m = std::min(n, kMaxFrames);
  used->clear();
  for (int i = 0; i < m; ++i) used->push_back(static_cast<int>(std::lround(i * (n - 1.0) / std::max(1, m - 1))));
  used->erase(std::unique(used->begin(), used->end()), used->end());
  std::map<std::uint64_t, align::Track> by_id;
  for (int k = 0; k < static_cast<int>(used->size()); ++k) {
    for (const FeatureObservation& o : frames_[(*used)[k]].observations) {
      if (!o.has_norm) continue;
      const int cam = o.cam_id == cameras_[0].cam_id ? 0 : !mono() && o.cam_id == cameras_[1].cam_id ? 1 : -1;
      if (cam < 0) continue;
      align::Track& tr = by_id[o.feature_id];
      tr.id = o.feature_id;
      tr.obs.push_back({k, cam, o.uv_norm});
    }
  }
  std::vector<align::Track> tracks;
  for (auto& [id, tr] : by_id) {
    // Stereo: the scale needs a stereo pair somewhere on the track, the frames it seen twice.
    // Mono: seen in three frames (two give a landmark, a third constrains the motion).
    bool stereo = false;
    int frames_seen = 0, last = -1;
    for (std::size_t i = 0; i < tr.obs.size(); ++i) {
      if (tr.obs[i].frame != last) ++frames_seen;
      if (i > 0 && tr.obs[i].frame == tr.obs[i - 1].frame && tr.obs[i].cam != tr.obs[i - 1].cam) stereo = true;
      last = tr.obs[i].frame;
    }
    if (mono() ? frames_seen >= 3 : stereo && frames_seen >= 2) tracks.push_back(std::move(tr));
  }
  std::stable_sort(tracks.begin(), tracks.end(),
                   [](const align::Track& a, const align::Track& b) { return a.obs.size() > b.obs.size(); });
  // Longest first, but every frame covered: a track is taken while one of its frames has fewer
  // than kWantedPerFrame bearings (at 3 rad/s of yaw no track spans the window; the frames are
  // chained by overlapping ones).
  std::vector<int> per_frame(used->size(), 0);
  std::vector<align::Track> chosen;
  for (align::Track& tr : tracks) {
    if (static_cast<int>(chosen.size()) >= kMaxLandmarks) break;
    bool needed = false;
    for (const align::Bearing& b : tr.obs) needed = needed || per_frame[b.frame] < kWantedPerFrame;
    if (!needed) continue;
    for (std::size_t i = 0; i < tr.obs.size(); ++i)
      if (i == 0 || tr.obs[i].frame != tr.obs[i - 1].frame) ++per_frame[tr.obs[i].frame];
    chosen.push_back(std::move(tr));
  }
  return chosen;
}

std::optional<InitResult> DynamicInitializer::try_window() {
  std::vector<int> used;
  const std::vector<align::Track> tracks = window_tracks(&used);
  diag_ = DynamicInitDiagnostics{};
  diag_.frames = static_cast<int>(used.size());
  std::vector<int> per_frame(used.size(), 0);
  for (const align::Track& tr : tracks)
    for (const align::Bearing& b : tr.obs) ++per_frame[b.frame];
  const int fewest = *std::min_element(per_frame.begin(), per_frame.end());
  const int min_per_frame = mono() ? kMinBearingsPerFrameMono : kMinBearingsPerFrame;
  if (static_cast<int>(tracks.size()) < params_.init_dynamic_min_features || fewest < min_per_frame) {
    reason_ = std::string(mono() ? "too few features" : "too few stereo features") +
              " tracked through the window (" + std::to_string(tracks.size()) + " tracks of the " +
              std::to_string(params_.init_dynamic_min_features) + " needed, " + std::to_string(fewest) +
              " in the sparsest frame of the " + std::to_string(min_per_frame) + " needed)";
    return std::nullopt;
  }
  std::vector<TimeNs> times;
  for (int k : used) times.push_back(frames_[k].t_ns);
  const CameraCalib& c0 = cameras_[0];
  const double sigma_norm = params_.pixel_noise_px / (0.5 * (c0.intrinsics[0] + c0.intrinsics[1]));
  if (mono()) return align_mono(tracks, times, sigma_norm);
  std::vector<Eigen::Isometry3d> T_IC{cameras_[0].T_IC, cameras_[1].T_IC};
  // Gyro bias: real IMUs have up to 0.08 rad/s (euroc_like: 0.077), which turns the window's
  // rotations by 0.08 rad; solved with the positions from the bearings, re-integrated each time.
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();
  align::WindowIntegrals w;
  std::optional<align::FramePositions> pos;
  for (int it = 0; it < 4; ++it) {
    w = integrate(times, b_g);
    pos = align::solve_frame_positions(tracks, w.R_Kk, T_IC, sigma_norm, &reason_,
                                       rotation_bias_jacobians(times, b_g, w));
    if (!pos) return std::nullopt;
    b_g += pos->d_bg;
    cov_b_g_ = pos->cov_bg;
    if (pos->d_bg.norm() < 1e-4) break;
  }
  // The positions and their covariance of the joint solve (the bias's uncertainty included).
  w = integrate(times, b_g);
  b_g_ = b_g;
  diag_.landmarks = pos->landmarks;
  diag_.observations = pos->observations;
  diag_.visual_chi2_per_dof = pos->chi2_per_dof;
  if (pos->chi2_per_dof > kMaxVisualChi2PerDof) {
    reason_ = "the gyro's rotations disagree with the camera over the window (chi2/dof " +
              std::to_string(pos->chi2_per_dof) + ")";
    return std::nullopt;
  }
  // The gyro bias's error turns the alphas: d alpha / d b_g numerically, times its covariance.
  const Eigen::MatrixXd Ja = alpha_bias_jacobian(times, b_g, w);
  const align::AlignedState s = align::solve_gravity_velocity(*pos, w, params_.accel_noise_density,
                                                              params_.init_sigma_accel_bias, params_.gravity,
                                                              Ja * cov_b_g_ * Ja.transpose());
  diag_.inertial_chi2_per_dof = s.chi2_per_dof;
  if (!s.cov.allFinite() || !s.v_I.allFinite()) {
    reason_ = "gravity and velocity not determined";
    return std::nullopt;
  }
  // IMU and camera far apart over the window: corrupted samples (a burst of garbage after which
  // the run re-initializes gave 2e8), not a mis-set noise density (the real Blackbird IMU with
  // the importer's noise: up to 20; the covariance is inflated by chi2/dof for those).
  if (s.chi2_per_dof > kMaxInertialChi2PerDof) {
    reason_ = "the IMU disagrees with the camera over the window (chi2/dof " + std::to_string(s.chi2_per_dof) + ")";
    return std::nullopt;
  }
  InitResult r = hand_over(s);
  add_window_poses(&r, times, w, pos->p);
  return r;
}

std::optional<InitResult> DynamicInitializer::align_mono(const std::vector<align::Track>& tracks,
                                                         const std::vector<TimeNs>& times, double sigma_norm) {
  const align::MonoNoise noise{sigma_norm, params_.accel_noise_density, params_.init_sigma_accel_bias,
                               params_.gravity};
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();
  align::WindowIntegrals w;
  std::optional<align::MonoAlignment> m;
  for (int it = 0; it < 4; ++it) {
    w = integrate(times, b_g);
    m = align::solve_mono_window(tracks, w, cameras_[0].T_IC, noise, rotation_bias_jacobians(times, b_g, w),
                                 alpha_bias_jacobian(times, b_g, w), &reason_);
    if (!m) return std::nullopt;
    b_g += m->pos.d_bg;
    cov_b_g_ = m->pos.cov_bg;
    if (m->pos.d_bg.norm() < 1e-4) break;
  }
  b_g_ = b_g;
  diag_.landmarks = m->pos.landmarks;
  diag_.observations = m->pos.observations;
  diag_.visual_chi2_per_dof = m->pos.chi2_per_dof;
  diag_.inertial_chi2_per_dof = m->inertial_chi2_per_dof;
  diag_.scale_sigma = m->scale_sigma;
  if (m->pos.chi2_per_dof > kMaxVisualChi2PerDof) {
    reason_ = "the gyro's rotations disagree with the camera over the window (chi2/dof " +
              std::to_string(m->pos.chi2_per_dof) + ")";
    return std::nullopt;
  }
  if (m->inertial_chi2_per_dof > kMaxInertialChi2PerDof) {
    reason_ = "the IMU disagrees with the camera over the window (chi2/dof " +
              std::to_string(m->inertial_chi2_per_dof) + ")";
    return std::nullopt;
  }
  if (!(m->scale_sigma <= kMaxMonoScaleSigma)) {
    reason_ = "too little acceleration over the mono window to fix the scale (its sigma " +
              std::to_string(100.0 * m->scale_sigma) + " %)";
    return std::nullopt;
  }
  InitResult r = hand_over(m->state);
  add_window_poses(&r, times, w, m->pos.p);
  return r;
}

align::WindowIntegrals DynamicInitializer::integrate(const std::vector<TimeNs>& times, const Eigen::Vector3d& b_g) const {
  std::vector<align::ImuRow> rows;
  for (const ImuSample3& s : imu_) rows.push_back({s.t, s.w - b_g, s.a});
  return align::integrate_window(rows, times);
}

std::vector<Eigen::Matrix3d> DynamicInitializer::rotation_bias_jacobians(const std::vector<TimeNs>& times,
                                                                         const Eigen::Vector3d& b_g,
                                                                         const align::WindowIntegrals& w) const {
  constexpr double h = 1e-4;
  std::vector<Eigen::Matrix3d> J_bg(w.R_Kk.size(), Eigen::Matrix3d::Zero());
  for (int i = 0; i < 3; ++i) {  // the gyro enters as w - b_g
    const align::WindowIntegrals wp = integrate(times, b_g + h * Eigen::Vector3d::Unit(i));
    for (std::size_t k = 0; k < J_bg.size(); ++k) J_bg[k].col(i) = so3::log(w.R_Kk[k].transpose() * wp.R_Kk[k]) / h;
  }
  return J_bg;
}

Eigen::MatrixXd DynamicInitializer::alpha_bias_jacobian(const std::vector<TimeNs>& times, const Eigen::Vector3d& b_g,
                                                        const align::WindowIntegrals& w) const {
  const int K = static_cast<int>(w.alpha.size()) - 1;
  Eigen::MatrixXd Ja(3 * K, 3);
  for (int i = 0; i < 3; ++i) {
    constexpr double h = 1e-4;
    const align::WindowIntegrals wp = integrate(times, b_g + h * Eigen::Vector3d::Unit(i));
    for (int k = 0; k < K; ++k) Ja.block<3, 1>(3 * k, i) = (wp.alpha[k] - w.alpha[k]) / h;
  }
  return Ja;
}

void DynamicInitializer::add_window_poses(InitResult* r, const std::vector<TimeNs>& times,
                                          const align::WindowIntegrals& w,
                                          const std::vector<Eigen::Vector3d>& p) const {
  r->t_ns = frames_.back().t_ns;
  const Eigen::Matrix3d R_WK = r->x.T_WI.q.toRotationMatrix();
  for (std::size_t k = 0; k + 1 < p.size(); ++k) {
    TimedPose pose{times[k], Pose{}};
    pose.T.q = Eigen::Quaterniond(R_WK * w.R_Kk[k]).normalized();
    pose.T.p = r->x.T_WI.p + R_WK * p[k];
    r->window_poses.push_back(pose);
  }
}

InitResult DynamicInitializer::hand_over(const align::AlignedState& s) const {
  InitResult r;
  r.x.T_WI.q = gravity_aligned_orientation(-s.g_I);  // R_WI (-g_I) along +z_W, yaw 0
  const Eigen::Matrix3d R = r.x.T_WI.q.toRotationMatrix();
  r.x.v_WI = R * s.v_I;
  r.x.b_a = s.b_a;
  r.x.b_g = b_g_;
  if (params_.mode == PropagationMode::kDynamics) {
    // External force: what the accelerometer measures beyond the thrust, last 0.1 s.
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    int n = 0;
    for (auto it = imu_.rbegin(); it != imu_.rend() && imu_.back().t - it->t <= 100'000'000; ++it, ++n)
      f += it->a - s.b_a - it->T;
    set_force_from_body(r.x, params_.force_frame, f / std::max(1, n));
  }
  r.P = initial_covariance(params_, r.x.T_WI.q);
  // (v_I, g_I, b_a) -> (theta, v_W, b_a), errors true - estimate, theta a right perturbation:
  // g_I = R^T g_W gives dg = [g_I]x dtheta, so dtheta = -[g_I]x dg / |g|^2 (its tilt part);
  // v_W = R v_I gives dv_W = R dv_I - R [v_I]x dtheta.
  const double g2 = s.g_I.squaredNorm();
  const Eigen::Matrix3d J_theta_g = -so3::skew(s.g_I) / g2;
  Eigen::Matrix<double, 9, 9> T = Eigen::Matrix<double, 9, 9>::Zero();
  T.block<3, 3>(0, 3) = J_theta_g;
  T.block<3, 3>(3, 0) = R;
  T.block<3, 3>(3, 3) = -R * so3::skew(s.v_I) * J_theta_g;
  T.block<3, 3>(6, 6).setIdentity();
  Eigen::Matrix<double, 9, 9> C = T * s.cov * T.transpose();
  const Eigen::Vector3d z_I = -s.g_I / std::sqrt(g2);  // yaw: the gauge, as the static initializer's
  C.block<3, 3>(0, 0) += params_.init_sigma_yaw * params_.init_sigma_yaw * z_I * z_I.transpose();
  const int idx[3] = {imu_idx::kTheta, imu_idx::kV, imu_idx::kBa};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) r.P.block<3, 3>(idx[a], idx[b]) = C.block<3, 3>(3 * a, 3 * b);
  // Gyro bias from the window's rotations (its correlation with the rest left out).
  r.P.block<3, 3>(imu_idx::kBg, imu_idx::kBg) = cov_b_g_;
  return r;
}

}  // namespace vid
