#include "sim/render/renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "frontend/camera_model.h"
#include "sim/render/random.h"

namespace vid::sim {

namespace {

constexpr int kTile = 16;  // tile edge [px] for per-tile box culling
constexpr float kInfF() { return std::numeric_limits<float>::infinity(); }

/// Inverse standard-normal CDF at 65536 equally likely levels: 16 random bits -> one
/// Gaussian sample by lookup (exact to the table's quantization, far below 1 gray level).
const std::array<float, 65536>& normal_table() {
  static const std::array<float, 65536> table = [] {
    std::array<float, 65536> t{};
    for (int i = 0; i < 65536; ++i) {
      const double p = (i + 0.5) / 65536.0;
      double x = 0.0;
      for (int it = 0; it < 60; ++it) {  // Newton on Phi(x) - p
        const double cdf = 0.5 * std::erfc(-x / std::numbers::sqrt2);
        const double pdf = std::exp(-0.5 * x * x) / std::sqrt(2.0 * std::numbers::pi);
        const double step = (cdf - p) / std::max(pdf, 1e-300);
        x -= std::clamp(step, -1.0, 1.0);
        if (std::abs(step) < 1e-13) break;
      }
      t[i] = static_cast<float>(x);
    }
    return t;
  }();
  return table;
}

/// Flattened per-surface texture access for the inner loop.
struct FastSurface {
  const std::uint8_t* data;
  std::size_t step;
  float max_x, max_y;  // last valid bilinear base coordinate
  float off_u, off_v;  // texel coordinate = p[axis] * tpm - off
  int u_axis, v_axis;
  bool board;
};

}  // namespace

Renderer::Renderer(const Scene& scene, const CameraCalib& calib, int supersampling)
    : scene_(scene), camera_(CameraModel::create(calib)), ss_(supersampling),
      width_(calib.width), height_(calib.height) {
  if (ss_ < 1 || ss_ > 4) throw std::invalid_argument("Renderer: supersampling must be in 1..4");
  precompute_rays();
}

Renderer::~Renderer() = default;

void Renderer::precompute_rays() {
  const int S = ss_ * ss_;
  dirs_C_.assign(static_cast<std::size_t>(width_) * height_ * S * 3, 0.0f);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      for (int sy = 0; sy < ss_; ++sy) {
        for (int sx = 0; sx < ss_; ++sx) {
          // Pixel centres are at integer coordinates (OpenCV convention).
          const Eigen::Vector2d uv(x + (sx + 0.5) / ss_ - 0.5, y + (sy + 0.5) / ss_ - 0.5);
          Eigen::Vector3d b;
          float* d = &dirs_C_[((static_cast<std::size_t>(y) * width_ + x) * S + sy * ss_ + sx) * 3];
          if (camera_->unproject(uv, &b) && b.z() > 1e-6) {
            d[0] = static_cast<float>(b.x());
            d[1] = static_cast<float>(b.y());
            d[2] = static_cast<float>(b.z());
          }
        }
      }
    }
  }
  tiles_.clear();
  for (int ty = 0; ty < height_; ty += kTile) {
    for (int tx = 0; tx < width_; tx += kTile) {
      Tile t{tx, ty, std::min(tx + kTile, width_), std::min(ty + kTile, height_),
             Eigen::Vector3f::Zero(), 0.0f};
      for (int y = t.y0; y < t.y1; ++y) {
        for (int x = t.x0; x < t.x1; ++x) {
          for (int s = 0; s < S; ++s) {
            const float* d = &dirs_C_[((static_cast<std::size_t>(y) * width_ + x) * S + s) * 3];
            t.axis_C += Eigen::Vector3f(d[0], d[1], d[2]);
          }
        }
      }
      if (t.axis_C.norm() > 0) t.axis_C.normalize();
      float max_angle = 0.0f;
      for (int y = t.y0; y < t.y1; ++y) {
        for (int x = t.x0; x < t.x1; ++x) {
          for (int s = 0; s < S; ++s) {
            const float* d = &dirs_C_[((static_cast<std::size_t>(y) * width_ + x) * S + s) * 3];
            const Eigen::Vector3f v(d[0], d[1], d[2]);
            if (v.squaredNorm() == 0.0f) continue;
            const float c = std::clamp(t.axis_C.dot(v.normalized()), -1.0f, 1.0f);
            max_angle = std::max(max_angle, std::acos(c));
          }
        }
      }
      t.half_angle = max_angle + 1e-3f;  // margin for float rounding
      tiles_.push_back(t);
    }
  }
}

