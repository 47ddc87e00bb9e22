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
/// ```

#include <Eigen/Core>
#include <cstdint>
#include <string>

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

/// @brief Everything that defines the rendered world; same config -> identical scene.
struct SceneConfig {
  Eigen::Vector3d room_size{12.0, 10.0, 4.0};    ///< [m]
  Eigen::Vector3d room_center{0.0, 0.0, 1.5};    ///< W [m]
  std::uint64_t texture_seed = 1;
  double texels_per_m = 250.0;
  BoxesConfig boxes;
  CheckerboardConfig checkerboard;
};

/// @brief Parse (with io::YamlMap; a null node = all defaults) a `scene:` YAML map. Missing keys keep their defaults; unknown keys and bad
/// values throw vid::io::ConfigError naming `file` and the key (e.g. "scene.boxes.count").
SceneConfig parse_scene_config(const YAML::Node& scene_node, const std::string& file);

/// @brief Check ranges (positive sizes, board inside its wall, keep-out leaves room, ...);
/// throws vid::io::ConfigError naming `file`.
void validate_scene_config(const SceneConfig& config, const std::string& file);

}  // namespace vid::sim
