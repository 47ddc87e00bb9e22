#pragma once
/// @file feature_simulator.h
/// @brief Feature-level simulation: landmarks on the scene surfaces observed by the cameras
/// like a tracking frontend would report them (distorted pixels, stable ids, tracks that
/// live while visible, random drops, new features spawned in empty image cells).
///
/// Landmarks are created on demand where a spawned feature's ray hits the scene, so their
/// supply never runs out; a landmark's id is its feature id and is never reused after its
/// track ends. Write landmarks() to landmarks.csv after the run.
///
/// Scenario YAML section (all optional):
/// ```yaml
/// features:
///   target_per_camera: 150     # spawn new features while a camera sees fewer
///   pixel_noise_sigma: 0.5     # Gaussian pixel noise [px] (0: exact projections)
///   drop_probability: 0.02     # per track and frame: lost like a KLT track
///   border_px: 2.0             # visible only this far inside the image
///   max_incidence_deg: 80      # not visible at more grazing view angles
///   min_depth_m: 0.2
///   max_depth_m: 20.0
///   min_separation_px: 8.0     # new features keep this distance to existing ones
///   grid: [8, 6]               # spawning grid (columns, rows)
///   seed: 1
/// ```

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sim/render/random.h"
#include "sim/render/scene.h"
#include "types/calibration.h"
#include "types/measurements.h"

namespace YAML {
class Node;
}

namespace vid {
class CameraModel;
}

namespace vid::sim {

/// @brief Settings of the feature-level simulation.
struct FeatureSimConfig {
  int target_per_camera = 150;
  double pixel_noise_sigma = 0.0;
  double drop_probability = 0.02;
  double border_px = 2.0;
  double max_incidence_deg = 80.0;
  double min_depth_m = 0.2;
  double max_depth_m = 20.0;
  double min_separation_px = 8.0;
  int grid_cols = 8;
  int grid_rows = 6;
  std::uint64_t seed = 1;
};

/// @brief Parse (with io::YamlMap; a null node = all defaults) a `features:` YAML map (strict keys; errors name file and key).
FeatureSimConfig parse_feature_sim_config(const YAML::Node& node, const std::string& file);

/// @brief A 3-D point on a scene surface; its id is the feature id of its one track.
struct Landmark {
  std::uint64_t id = 0;
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_W = Eigen::Vector3d::Zero();  ///< surface normal (towards free space)
};

/// @brief Produces one FeatureFrame per call, for a sequence of IMU poses.
class FeatureSimulator {
 public:
  /// @brief The scene must outlive the simulator. One entry per camera (cam_id from calib).
  FeatureSimulator(const Scene& scene, const std::vector<CameraCalib>& cameras,
                   const FeatureSimConfig& config);
  ~FeatureSimulator();
  FeatureSimulator(const FeatureSimulator&) = delete;
  FeatureSimulator& operator=(const FeatureSimulator&) = delete;

  /// @brief Observations of all cameras at time t_ns for IMU pose T_WI (camera poses are
  /// T_WI * T_IC). Observations are ordered by camera, then feature id.
  FeatureFrame step(TimeNs t_ns, const Eigen::Isometry3d& T_WI);

  /// @brief Every landmark created so far, in id order (id == index).
  const std::vector<Landmark>& landmarks() const { return landmarks_; }
  /// @brief Number of tracks alive after the last step.
  std::size_t active_tracks() const { return active_.size(); }
  /// @brief Camera model of camera index k (as passed to the constructor).
  const CameraModel& camera(std::size_t k) const { return *cameras_[k]; }

  /// @brief True if landmark point p_W (on a surface with normal n_W) is visible from camera
  /// k at pose T_WC: in front, inside the image (border), not too oblique, not occluded.
  /// On success *uv is its exact (noise-free) pixel.
  bool visible(std::size_t k, const Eigen::Isometry3d& T_WC, const Eigen::Vector3d& p_W,
               const Eigen::Vector3d& n_W, Eigen::Vector2d* uv) const;

 private:
  void spawn(std::size_t k, const Eigen::Isometry3d& T_WC,
             std::vector<Eigen::Vector2d>* taken);

  const Scene& scene_;
  std::vector<std::unique_ptr<CameraModel>> cameras_;
  FeatureSimConfig config_;
  double cos_max_incidence_;
  std::vector<Landmark> landmarks_;
  std::vector<std::uint64_t> active_;  ///< ids of live tracks, ascending
  Rng track_rng_;
  Rng noise_rng_;
};

}  // namespace vid::sim
