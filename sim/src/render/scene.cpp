#include "sim/render/scene.h"

#include "io/strict_yaml.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "io/errors.h"
#include "sim/render/random.h"
#include "sim/render/texture.h"

namespace vid::sim {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMinT = 1e-9;

/// Slab test of a ray against an axis-aligned box; entry/exit parameters and their axes.
struct Slab {
  double t_near = -kInf, t_far = kInf;
  int axis_near = -1, axis_far = -1;
};

bool slab(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& lo,
          const Eigen::Vector3d& hi, Slab* s) {
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < lo[a] || o[a] > hi[a]) return false;
      continue;
    }
    const double inv = 1.0 / d[a];
    double t1 = (lo[a] - o[a]) * inv, t2 = (hi[a] - o[a]) * inv;
    if (t1 > t2) std::swap(t1, t2);
    if (t1 > s->t_near) {
      s->t_near = t1;
      s->axis_near = a;
    }
    if (t2 < s->t_far) {
      s->t_far = t2;
      s->axis_far = a;
    }
  }
  return s->t_near <= s->t_far && s->t_far > kMinT;
}

bool overlaps(const Box& a, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return (a.min_W.array() < hi.array()).all() && (a.max_W.array() > lo.array()).all();
}

/// Next mip level: 2x2 box average, odd sizes padded by repeating the last row/column.
cv::Mat half_size(const cv::Mat& src) {
  const int w = (src.cols + 1) / 2, h = (src.rows + 1) / 2;
  cv::Mat dst(h, w, CV_8U);
  for (int r = 0; r < h; ++r) {
    const std::uint8_t* a = src.ptr<std::uint8_t>(std::min(2 * r, src.rows - 1));
    const std::uint8_t* b = src.ptr<std::uint8_t>(std::min(2 * r + 1, src.rows - 1));
    std::uint8_t* d = dst.ptr<std::uint8_t>(r);
    for (int c = 0; c < w; ++c) {
      const int c0 = std::min(2 * c, src.cols - 1), c1 = std::min(2 * c + 1, src.cols - 1);
      d[c] = static_cast<std::uint8_t>((a[c0] + a[c1] + b[c0] + b[c1] + 2) / 4);
    }
  }
  return dst;
}

int u_axis_of(int normal_axis) { return normal_axis == 0 ? 1 : 0; }
int v_axis_of(int normal_axis) { return normal_axis == 2 ? 1 : 2; }

}  // namespace

Scene::Scene(const SceneConfig& config) : config_(config) {
  validate_scene_config(config_, "<scene config>");
  room_min_ = config_.room_center - 0.5 * config_.room_size;
  room_max_ = config_.room_center + 0.5 * config_.room_size;
  if (config_.checkerboard.enabled) {
    const auto& k = config_.checkerboard;
    const int axis = k.wall[1] == 'x' ? 0 : 1;
    board_surface_ = 2 * axis + (k.wall[0] == '+' ? 1 : 0);
    const int ua = u_axis_of(axis), va = v_axis_of(axis);
    const double cu = k.center.x() - room_min_[ua], cv = k.center.y() - room_min_[va];
    const double hw = 0.5 * k.squares_x * k.square_size, hh = 0.5 * k.squares_y * k.square_size;
    board_rect_ = Eigen::Vector4d(cu - hw, cv - hh, cu + hw, cv + hh);
  }
  place_boxes();
  make_surfaces();
}