void Renderer::render_radiance_generic(const Eigen::Isometry3d& T_WC, float* out) const {
  const int S = ss_ * ss_;
  for (int i = 0; i < width_ * height_; ++i) {
    float acc = 0.0f;
    for (int s = 0; s < S; ++s) {
      const float* d = &dirs_C_[(static_cast<std::size_t>(i) * S + s) * 3];
      const Eigen::Vector3d dir_W =
          T_WC.linear() * Eigen::Vector3d(d[0], d[1], d[2]);
      if (dir_W.squaredNorm() == 0.0) continue;
      const auto hit = scene_.intersect(T_WC.translation(), dir_W);
      if (hit) acc += scene_.shade(hit->surface, hit->uv_m.x(), hit->uv_m.y());
    }
    out[i] = acc / S;
  }
}

void Renderer::render_radiance(const Eigen::Isometry3d& T_WC, float* out) const {
  if (!scene_.is_free(T_WC.translation(), 1e-6)) {
    render_radiance_generic(T_WC, out);  // camera outside the room or inside a box
    return;
  }
  const int S = ss_ * ss_;
  const float inv_S = 1.0f / S;
  const Eigen::Matrix3f R = T_WC.linear().cast<float>();
  const float o[3] = {static_cast<float>(T_WC.translation().x()),
                      static_cast<float>(T_WC.translation().y()),
                      static_cast<float>(T_WC.translation().z())};
  const Eigen::Vector3f room_lo = scene_.room_min().cast<float>();
  const Eigen::Vector3f room_hi = scene_.room_max().cast<float>();
  const float tpm = static_cast<float>(scene_.config().texels_per_m);

  const auto& surfaces = scene_.surfaces();
  std::vector<FastSurface> fs(surfaces.size());
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const Surface& s = surfaces[i];
    fs[i] = FastSurface{s.texture.ptr<std::uint8_t>(0), s.texture.step[0],
                        static_cast<float>(s.texture.cols) - 1.001f,
                        static_cast<float>(s.texture.rows) - 1.001f,
                        static_cast<float>(s.u0 * tpm + 0.5), static_cast<float>(s.v0 * tpm + 0.5),
                        s.u_axis, s.v_axis, static_cast<int>(i) == scene_.checkerboard_surface()};
  }

  // Boxes as float slabs plus their bounding spheres in the camera frame for tile culling.
  const auto& boxes = scene_.boxes();
  const int nb = static_cast<int>(boxes.size());
  std::vector<float> blo(3 * nb), bhi(3 * nb), b_ang(nb);
  std::vector<Eigen::Vector3f> b_dir(nb);
  std::vector<bool> b_always(nb);
  const Eigen::Isometry3d T_CW = T_WC.inverse();
  for (int b = 0; b < nb; ++b) {
    for (int a = 0; a < 3; ++a) {
      blo[3 * b + a] = static_cast<float>(boxes[b].min_W[a]);
      bhi[3 * b + a] = static_cast<float>(boxes[b].max_W[a]);
    }
    const Eigen::Vector3d c_C = T_CW * (0.5 * (boxes[b].min_W + boxes[b].max_W));
    const double r = 0.5 * (boxes[b].max_W - boxes[b].min_W).norm() * 1.001 + 1e-4;
    const double dist = c_C.norm();
    b_always[b] = dist <= r;
    b_dir[b] = b_always[b] ? Eigen::Vector3f::Zero().eval() : Eigen::Vector3f((c_C / dist).cast<float>());
    b_ang[b] = b_always[b] ? 0.0f : static_cast<float>(std::asin(r / dist));
  }

  std::vector<int> cand;
  cand.reserve(nb);
  for (const Tile& tile : tiles_) {
    cand.clear();
    for (int b = 0; b < nb; ++b) {
      if (b_always[b]) {
        cand.push_back(b);
        continue;
      }
      const float c = std::clamp(tile.axis_C.dot(b_dir[b]), -1.0f, 1.0f);
      if (std::acos(c) <= tile.half_angle + b_ang[b]) cand.push_back(b);
    }
    const int nc = static_cast<int>(cand.size());
    for (int y = tile.y0; y < tile.y1; ++y) {
      for (int x = tile.x0; x < tile.x1; ++x) {
        const std::size_t pix = static_cast<std::size_t>(y) * width_ + x;
        const float* dc = &dirs_C_[pix * S * 3];
        float acc = 0.0f;
        for (int s = 0; s < S; ++s, dc += 3) {
          const float d[3] = {R(0, 0) * dc[0] + R(0, 1) * dc[1] + R(0, 2) * dc[2],
                              R(1, 0) * dc[0] + R(1, 1) * dc[1] + R(1, 2) * dc[2],
                              R(2, 0) * dc[0] + R(2, 1) * dc[1] + R(2, 2) * dc[2]};
          if (dc[2] == 0.0f) continue;  // ray outside the model's valid domain: black
          const float inv[3] = {1.0f / d[0], 1.0f / d[1], 1.0f / d[2]};
          // Leaving the room: the exit plane on each axis follows the sign of the direction.
          float t = kInfF();
          int surface = 0, axis = 0;
          for (int a = 0; a < 3; ++a) {
            const bool pos = inv[a] >= 0.0f;
            const float ta = ((pos ? room_hi[a] : room_lo[a]) - o[a]) * inv[a];
            if (ta < t) {
              t = ta;
              axis = a;
              surface = 2 * a + (pos ? 1 : 0);
            }
          }
          for (int k = 0; k < nc; ++k) {
            const int b = cand[k];
            float tn = -kInfF(), tf = kInfF();
            int an = 0;
            for (int a = 0; a < 3; ++a) {
              const float t1 = (blo[3 * b + a] - o[a]) * inv[a];
              const float t2 = (bhi[3 * b + a] - o[a]) * inv[a];
              const float lo = std::min(t1, t2), hi = std::max(t1, t2);
              if (lo > tn) {
                tn = lo;
                an = a;
              }
              tf = std::min(tf, hi);
            }
            if (tn <= tf && tn > 0.0f && tn < t) {
              t = tn;
              axis = an;
              // Entering through the min face when moving in +axis.
              surface = 6 + 6 * b + 2 * an + (inv[an] >= 0.0f ? 0 : 1);
            }
          }
          (void)axis;
          const FastSurface& f = fs[surface];
          const float pu = o[f.u_axis] + t * d[f.u_axis];
          const float pv = o[f.v_axis] + t * d[f.v_axis];
          if (f.board) {
            const Surface& sf = surfaces[surface];
            acc += scene_.shade(surface, pu - sf.u0, pv - sf.v0);
            continue;
          }
          const float tx = std::clamp(pu * tpm - f.off_u, 0.0f, f.max_x);
          const float ty = std::clamp(pv * tpm - f.off_v, 0.0f, f.max_y);
          const int x0 = static_cast<int>(tx), y0 = static_cast<int>(ty);
          const float fx = tx - x0, fy = ty - y0;
          const std::uint8_t* r0 = f.data + y0 * f.step + x0;
          const std::uint8_t* r1 = r0 + f.step;
          const float top = r0[0] + fx * (static_cast<float>(r0[1]) - r0[0]);
          const float bot = r1[0] + fx * (static_cast<float>(r1[1]) - r1[0]);
          acc += top + fy * (bot - top);
        }
        out[pix] = acc * inv_S;
      }
    }
  }
}

