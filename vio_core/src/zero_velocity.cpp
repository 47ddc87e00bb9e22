/// @file zero_velocity.cpp
/// @brief Rotation-compensated window parallax and the zero-velocity update.
#include "vio_core/zero_velocity.h"

#include <algorithm>

#include "types/median.h"
#include "vio_core/ekf_update.h"

namespace vid {

WindowParallax rotation_compensated_parallax(const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& uv_old_new,
                                             const Eigen::Matrix3d& R_new_old, double focal_px) {
  std::vector<double> d;
  d.reserve(uv_old_new.size());
  for (const auto& [uv_old, uv_new] : uv_old_new) {
    const Eigen::Vector3d ray = R_new_old * uv_old.homogeneous();
    if (!(ray.z() > 1e-6)) continue;  // rotated behind the camera: no prediction
    d.push_back(focal_px * (uv_new - ray.head<2>() / ray.z()).norm());
  }
  WindowParallax out;
  out.features = static_cast<int>(d.size());
  if (d.empty()) return out;
  out.median_px = upper_median(d);
  return out;
}

void ParallaxWindow::add(const FeatureFrame& frame) {
  std::unordered_map<std::uint64_t, Eigen::Vector2d> uv;
  for (const FeatureObservation& o : frame.observations) {
    if (o.cam_id == cam_id_ && o.has_norm) uv.emplace(o.feature_id, o.uv_norm);
  }
  frames_.emplace_back(frame.t_ns, std::move(uv));
}

void ParallaxWindow::drop_before(TimeNs t) {
  while (!frames_.empty() && frames_.front().first < t) frames_.pop_front();
}

std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> ParallaxWindow::matches(TimeNs t_old) const {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> out;
  if (frames_.empty()) return out;
  const auto old = std::find_if(frames_.begin(), frames_.end(), [t_old](const auto& f) { return f.first == t_old; });
  if (old == frames_.end()) return out;
  for (const auto& [id, uv_new] : frames_.back().second) {
    const auto it = old->second.find(id);
    if (it != old->second.end()) out.emplace_back(it->second, uv_new);
  }
  return out;
}

bool zero_velocity_update(FilterState& state, double sigma_mps) {
  const std::vector<int> cols = {imu_idx::kV, imu_idx::kV + 1, imu_idx::kV + 2};
  const Eigen::MatrixXd H = Eigen::MatrixXd::Identity(3, 3);
  const Eigen::VectorXd r = -state.imu().v_WI;
  const Eigen::MatrixXd R = sigma_mps * sigma_mps * Eigen::MatrixXd::Identity(3, 3);
  return ekf_update_columns(state, cols, H, r, R, 0.0).applied;
}

}  // namespace vid
