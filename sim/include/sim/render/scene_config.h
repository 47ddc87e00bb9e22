#pragma once
/// @file scene_config.h
/// @brief Configuration of the simulated world (scenario YAML section `scene:`).
///
/// ```yaml
/// scene:
///   room_size: [12.0, 10.0, 4.0]   # x, y, z extent of the room [m]
///   room_center: [0.0, 0.0, 1.5]   # centre of the room box in W [m]
///   texture_seed: 7                # textures and box placement
///   texels_per_m: 250              # texture resolution
///   boxes:
///     count: 8
///     size_min: 0.3                # edge length range [m]
///     size_max: 1.2
///     keep_out_min: [-3, -3, -10]  # no box intersects this W box (the flight volume);
///     keep_out_max: [3, 3, 10]     # default: the central 60 % of the room in x and y
///   checkerboard:                  # optional calibration target on a wall
///     wall: +x                     # +x, -x, +y, -y (wall at the max/min x or y)
///     center: [0.0, 1.5]           # along-wall coordinate (y for x walls, x for y walls), z [m]
///     squares: [9, 7]              # squares horizontally, vertically
///     square_size: 0.08            # [m]
///   low_texture:                   # optional plain (painted) surfaces
///     surfaces: [+y, floor]        # room faces: +x, -x, +y, -y, floor, ceiling
///     box_fraction: 0.3            # share of the boxes with plain faces
///     noise_amplitude: 4.0         # smooth shading left on them [gray levels]
///   lighting:                      # optional: one lamp, brightness falls off away from it
///     lamp: [0.0, 0.0, 3.9]        # W [m]
///     ambient: 0.5                 # uniform share of the light
///     reach_m: 3.0                 # lamp share is min(1, cos(incidence) (reach / distance)^2)
/// ```

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace YAML {
class Node;
}

namespace vid::sim {

/// @brief Obstacle boxes inside the room.
struct BoxesConfig {
  int count = 8;
  double size_min = 0.3;  ///< [m]
  double size_max = 1.2;  ///< [m]
  bool has_keep_out = false;
  Eigen::Vector3d keep_out_min = Eigen::Vector3d::Zero();  ///< W [m]
  Eigen::Vector3d keep_out_max = Eigen::Vector3d::Zero();  ///< W [m]
};

/// @brief A black/white checkerboard printed on one wall (with a one-square white margin).
struct CheckerboardConfig {
  bool enabled = false;
  std::string wall = "+x";                          ///< "+x", "-x", "+y" or "-y"
  Eigen::Vector2d center{0.0, 1.5};                 ///< along-wall coordinate, height z [m]
  int squares_x = 9;                                ///< squares along the wall
  int squares_y = 7;                                ///< squares vertically
  double square_size = 0.08;                        ///< [m]
};

/// @brief Plain surfaces: no shapes, only weak smooth shading (few trackable corners).
struct LowTextureConfig {
  std::vector<std::string> surfaces;  ///< room faces: "+x", "-x", "+y", "-y", "floor", "ceiling"
  double box_fraction = 0.0;          ///< share of the boxes drawn plain, in [0, 1]
  double noise_amplitude = 4.0;       ///< [gray levels]
};

/// @brief Uneven room light baked into the textures: ambient + (1 - ambient) * lamp term,
/// lamp term = min(1, cos(incidence) * (reach_m / distance)^2); no shadows.
struct LightingConfig {
  bool enabled = false;
  Eigen::Vector3d lamp_W{0.0, 0.0, 3.0};
  double ambient = 0.5;
  double reach_m = 3.0;
};

/// @brief Everything that defines the rendered world; same config -> identical scene.
struct SceneConfig {
  Eigen::Vector3d room_size{12.0, 10.0, 4.0};    ///< [m]
  Eigen::Vector3d room_center{0.0, 0.0, 1.5};    ///< W [m]
  std::uint64_t texture_seed = 1;
  double texels_per_m = 250.0;
  BoxesConfig boxes;
  CheckerboardConfig checkerboard;
  LowTextureConfig low_texture;
  LightingConfig lighting;
};

/// @brief Parse (with io::YamlMap; a null node = all defaults) a `scene:` YAML map. Missing keys keep their defaults; unknown keys and bad
/// values throw vid::io::ConfigError naming `file` and the key (e.g. "scene.boxes.count").
SceneConfig parse_scene_config(const YAML::Node& scene_node, const std::string& file);

/// @brief Room face id (Surface ids 0..5) of "-x", "+x", "-y", "+y", "floor", "ceiling"; -1 if none.
int room_face_index(const std::string& name);

/// @brief Check ranges (positive sizes, board inside its wall, keep-out leaves room, ...);
/// throws vid::io::ConfigError naming `file`.
void validate_scene_config(const SceneConfig& config, const std::string& file);

}  // namespace vid::sim