void Scene::place_boxes() {
  const BoxesConfig& bc = config_.boxes;
  Eigen::Vector3d ko_min, ko_max;
  if (bc.has_keep_out) {
    ko_min = bc.keep_out_min;
    ko_max = bc.keep_out_max;
  } else {  // central 60 % of the room in x and y, all heights
    ko_min = config_.room_center - 0.3 * config_.room_size;
    ko_max = config_.room_center + 0.3 * config_.room_size;
    ko_min.z() = -kInf;
    ko_max.z() = kInf;
  }
  // Keep the space in front of the checkerboard clear so the board stays visible.
  Eigen::Vector3d bk_min = Eigen::Vector3d::Constant(kInf), bk_max = -bk_min;
  if (board_surface_ >= 0) {
    const int axis = board_surface_ / 2, ua = u_axis_of(axis), va = v_axis_of(axis);
    const double margin = 0.5;
    bk_min[ua] = room_min_[ua] + board_rect_[0] - margin;
    bk_max[ua] = room_min_[ua] + board_rect_[2] + margin;
    bk_min[va] = room_min_[va] + board_rect_[1] - margin;
    bk_max[va] = room_min_[va] + board_rect_[3] + margin;
    const bool max_side = board_surface_ % 2 == 1;
    bk_min[axis] = max_side ? room_max_[axis] - 3.0 : room_min_[axis];
    bk_max[axis] = max_side ? room_max_[axis] : room_min_[axis] + 3.0;
  }
  Rng rng(derive_seed(config_.texture_seed, 1000));
  for (int i = 0; i < bc.count; ++i) {
    for (int attempt = 0; attempt < 200; ++attempt) {
      Eigen::Vector3d size;
      for (int a = 0; a < 3; ++a) size[a] = rng.uniform(bc.size_min, bc.size_max);
      size = size.cwiseMin(config_.room_size);
      Box b;
      for (int a = 0; a < 3; ++a) b.min_W[a] = rng.uniform(room_min_[a], room_max_[a] - size[a]);
      if (rng.uniform() < 0.65) {
        b.min_W.z() = room_min_.z();  // standing on the floor
      } else {  // fixed to a wall, like a cabinet or a shelf
        const int wall = rng.uniform_int(4), a = wall / 2;
        b.min_W[a] = (wall % 2 == 1) ? room_max_[a] - size[a] : room_min_[a];
      }
      b.max_W = b.min_W + size;
      if (overlaps(b, ko_min, ko_max) || overlaps(b, bk_min, bk_max)) continue;
      const Eigen::Vector3d gap = Eigen::Vector3d::Constant(0.05);
      const bool clash = std::any_of(boxes_.begin(), boxes_.end(), [&](const Box& o) {
        return overlaps(b, o.min_W - gap, o.max_W + gap);
      });
      if (clash) continue;
      boxes_.push_back(b);
      break;
    }
  }
}

void Scene::make_surfaces() {
  const double tpm = config_.texels_per_m;
  auto add = [&](int axis, double plane, double sign, const Eigen::Vector3d& lo,
                 const Eigen::Vector3d& hi, const TextureStyle& style, std::uint64_t stream) {
    Surface s;
    s.normal_axis = axis;
    s.u_axis = u_axis_of(axis);
    s.v_axis = v_axis_of(axis);
    s.plane = plane;
    s.normal_sign = sign;
    s.u0 = lo[s.u_axis];
    s.v0 = lo[s.v_axis];
    s.u_len = hi[s.u_axis] - lo[s.u_axis];
    s.v_len = hi[s.v_axis] - lo[s.v_axis];
    s.texture = make_surface_texture(s.u_len, s.v_len, tpm,
                                     derive_seed(config_.texture_seed, stream), style);
    if (config_.lighting.enabled) apply_lighting(&s);
    s.mips.push_back(s.texture);
    while (s.mips.back().cols > 4 && s.mips.back().rows > 4) s.mips.push_back(half_size(s.mips.back()));
    surfaces_.push_back(std::move(s));
  };
  Rng style_rng(derive_seed(config_.texture_seed, 2000));
  const LowTextureConfig& low = config_.low_texture;
  auto make_plain = [&](TextureStyle* st) {  // painted: no shapes, weak smooth shading only
    st->shape_density = 0.0;
    st->noise_amplitude = low.noise_amplitude;
  };
  for (int f = 0; f < 6; ++f) {
    const int axis = f / 2;
    const bool max_side = f % 2 == 1;
    TextureStyle st;
    st.mean_level = axis == 2 ? (max_side ? 150.0 : 100.0) : style_rng.uniform(105.0, 150.0);
    st.level_spread = style_rng.uniform(80.0, 105.0);
    for (const std::string& name : low.surfaces) {
      if (room_face_index(name) == f) make_plain(&st);
    }
    add(axis, max_side ? room_max_[axis] : room_min_[axis], max_side ? -1.0 : 1.0, room_min_,
        room_max_, st, static_cast<std::uint64_t>(f));
  }
  Rng plain_rng(derive_seed(config_.texture_seed, 3000));  // own stream: styles unchanged
  for (std::size_t b = 0; b < boxes_.size(); ++b) {
    const double mean = style_rng.uniform(70.0, 180.0);
    const bool plain_box = low.box_fraction > 0.0 && plain_rng.uniform() < low.box_fraction;
    for (int f = 0; f < 6; ++f) {
      const int axis = f / 2;
      const bool max_side = f % 2 == 1;
      TextureStyle st;
      // Faces of one box differ a little in brightness, like shading under room light.
      st.mean_level = std::clamp(mean + (axis == 2 ? 20.0 : (axis == 0 ? 0.0 : -15.0)), 70.0, 180.0);
      st.level_spread = style_rng.uniform(80.0, 105.0);
      if (plain_box) make_plain(&st);
      add(axis, max_side ? boxes_[b].max_W[axis] : boxes_[b].min_W[axis], max_side ? 1.0 : -1.0,
          boxes_[b].min_W, boxes_[b].max_W, st, 6 + 6 * b + static_cast<std::uint64_t>(f));
    }
  }
}

