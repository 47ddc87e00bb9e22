#include "sim/render/feature_simulator.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "frontend/camera_model.h"
#include "io/strict_yaml.h"

namespace vid::sim {

FeatureSimConfig parse_feature_sim_config(const YAML::Node& node, const std::string& file) {
  FeatureSimConfig c;
  const io::YamlMap m = io::YamlMap::from_node(node, file, "features");
  c.target_per_camera = m.get_int("target_per_camera", c.target_per_camera);
  c.pixel_noise_sigma = m.get_double("pixel_noise_sigma", c.pixel_noise_sigma);
  c.drop_probability = m.get_double("drop_probability", c.drop_probability);
  c.border_px = m.get_double("border_px", c.border_px);
  c.max_incidence_deg = m.get_double("max_incidence_deg", c.max_incidence_deg);
  c.min_depth_m = m.get_double("min_depth_m", c.min_depth_m);
  c.max_depth_m = m.get_double("max_depth_m", c.max_depth_m);
  c.min_separation_px = m.get_double("min_separation_px", c.min_separation_px);
  Eigen::Vector2d grid(c.grid_cols, c.grid_rows);
  grid = m.get_vec2("grid", grid);
  c.seed = m.get_u64("seed", c.seed);
  m.check_unknown();
  if (grid.x() != std::floor(grid.x()) || grid.y() != std::floor(grid.y()) || grid.x() < 1 ||
      grid.y() < 1 || grid.x() > 64 || grid.y() > 64) {
    m.fail("grid", "expected two integers in 1..64");
  }
  c.grid_cols = static_cast<int>(grid.x());
  c.grid_rows = static_cast<int>(grid.y());
  if (c.target_per_camera < 0 || c.target_per_camera > 5000) {
    m.fail("target_per_camera", "must be in [0, 5000]");
  }
  if (c.pixel_noise_sigma < 0.0) m.fail("pixel_noise_sigma", "must be >= 0");
  if (c.drop_probability < 0.0 || c.drop_probability >= 1.0) {
    m.fail("drop_probability", "must be in [0, 1)");
  }
  if (c.border_px < 0.0) m.fail("border_px", "must be >= 0");
  if (c.max_incidence_deg <= 0.0 || c.max_incidence_deg > 90.0) {
    m.fail("max_incidence_deg", "must be in (0, 90]");
  }
  if (c.min_depth_m <= 0.0 || c.max_depth_m <= c.min_depth_m) {
    m.fail("max_depth_m", "need 0 < min_depth_m < max_depth_m");
  }
  if (c.min_separation_px < 0.0) m.fail("min_separation_px", "must be >= 0");
  return c;
}

FeatureSimulator::FeatureSimulator(const Scene& scene, const std::vector<CameraCalib>& cameras,
                                   const FeatureSimConfig& config)
    : scene_(scene), config_(config),
      cos_max_incidence_(std::cos(config.max_incidence_deg * std::numbers::pi / 180.0)),
      track_rng_(derive_seed(config.seed, 2)), noise_rng_(derive_seed(config.seed, 1)) {
  for (const auto& c : cameras) cameras_.push_back(CameraModel::create(c));
}

FeatureSimulator::~FeatureSimulator() = default;

bool FeatureSimulator::visible(std::size_t k, const Eigen::Isometry3d& T_WC,
                               const Eigen::Vector3d& p_W, const Eigen::Vector3d& n_W,
                               Eigen::Vector2d* uv) const {
  const Eigen::Vector3d p_C = T_WC.inverse() * p_W;
  if (p_C.z() < config_.min_depth_m || p_C.norm() > config_.max_depth_m) return false;
  if (!cameras_[k]->project(p_C, uv) || !cameras_[k]->in_image(*uv, config_.border_px)) {
    return false;
  }
  const Eigen::Vector3d ray = p_W - T_WC.translation();
  const double dist = ray.norm();
  if (n_W.dot(-ray) < cos_max_incidence_ * dist) return false;  // too oblique or back side
  // Occluded if the first surface along the ray is closer than the landmark.
  const auto hit = scene_.intersect(T_WC.translation(), ray);
  return hit && hit->t > 1.0 - 1e-6;
}

void FeatureSimulator::spawn(std::size_t k, const Eigen::Isometry3d& T_WC,
                             std::vector<Eigen::Vector2d>* taken) {
  const CameraModel& cam = *cameras_[k];
  const int gc = config_.grid_cols, gr = config_.grid_rows;
  const double cw = static_cast<double>(cam.width()) / gc, chh = static_cast<double>(cam.height()) / gr;
  std::vector<int> count(static_cast<std::size_t>(gc * gr), 0);
  auto cell_of = [&](const Eigen::Vector2d& uv) {
    const int cx = std::clamp(static_cast<int>(uv.x() / cw), 0, gc - 1);
    const int cy = std::clamp(static_cast<int>(uv.y() / chh), 0, gr - 1);
    return cy * gc + cx;
  };
  for (const auto& uv : *taken) ++count[cell_of(uv)];
  const double sep2 = config_.min_separation_px * config_.min_separation_px;
  int deficit = config_.target_per_camera - static_cast<int>(taken->size());
  const int max_attempts = 6 * std::max(deficit, 0) + 20;
  for (int attempt = 0; attempt < max_attempts && deficit > 0; ++attempt) {
    // The emptiest cell (ties: first after a random start) gets the next feature.
    const int start = track_rng_.uniform_int(gc * gr);
    int best = start;
    for (int i = 0; i < gc * gr; ++i) {
      const int c = (start + i) % (gc * gr);
      if (count[c] < count[best]) best = c;
    }
    const Eigen::Vector2d uv((best % gc + track_rng_.uniform()) * cw,
                             (best / gc + track_rng_.uniform()) * chh);
    if (!cam.in_image(uv, config_.border_px)) continue;
    const bool crowded = std::any_of(taken->begin(), taken->end(), [&](const Eigen::Vector2d& q) {
      return (q - uv).squaredNorm() < sep2;
    });
    Eigen::Vector3d bearing_C;
    if (crowded || !cam.unproject(uv, &bearing_C)) {
      ++count[best];  // try elsewhere next time
      continue;
    }
    const auto hit = scene_.intersect(T_WC.translation(), T_WC.linear() * bearing_C);
    Eigen::Vector2d uv_exact;
    if (!hit || !visible(k, T_WC, hit->p_W, hit->normal_W, &uv_exact)) {
      ++count[best];
      continue;
    }
    Landmark lm;
    lm.id = landmarks_.size();
    lm.p_W = hit->p_W;
    lm.normal_W = hit->normal_W;
    landmarks_.push_back(lm);
    active_.push_back(lm.id);  // ids grow, so active_ stays sorted
    taken->push_back(uv_exact);
    ++count[cell_of(uv_exact)];
    --deficit;
  }
}

FeatureFrame FeatureSimulator::step(TimeNs t_ns, const Eigen::Isometry3d& T_WI) {
  const std::size_t nc = cameras_.size();
  std::vector<Eigen::Isometry3d> T_WC(nc);
  for (std::size_t k = 0; k < nc; ++k) T_WC[k] = T_WI * cameras_[k]->calib().T_IC;

  // Keep tracks that some camera still sees, minus random losses.
  std::vector<std::uint64_t> kept;
  std::vector<std::vector<Eigen::Vector2d>> taken(nc);
  Eigen::Vector2d uv;
  std::vector<char> seen_in(nc);
  for (const std::uint64_t id : active_) {
    const Landmark& lm = landmarks_[id];
    bool seen = false;
    for (std::size_t k = 0; k < nc; ++k) {
      seen_in[k] = visible(k, T_WC[k], lm.p_W, lm.normal_W, &uv);
      if (seen_in[k]) {
        seen = true;
        taken[k].push_back(uv);
      }
    }
    const bool dropped = track_rng_.uniform() < config_.drop_probability;
    if (seen && !dropped) {
      kept.push_back(id);
    } else {  // lost track: its pixels no longer block new features
      for (std::size_t k = 0; k < nc; ++k) {
        if (seen_in[k]) taken[k].pop_back();
      }
    }
  }
  active_ = std::move(kept);
  for (std::size_t k = 0; k < nc; ++k) {
    const std::size_t first_new = landmarks_.size();
    spawn(k, T_WC[k], &taken[k]);
    // New features that later cameras see count towards their targets too (stereo overlap).
    for (std::size_t id = first_new; id < landmarks_.size(); ++id) {
      for (std::size_t j = k + 1; j < nc; ++j) {
        if (visible(j, T_WC[j], landmarks_[id].p_W, landmarks_[id].normal_W, &uv)) {
          taken[j].push_back(uv);
        }
      }
    }
  }

  FeatureFrame frame;
  frame.t_ns = t_ns;
  for (std::size_t k = 0; k < nc; ++k) {
    const CameraModel& cam = *cameras_[k];
    const Eigen::Isometry3d T_CW = T_WC[k].inverse();
    for (const std::uint64_t id : active_) {
      const Landmark& lm = landmarks_[id];
      if (!visible(k, T_WC[k], lm.p_W, lm.normal_W, &uv)) continue;
      FeatureObservation ob;
      ob.cam_id = cam.calib().cam_id;
      ob.feature_id = id;
      if (config_.pixel_noise_sigma > 0.0) {
        ob.uv = uv + config_.pixel_noise_sigma * Eigen::Vector2d(noise_rng_.normal(), noise_rng_.normal());
        ob.has_norm = cam.undistort(ob.uv, &ob.uv_norm);
      } else {
        const Eigen::Vector3d p_C = T_CW * lm.p_W;
        ob.uv = uv;
        ob.uv_norm = p_C.head<2>() / p_C.z();
        ob.has_norm = true;
      }
      frame.observations.push_back(ob);
    }
  }
  return frame;
}

}  // namespace vid::sim
