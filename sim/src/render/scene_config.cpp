#include "sim/render/scene_config.h"

#include <yaml-cpp/yaml.h>

#include "io/errors.h"
#include "yaml_fields.h"

namespace vid::sim {

SceneConfig parse_scene_config(const YAML::Node& scene_node, const std::string& file) {
  SceneConfig c;
  const detail::YamlMap m(scene_node, file, "scene");
  m.allow_only({"room_size", "room_center", "texture_seed", "texels_per_m", "boxes",
                "checkerboard"});
  m.read("room_size", &c.room_size);
  m.read("room_center", &c.room_center);
  m.read("texture_seed", &c.texture_seed);
  m.read("texels_per_m", &c.texels_per_m);
  if (m.has("boxes")) {
    const detail::YamlMap b = m.child("boxes");
    b.allow_only({"count", "size_min", "size_max", "keep_out_min", "keep_out_max"});
    b.read("count", &c.boxes.count);
    b.read("size_min", &c.boxes.size_min);
    b.read("size_max", &c.boxes.size_max);
    if (b.has("keep_out_min") != b.has("keep_out_max")) {
      b.fail(b.has("keep_out_min") ? "keep_out_min" : "keep_out_max",
             "keep_out_min and keep_out_max must be given together");
    }
    if (b.has("keep_out_min")) {
      c.boxes.has_keep_out = true;
      b.read("keep_out_min", &c.boxes.keep_out_min);
      b.read("keep_out_max", &c.boxes.keep_out_max);
    }
  }
  if (m.has("checkerboard")) {
    const detail::YamlMap k = m.child("checkerboard");
    k.allow_only({"wall", "center", "squares", "square_size"});
    c.checkerboard.enabled = true;
    k.read("wall", &c.checkerboard.wall);
    k.read("center", &c.checkerboard.center);
    Eigen::Vector2d sq(c.checkerboard.squares_x, c.checkerboard.squares_y);
    k.read("squares", &sq);
    if (sq.x() != static_cast<int>(sq.x()) || sq.y() != static_cast<int>(sq.y())) {
      k.fail("squares", "expected two integers");
    }
    c.checkerboard.squares_x = static_cast<int>(sq.x());
    c.checkerboard.squares_y = static_cast<int>(sq.y());
    k.read("square_size", &c.checkerboard.square_size);
  }
  validate_scene_config(c, file);
  return c;
}

void validate_scene_config(const SceneConfig& c, const std::string& file) {
  auto bad = [&](const std::string& key, const std::string& msg) {
    throw io::ConfigError(file + ": key 'scene." + key + "': " + msg);
  };
  if ((c.room_size.array() <= 0.0).any()) bad("room_size", "sizes must be positive");
  if (c.texels_per_m < 10.0 || c.texels_per_m > 2000.0) bad("texels_per_m", "must be in [10, 2000]");
  const double area = 2.0 * (c.room_size.x() * c.room_size.y() + c.room_size.x() * c.room_size.z() +
                             c.room_size.y() * c.room_size.z());
  if (area * c.texels_per_m * c.texels_per_m > 4.0e8) {
    bad("texels_per_m", "textures would exceed 400 Mtexel; lower texels_per_m or the room size");
  }
  if (c.boxes.count < 0 || c.boxes.count > 200) bad("boxes.count", "must be in [0, 200]");
  if (c.boxes.size_min <= 0.0 || c.boxes.size_max < c.boxes.size_min) {
    bad("boxes.size_min", "need 0 < size_min <= size_max");
  }
  if (c.boxes.size_max > c.room_size.minCoeff()) bad("boxes.size_max", "larger than the room");
  if (c.boxes.has_keep_out && (c.boxes.keep_out_max.array() < c.boxes.keep_out_min.array()).any()) {
    bad("boxes.keep_out_max", "must be >= keep_out_min");
  }
  const auto& k = c.checkerboard;
  if (!k.enabled) return;
  if (k.wall != "+x" && k.wall != "-x" && k.wall != "+y" && k.wall != "-y") {
    bad("checkerboard.wall", "must be one of +x, -x, +y, -y");
  }
  if (k.squares_x < 2 || k.squares_y < 2 || k.squares_x > 100 || k.squares_y > 100) {
    bad("checkerboard.squares", "need 2..100 squares in each direction");
  }
  if (k.square_size <= 0.0) bad("checkerboard.square_size", "must be positive");
  // The board plus its one-square white margin must fit on the wall.
  const bool x_wall = k.wall[1] == 'x';
  const double along_c = x_wall ? c.room_center.y() : c.room_center.x();
  const double along_half = 0.5 * (x_wall ? c.room_size.y() : c.room_size.x());
  const double half_w = 0.5 * (k.squares_x + 2) * k.square_size;
  const double half_h = 0.5 * (k.squares_y + 2) * k.square_size;
  const double z_lo = c.room_center.z() - 0.5 * c.room_size.z();
  const double z_hi = c.room_center.z() + 0.5 * c.room_size.z();
  if (k.center.x() - half_w < along_c - along_half || k.center.x() + half_w > along_c + along_half ||
      k.center.y() - half_h < z_lo || k.center.y() + half_h > z_hi) {
    bad("checkerboard.center", "board (with its margin) does not fit on the wall");
  }
}

}  // namespace vid::sim