cv::Mat Renderer::render(const Eigen::Isometry3d& T_WC, const FrameAppearance& appearance) const {
  cv::Mat img;
  render(T_WC, appearance, &img);
  return img;
}

void Renderer::render(const Eigen::Isometry3d& T_WC, const FrameAppearance& app,
                      cv::Mat* out) const {
  radiance_.resize(static_cast<std::size_t>(width_) * height_);
  render_radiance(T_WC, radiance_.data());
  out->create(height_, width_, CV_8UC1);
  const float gain = static_cast<float>(app.gain), offset = static_cast<float>(app.offset);
  const float sigma = static_cast<float>(app.noise_sigma);
  const auto& table = normal_table();
  Rng rng(app.noise_seed);
  std::uint64_t bits = 0;
  int left = 0;
  for (int y = 0; y < height_; ++y) {
    std::uint8_t* row = out->ptr<std::uint8_t>(y);
    const float* rad = &radiance_[static_cast<std::size_t>(y) * width_];
    for (int x = 0; x < width_; ++x) {
      float v = gain * rad[x] + offset;
      if (sigma > 0.0f) {
        if (left == 0) {
          bits = rng.next();
          left = 4;
        }
        v += sigma * table[bits & 0xFFFF];
        bits >>= 16;
        --left;
      }
      row[x] = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    }
  }
}

FrameAppearance appearance_for_frame(const RenderConfig& c, std::int64_t t_ns, int cam_id,
                                     std::uint64_t frame_index) {
  FrameAppearance a;
  const double t_s = static_cast<double>(t_ns) * 1e-9;
  Rng phase_rng(derive_seed(c.seed, 77));
  const double phase = phase_rng.uniform(0.0, 2.0 * std::numbers::pi);
  const double drift = c.brightness_period_s > 0.0
                           ? c.brightness_amplitude *
                                 std::sin(2.0 * std::numbers::pi * t_s / c.brightness_period_s + phase)
                           : 0.0;
  const std::uint64_t stream = frame_index * 16 + static_cast<std::uint64_t>(cam_id);
  Rng jitter_rng(derive_seed(c.seed, 1000 + 2 * stream));
  a.gain = std::max(0.05, 1.0 + drift + c.brightness_jitter * jitter_rng.normal());
  a.offset = 0.0;
  a.noise_sigma = c.noise_sigma;
  a.noise_seed = derive_seed(c.seed, 1001 + 2 * stream);
  return a;
}

}  // namespace vid::sim
