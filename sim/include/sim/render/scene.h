#pragma once
/// @file scene.h
/// @brief The simulated world: an axis-aligned room (walls, floor, ceiling) with obstacle
/// boxes and an optional checkerboard on a wall, every surface with its own procedural
/// texture. Built deterministically from a SceneConfig. Geometry is exact (double); the
/// renderer and the feature simulator both use it, so images and landmarks agree in 3-D.

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <optional>
#include <string>
#include <vector>

#include "sim/render/scene_config.h"

namespace vid::sim {

/// @brief One axis-aligned rectangle of the scene with its texture.
/// Surface ids: room faces 0..5 = 2*axis + (max side ? 1 : 0); box b face f -> 6 + 6*b + f.
struct Surface {
  int normal_axis = 0;         ///< 0, 1, 2 = x, y, z
  int u_axis = 1, v_axis = 2;  ///< texture axes (the two other W axes)
  double plane = 0.0;          ///< W coordinate along normal_axis
  double normal_sign = 1.0;    ///< the side facing free space: +1 or -1 along normal_axis
  double u0 = 0.0, v0 = 0.0;   ///< W coordinates of the texture origin (rectangle min corner)
  double u_len = 0.0, v_len = 0.0;  ///< rectangle size [m]
  cv::Mat texture;             ///< CV_8UC1, cols along u, rows along v
  /// Mip levels: mips[0] is `texture`, mips[L] is 2^L x 2^L box-averaged (texel j of level L
  /// covers texels [2^L j, 2^L (j+1)) of level 0), down to a few texels.
  std::vector<cv::Mat> mips;
};

/// @brief Axis-aligned obstacle box.
struct Box {
  Eigen::Vector3d min_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d max_W = Eigen::Vector3d::Zero();
};

/// @brief Result of a ray query.
struct SceneHit {
  double t = 0.0;               ///< ray parameter: p_W = origin + t * dir
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_W = Eigen::Vector3d::Zero();  ///< unit normal facing the ray origin
  int surface = -1;             ///< surface id (see Surface)
  Eigen::Vector2d uv_m = Eigen::Vector2d::Zero();      ///< texture coordinate on it [m]
};

/// @brief Room + boxes + optional checkerboard, with textures.
class Scene {
 public:
  /// @brief Build from config (validated; throws vid::io::ConfigError on bad values).
  explicit Scene(const SceneConfig& config);

  /// @brief First surface point hit by the ray (dir need not be unit), or nothing.
  std::optional<Eigen::Vector3d> raycast(const Eigen::Vector3d& origin_W,
                                         const Eigen::Vector3d& dir_W) const;
  /// @brief First hit with surface id, normal and texture coordinate (t > 1e-9).
  std::optional<SceneHit> intersect(const Eigen::Vector3d& origin_W,
                                    const Eigen::Vector3d& dir_W) const;

  /// @brief Gray level [0, 255] of surface `surface` at texture coordinate (u, v) [m]:
  /// bilinear texture lookup, or the checkerboard pattern on the board, box-filtered over
  /// `footprint_m` (the sample spacing on the surface; 0: the exact, unfiltered pattern).
  /// The filter keeps the board's edges and corners free of sampling bias.
  float shade(int surface, double u_m, double v_m, double footprint_m = 0.0) const;

  /// @brief True if p_W is inside the room and outside every box (by `margin` metres).
  bool is_free(const Eigen::Vector3d& p_W, double margin = 0.0) const;

  const SceneConfig& config() const { return config_; }
  const std::vector<Surface>& surfaces() const { return surfaces_; }
  const std::vector<Box>& boxes() const { return boxes_; }
  Eigen::Vector3d room_min() const { return room_min_; }
  Eigen::Vector3d room_max() const { return room_max_; }

  /// @brief Inner corners of the checkerboard in W ((squares_x-1) x (squares_y-1), row by
  /// row from the top); empty if the scene has no board.
  std::vector<Eigen::Vector3d> checkerboard_corners_W() const;
  /// @brief Surface id of the wall carrying the board, or -1.
  int checkerboard_surface() const { return board_surface_; }
  /// @brief Board rectangle (squares only) in that wall's texture coordinates [m].
  Eigen::Vector4d checkerboard_rect_uv() const { return board_rect_; }

  /// @brief Board gray levels (dark squares, light squares and margin).
  static constexpr float kBoardDark = 25.0f;
  static constexpr float kBoardLight = 230.0f;

 private:
  void place_boxes();
  void make_surfaces();
  float board_value(double u, double v, double footprint_m) const;
  /// Multiply a surface's texture by the lamp's light (config.lighting).
  void apply_lighting(Surface* s) const;

  SceneConfig config_;
  Eigen::Vector3d room_min_, room_max_;
  std::vector<Box> boxes_;
  std::vector<Surface> surfaces_;
  int board_surface_ = -1;
  Eigen::Vector4d board_rect_ = Eigen::Vector4d::Zero();  ///< u_min, v_min, u_max, v_max
};

/// @brief Scene of a scenario YAML file: its `scene:` section (defaults if absent; other
/// top-level keys are ignored). Throws vid::io::ConfigError on unreadable files or bad keys.
Scene scene_from_scenario_file(const std::string& path);

/// @brief SceneConfig of a scenario YAML file (see scene_from_scenario_file).
SceneConfig scene_config_from_scenario_file(const std::string& path);

}  // namespace vid::sim