void Scene::apply_lighting(Surface* s) const {
  // The lamp term varies slowly: evaluate it every kStep texels and interpolate.
  constexpr int kStep = 8;
  const LightingConfig& l = config_.lighting;
  const double tpm = config_.texels_per_m;
  const int gw = s->texture.cols / kStep + 2, gh = s->texture.rows / kStep + 2;
  cv::Mat shade(gh, gw, CV_32F);
  for (int r = 0; r < gh; ++r) {
    for (int c = 0; c < gw; ++c) {
      Eigen::Vector3d p_W;
      p_W[s->normal_axis] = s->plane;
      p_W[s->u_axis] = s->u0 + c * kStep / tpm;
      p_W[s->v_axis] = s->v0 + r * kStep / tpm;
      const Eigen::Vector3d to_lamp = l.lamp_W - p_W;
      const double d = std::max(to_lamp.norm(), 1e-3);
      const double cos_inc = std::max(0.0, s->normal_sign * to_lamp[s->normal_axis] / d);
      const double lamp = std::min(1.0, cos_inc * (l.reach_m / d) * (l.reach_m / d));
      shade.at<float>(r, c) = static_cast<float>(l.ambient + (1.0 - l.ambient) * lamp);
    }
  }
  cv::Mat up;
  cv::resize(shade, up, cv::Size(gw * kStep, gh * kStep), 0, 0, cv::INTER_LINEAR);
  cv::Mat tex;
  s->texture.convertTo(tex, CV_32F);
  cv::multiply(tex, up(cv::Rect(0, 0, tex.cols, tex.rows)), tex);
  tex.convertTo(s->texture, CV_8U);
}

std::optional<SceneHit> Scene::intersect(const Eigen::Vector3d& o, const Eigen::Vector3d& d) const {
  double best_t = kInf;
  int best_surface = -1, best_axis = -1;
  auto consider = [&](const Slab& s, int surface_base, bool two_sided_inside) {
    double t;
    int axis;
    bool entering;
    if (s.t_near > kMinT) {
      t = s.t_near, axis = s.axis_near, entering = true;
    } else if (two_sided_inside) {
      t = s.t_far, axis = s.axis_far, entering = false;
    } else {
      return;
    }
    if (axis < 0 || t >= best_t) return;
    // Entering through the min side when moving +, leaving through the max side when moving +.
    const bool max_side = entering ? d[axis] < 0.0 : d[axis] > 0.0;
    best_t = t;
    best_axis = axis;
    best_surface = surface_base + 2 * axis + (max_side ? 1 : 0);
  };
  Slab room;
  if (slab(o, d, room_min_, room_max_, &room)) consider(room, 0, true);
  for (std::size_t b = 0; b < boxes_.size(); ++b) {
    Slab s;
    if (slab(o, d, boxes_[b].min_W, boxes_[b].max_W, &s)) {
      consider(s, 6 + 6 * static_cast<int>(b), true);
    }
  }
  if (best_surface < 0) return std::nullopt;
  const Surface& surf = surfaces_[best_surface];
  SceneHit h;
  h.t = best_t;
  h.surface = best_surface;
  h.p_W = o + best_t * d;
  h.p_W[best_axis] = surf.plane;  // exactly on the surface
  h.normal_W = Eigen::Vector3d::Zero();
  h.normal_W[best_axis] = d[best_axis] > 0.0 ? -1.0 : 1.0;
  h.uv_m = Eigen::Vector2d(h.p_W[surf.u_axis] - surf.u0, h.p_W[surf.v_axis] - surf.v0);
  return h;
}

std::optional<Eigen::Vector3d> Scene::raycast(const Eigen::Vector3d& origin_W,
                                              const Eigen::Vector3d& dir_W) const {
  const auto h = intersect(origin_W, dir_W);
  if (!h) return std::nullopt;
  return h->p_W;
}

namespace {
/// Integral of the +-1 square wave of half-period sq (+1 on [0, sq)) from 0 to x.
double square_wave_integral(double x, double sq) {
  const double p = x - 2.0 * sq * std::floor(x / (2.0 * sq));
  return p <= sq ? p : 2.0 * sq - p;
}
/// Mean of that square wave over [x - w/2, x + w/2] (w > 0), or its value (w = 0).
double filtered_square_wave(double x, double sq, double w) {
  if (w <= 0.0) return (x - 2.0 * sq * std::floor(x / (2.0 * sq))) < sq ? 1.0 : -1.0;
  return (square_wave_integral(x + 0.5 * w, sq) - square_wave_integral(x - 0.5 * w, sq)) / w;
}
}  // namespace

