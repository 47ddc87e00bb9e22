#pragma once
/// @file synthetic_scene.h
/// @brief Deterministic synthetic MSCKF scene for tests and benchmarks: a stereo rig on a
/// short forward trajectory (clones), landmarks in front, exact and noisy normalized
/// observations, and a prior covariance over [IMU block, clones].

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "geometry/so3.h"
#include "vio_core/msckf/msckf_types.h"
#include "vio_core/msckf/projection.h"

namespace vid::msckf::testing {

struct SceneOptions {
  int num_clones = 11;
  int num_features = 40;
  bool stereo = true;
  int imu_block = 15;            ///< columns before the clones in P (IMU state)
  double pixel_sigma_norm = 0.0; ///< noise added to observations
  double focal = 400.0;          ///< for converting px to normalized units
  unsigned seed = 1;
};

struct Scene {
  std::vector<ClonePose> clones_true;
  std::vector<CameraExtrinsic> extrinsics;
  std::vector<Eigen::Vector3d> landmarks_W;
  std::vector<FeatureTrack> tracks;
  int state_dim = 0;
};

/// Pose of the camera rig: forward-looking (camera z = body x), VID-like mounting.
inline std::vector<CameraExtrinsic> make_extrinsics(bool stereo) {
  Eigen::Matrix3d R_IC;
  R_IC << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  CameraExtrinsic c0;
  c0.T_IC.linear() = R_IC * so3::exp(Eigen::Vector3d(0.01, -0.02, 0.015));
  c0.T_IC.translation() = Eigen::Vector3d(0.09, 0.03, 0.02);
  std::vector<CameraExtrinsic> out{c0};
  if (stereo) {
    CameraExtrinsic c1 = c0;
    c1.T_IC.translation() += c0.T_IC.linear() * Eigen::Vector3d(0.11, 0.0, 0.0);  // baseline
    c1.T_IC.linear() = c0.T_IC.linear() * so3::exp(Eigen::Vector3d(0.002, 0.004, -0.003));
    out.push_back(c1);
  }
  return out;
}

inline Scene make_scene(const SceneOptions& opt) {
  Scene s;
  std::mt19937 rng(opt.seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  s.extrinsics = make_extrinsics(opt.stereo);
  s.state_dim = opt.imu_block + 6 * opt.num_clones;
  for (int i = 0; i < opt.num_clones; ++i) {
    ClonePose c;
    c.t_ns = 1'000'000'000LL + i * 50'000'000LL;
    const double u = static_cast<double>(i);
    c.p_WI = Eigen::Vector3d(0.08 * u, 0.3 * std::sin(0.25 * u), 1.0 + 0.02 * u);
    c.R_WI = so3::exp(Eigen::Vector3d(0.02 * std::sin(u), 0.03 * std::cos(0.7 * u), 0.05 * u));
    c.R_WI_fej = c.R_WI;
    c.p_WI_fej = c.p_WI;
    c.cov_index = opt.imu_block + 6 * i;
    s.clones_true.push_back(c);
  }
  // Landmarks in front of the middle clone, visible from every clone and camera.
  const ClonePose& mid = s.clones_true[opt.num_clones / 2];
  std::uint64_t id = 100;
  while (static_cast<int>(s.landmarks_W.size()) < opt.num_features) {
    const Eigen::Vector3d p_I(3.0 + 4.0 * (0.5 * uni(rng) + 0.5), 2.0 * uni(rng), 1.2 * uni(rng));
    const Eigen::Vector3d p_W = mid.R_WI * p_I + mid.p_WI;
    FeatureTrack tr;
    tr.feature_id = id;
    bool visible = true;
    for (const ClonePose& c : s.clones_true) {
      for (std::size_t cam = 0; cam < s.extrinsics.size() && visible; ++cam) {
        Eigen::Vector2d z;
        visible = project_point(c.R_WI, c.p_WI, s.extrinsics[cam].T_IC, p_W, &z, 0.5) &&
                  std::abs(z.x()) < 0.75 && std::abs(z.y()) < 0.55;
        if (!visible) break;
        const Eigen::Vector2d noise(gauss(rng), gauss(rng));
        tr.obs.push_back({c.t_ns, static_cast<int>(cam), z + opt.pixel_sigma_norm * noise});
      }
    }
    if (!visible) continue;
    s.landmarks_W.push_back(p_W);
    s.tracks.push_back(tr);
    ++id;
  }
  return s;
}

}  // namespace vid::msckf::testing
