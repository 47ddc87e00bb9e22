#include "sim/render/scene_config.h"

#include <yaml-cpp/yaml.h>

#include "io/errors.h"
#include "io/strict_yaml.h"

namespace vid::sim {

int room_face_index(const std::string& name) {
  static const char* const kNames[6] = {"-x", "+x", "-y", "+y", "floor", "ceiling"};
  for (int f = 0; f < 6; ++f) {
    if (name == kNames[f]) return f;
  }
  return -1;
}

SceneConfig parse_scene_config(const YAML::Node& scene_node, const std::string& file) {
  SceneConfig c;
  const io::YamlMap m = io::YamlMap::from_node(scene_node, file, "scene");
  c.room_size = m.get_vec3("room_size", c.room_size);
  c.room_center = m.get_vec3("room_center", c.room_center);
  c.texture_seed = m.get_u64("texture_seed", c.texture_seed);
  c.texels_per_m = m.get_double("texels_per_m", c.texels_per_m);
  if (m.has("boxes")) {
    const io::YamlMap b = m.get_map("boxes");
    c.boxes.count = b.get_int("count", c.boxes.count);
    c.boxes.size_min = b.get_double("size_min", c.boxes.size_min);
    c.boxes.size_max = b.get_double("size_max", c.boxes.size_max);
    if (b.has("keep_out_min") != b.has("keep_out_max")) {
      b.fail(b.has("keep_out_min") ? "keep_out_min" : "keep_out_max",
             "keep_out_min and keep_out_max must be given together");
    }
    if (b.has("keep_out_min")) {
      c.boxes.has_keep_out = true;
      c.boxes.keep_out_min = b.get_vec3("keep_out_min", c.boxes.keep_out_min);
      c.boxes.keep_out_max = b.get_vec3("keep_out_max", c.boxes.keep_out_max);
    }
    b.check_unknown();
  }
  if (m.has("checkerboard")) {
    const io::YamlMap k = m.get_map("checkerboard");
    c.checkerboard.enabled = true;
    c.checkerboard.wall = k.get_string("wall", c.checkerboard.wall);
    c.checkerboard.center = k.get_vec2("center", c.checkerboard.center);
    Eigen::Vector2d sq(c.checkerboard.squares_x, c.checkerboard.squares_y);
    sq = k.get_vec2("squares", sq);
    if (sq.x() != static_cast<int>(sq.x()) || sq.y() != static_cast<int>(sq.y())) {
      k.fail("squares", "expected two integers");
    }
    c.checkerboard.squares_x = static_cast<int>(sq.x());
    c.checkerboard.squares_y = static_cast<int>(sq.y());
    c.checkerboard.square_size = k.get_double("square_size", c.checkerboard.square_size);
    k.check_unknown();
  }
  if (m.has("low_texture")) {
    const io::YamlMap l = m.get_map("low_texture");
    if (l.has("surfaces")) c.low_texture.surfaces = l.get_strings("surfaces");
    c.low_texture.box_fraction = l.get_double("box_fraction", c.low_texture.box_fraction);
    c.low_texture.noise_amplitude = l.get_double("noise_amplitude", c.low_texture.noise_amplitude);
    l.check_unknown();
  }
  if (m.has("lighting")) {
    const io::YamlMap l = m.get_map("lighting");
    c.lighting.enabled = true;
    c.lighting.lamp_W = l.get_vec3("lamp", c.lighting.lamp_W);
    c.lighting.ambient = l.get_double("ambient", c.lighting.ambient);
    c.lighting.reach_m = l.get_double("reach_m", c.lighting.reach_m);
    l.check_unknown();
  }
  m.accept("boxes");  // read above when present; an empty value means defaults
  m.accept("checkerboard");
  m.accept("low_texture");
  m.accept("lighting");
  m.check_unknown();
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
  for (const std::string& f : c.low_texture.surfaces) {
    if (room_face_index(f) < 0) bad("low_texture.surfaces", "'" + f + "' is not one of +x, -x, +y, -y, floor, ceiling");
  }
  if (!(c.low_texture.box_fraction >= 0.0 && c.low_texture.box_fraction <= 1.0)) {
    bad("low_texture.box_fraction", "must be in [0, 1]");
  }
  if (!(c.low_texture.noise_amplitude >= 0.0 && c.low_texture.noise_amplitude <= 50.0)) {
    bad("low_texture.noise_amplitude", "must be in [0, 50]");
  }
  if (c.lighting.enabled) {
    if (!(c.lighting.ambient >= 0.0 && c.lighting.ambient <= 1.0)) bad("lighting.ambient", "must be in [0, 1]");
    if (!(c.lighting.reach_m > 0.0)) bad("lighting.reach_m", "must be > 0");
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