float Scene::board_value(double u, double v, double footprint_m) const {
  const double sq = config_.checkerboard.square_size;
  const double du = u - board_rect_[0], dv = v - board_rect_[1];
  const double w = std::min(footprint_m, 0.5 * sq);
  // Outside the squares (plus half a filter width) is the white margin.
  if (du < -0.5 * w || dv < -0.5 * w || u > board_rect_[2] + 0.5 * w || v > board_rect_[3] + 0.5 * w) {
    return kBoardLight;
  }
  // Dark where both square waves agree: value = light + (dark - light) (1 + s_u s_v) / 2.
  // The 2-D box filter of this separable product is the product of the 1-D filtered waves.
  double su = filtered_square_wave(du, sq, w), sv = filtered_square_wave(dv, sq, w);
  // Blend to white across the outer board edge (the filter sees the margin there).
  auto edge = [&](double x, double len) {
    const double in = std::clamp((x + 0.5 * w) / std::max(w, 1e-12), 0.0, 1.0) *
                      std::clamp((len - x + 0.5 * w) / std::max(w, 1e-12), 0.0, 1.0);
    return w > 0.0 ? in : 1.0;
  };
  const double inside = edge(du, board_rect_[2] - board_rect_[0]) * edge(dv, board_rect_[3] - board_rect_[1]);
  const double dark_fraction = inside * 0.5 * (1.0 + su * sv);
  return static_cast<float>(kBoardLight + (kBoardDark - kBoardLight) * dark_fraction);
}

float Scene::shade(int surface, double u, double v, double footprint_m) const {
  if (surface == board_surface_) {
    const double m = config_.checkerboard.square_size;
    if (u >= board_rect_[0] - m && u <= board_rect_[2] + m && v >= board_rect_[1] - m &&
        v <= board_rect_[3] + m) {
      return board_value(u, v, footprint_m);
    }
  }
  const cv::Mat& tex = surfaces_[surface].texture;
  const double tpm = config_.texels_per_m;
  const double x = std::clamp(u * tpm - 0.5, 0.0, tex.cols - 1.001);
  const double y = std::clamp(v * tpm - 0.5, 0.0, tex.rows - 1.001);
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const double fx = x - x0, fy = y - y0;
  const std::uint8_t* r0 = tex.ptr<std::uint8_t>(y0);
  const std::uint8_t* r1 = tex.ptr<std::uint8_t>(y0 + 1);
  const double top = r0[x0] + fx * (r0[x0 + 1] - r0[x0]);
  const double bot = r1[x0] + fx * (r1[x0 + 1] - r1[x0]);
  return static_cast<float>(top + fy * (bot - top));
}

bool Scene::is_free(const Eigen::Vector3d& p, double margin) const {
  const Eigen::Vector3d m = Eigen::Vector3d::Constant(margin);
  if ((p.array() < (room_min_ + m).array()).any() || (p.array() > (room_max_ - m).array()).any()) {
    return false;
  }
  for (const Box& b : boxes_) {
    if ((p.array() > (b.min_W - m).array()).all() && (p.array() < (b.max_W + m).array()).all()) {
      return false;
    }
  }
  return true;
}

std::vector<Eigen::Vector3d> Scene::checkerboard_corners_W() const {
  std::vector<Eigen::Vector3d> out;
  if (board_surface_ < 0) return out;
  const Surface& s = surfaces_[board_surface_];
  const auto& k = config_.checkerboard;
  for (int r = 1; r < k.squares_y; ++r) {
    for (int c = 1; c < k.squares_x; ++c) {
      Eigen::Vector3d p;
      p[s.normal_axis] = s.plane;
      p[s.u_axis] = s.u0 + board_rect_[0] + c * k.square_size;
      p[s.v_axis] = s.v0 + board_rect_[3] - r * k.square_size;
      out.push_back(p);
    }
  }
  return out;
}

SceneConfig scene_config_from_scenario_file(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw io::ConfigError(path + ": cannot open scenario file");
  }
  const YAML::Node root = io::YamlMap::parse_file(path);
  if (root && root.IsMap() && root["scene"]) return parse_scene_config(root["scene"], path);
  SceneConfig c;
  validate_scene_config(c, path);
  return c;
}

Scene scene_from_scenario_file(const std::string& path) {
  return Scene(scene_config_from_scenario_file(path));
}

}  // namespace vid::sim
