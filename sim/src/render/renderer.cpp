#include "sim/render/renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "frontend/camera_model.h"
#include "render_internal.h"
#include "sim/render/random.h"

namespace vid::sim {

namespace {

constexpr int kTile = Renderer::kTileSize;
constexpr int kMaxCandidates = 32;  // boxes per tile kept on the stack (more: a heap list)
constexpr float kInfF() { return std::numeric_limits<float>::infinity(); }

/// Flattened per-surface texture access for the inner loop.
struct FastLevel {
  const std::uint8_t* data;
  std::size_t step;
  float max_x, max_y;  // last valid bilinear base coordinate
  float scale;         // texels per metre at this level
  float off_u, off_v;  // texel coordinate = p[axis] * scale - off
};
}  // namespace

struct Renderer::FastSurface {
  int u_axis, v_axis, normal_axis, n_levels;
  bool board;
  float board_lo_u, board_lo_v, board_hi_u, board_hi_v;  // board + margin, W coordinates
  FastLevel level[24];
};

namespace {

/// floor(log2(x)) / 2 for x >= 1 from the float exponent (0 for x < 4).
inline int half_log2_floor(float x) {
  std::uint32_t bits;
  std::memcpy(&bits, &x, sizeof(bits));
  const int e = static_cast<int>((bits >> 23) & 0xFF) - 127;
  return e > 0 ? e >> 1 : 0;
}

}  // namespace

Renderer::Renderer(const Scene& scene, const CameraCalib& calib, int supersampling)
    : scene_(scene), camera_(CameraModel::create(calib)), ss_(supersampling),
      width_(calib.width), height_(calib.height) {
  if (ss_ < 1 || ss_ > 4) throw std::invalid_argument("Renderer: supersampling must be in 1..4");
  precompute_rays();
  build_surface_table();
}

Renderer::~Renderer() = default;

void Renderer::precompute_rays() {
  chunks_.clear();
  tiles_.clear();
  for (int ty = 0; ty < height_; ty += kTile) {
    for (int tx = 0; tx < width_; tx += kTile) {
      Tile tile{chunks_.size(), chunks_.size(), {}, Eigen::Vector3f::Zero(), 0.0f};
      std::vector<Eigen::Vector3f> rays;
      int lane = 4;
      const int y_end = std::min(ty + kTile, height_);
      for (int y = ty; y < y_end; ++y) {
        // First chunk of pixel row y: the next one created (a chunk that straddles two rows,
        // possible only for odd tile widths at odd supersampling, counts for its first row).
        tile.row_begin[y - ty] = static_cast<std::uint32_t>(chunks_.size());
        for (int x = tx; x < std::min(tx + kTile, width_); ++x) {
          for (int sy = 0; sy < ss_; ++sy) {
            for (int sx = 0; sx < ss_; ++sx) {
              if (lane == 4) {
                chunks_.push_back(Chunk{{0, 0, 0, 0}, {0, 0, 0, 0}, {1, 1, 1, 1}, {-1, -1, -1, -1}});
                lane = 0;
              }
              // Pixel centres are at integer coordinates (OpenCV convention).
              const Eigen::Vector2d uv(x + (sx + 0.5) / ss_ - 0.5, y + (sy + 0.5) / ss_ - 0.5);
              Eigen::Vector3d b;
              Chunk& c = chunks_.back();
              if (camera_->unproject(uv, &b) && b.z() > 1e-6) {
                c.x[lane] = static_cast<float>(b.x());
                c.y[lane] = static_cast<float>(b.y());
                c.z[lane] = static_cast<float>(b.z());
                c.pix[lane] = y * width_ + x;
                rays.push_back(b.cast<float>());
                tile.axis_C += rays.back();
              }
              ++lane;
            }
          }
        }
      }
      tile.chunk_end = chunks_.size();
      for (int r = y_end - ty; r <= kTile; ++r) tile.row_begin[r] = static_cast<std::uint32_t>(tile.chunk_end);
      if (tile.axis_C.norm() > 0) tile.axis_C.normalize();
      float max_angle = 0.0f;
      for (const auto& r : rays) {
        max_angle = std::max(max_angle, std::acos(std::clamp(tile.axis_C.dot(r), -1.0f, 1.0f)));
      }
      tile.half_angle = max_angle + 1e-3f;  // margin for float rounding
      tiles_.push_back(tile);
    }
  }
}

void Renderer::trace_generic(const Eigen::Isometry3d& T_WC, std::size_t chunk_begin,
                             std::size_t chunk_end, float* out) const {
  const float inv_S = 1.0f / static_cast<float>(ss_ * ss_);
  const double angle_per_sample =
      1.0 / (0.5 * (camera_->calib().intrinsics[0] + camera_->calib().intrinsics[1]) * ss_);
  for (std::size_t ci = chunk_begin; ci < chunk_end; ++ci) {
    const Chunk& c = chunks_[ci];
    for (int l = 0; l < 4; ++l) {
      if (c.pix[l] < 0) continue;
      const Eigen::Vector3d dir_W = T_WC.linear() * Eigen::Vector3d(c.x[l], c.y[l], c.z[l]);
      const auto hit = scene_.intersect(T_WC.translation(), dir_W);
      if (!hit) continue;
      const double cos_inc = std::max(1e-3, std::abs(hit->normal_W.dot(dir_W.normalized())));
      const double footprint = hit->t * dir_W.norm() * angle_per_sample / std::sqrt(cos_inc);
      out[c.pix[l]] += inv_S * scene_.shade(hit->surface, hit->uv_m.x(), hit->uv_m.y(), footprint);
    }
  }
}

namespace {

// Four lanes of floats / ints (GCC/Clang vector extensions; SSE2 or NEON code).
typedef float v4f __attribute__((vector_size(16)));
typedef std::int32_t v4i __attribute__((vector_size(16)));

inline v4f vmin(v4f a, v4f b) { return a < b ? a : b; }
inline v4f vmax(v4f a, v4f b) { return a > b ? a : b; }
inline v4f splat(float x) { return v4f{x, x, x, x}; }
inline v4i splat_i(std::int32_t x) { return v4i{x, x, x, x}; }

}  // namespace

void Renderer::build_surface_table() {
  const auto& surfaces = scene_.surfaces();
  fs_.assign(surfaces.size(), FastSurface{});
  const Eigen::Vector4d board = scene_.checkerboard_rect_uv();
  const double board_margin = scene_.config().checkerboard.square_size;
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const Surface& s = surfaces[i];
    FastSurface& f = fs_[i];
    f.u_axis = s.u_axis;
    f.v_axis = s.v_axis;
    f.normal_axis = s.normal_axis;
    f.n_levels = std::min<int>(static_cast<int>(s.mips.size()), 24);
    for (int L = 0; L < f.n_levels; ++L) {
      const cv::Mat& m = s.mips[L];
      if (static_cast<double>(m.rows) * static_cast<double>(m.step[0]) >= 2147483647.0) {
        throw std::invalid_argument("Renderer: texture level too large (2 GB or more)");
      }
      const double scale = scene_.config().texels_per_m / (1 << L);
      f.level[L] = FastLevel{m.ptr<std::uint8_t>(0), m.step[0], static_cast<float>(m.cols) - 1.001f,
                             static_cast<float>(m.rows) - 1.001f, static_cast<float>(scale),
                             static_cast<float>(s.u0 * scale + 0.5),
                             static_cast<float>(s.v0 * scale + 0.5)};
    }
    f.board = static_cast<int>(i) == scene_.checkerboard_surface();
    f.board_lo_u = static_cast<float>(s.u0 + board[0] - board_margin);
    f.board_lo_v = static_cast<float>(s.v0 + board[1] - board_margin);
    f.board_hi_u = static_cast<float>(s.u0 + board[2] + board_margin);
    f.board_hi_v = static_cast<float>(s.v0 + board[3] + board_margin);
  }
  for (const Box& b : scene_.boxes()) {
    box_lo_.push_back(b.min_W.cast<float>());
    box_hi_.push_back(b.max_W.cast<float>());
  }
}

Renderer::PoseSetup Renderer::setup_pose(const Eigen::Isometry3d& T_WC) const {
  PoseSetup p;
  p.T_WC = T_WC;
  p.free = scene_.is_free(T_WC.translation(), 1e-6);
  p.R = T_WC.linear().cast<float>();
  p.o = T_WC.translation().cast<float>();
  // Bounding spheres of the boxes in the camera frame, for culling them per tile.
  const auto& boxes = scene_.boxes();
  const int nb = static_cast<int>(boxes.size());
  p.b_ang.resize(nb);
  p.b_dir.resize(nb);
  p.b_always.resize(nb);
  const Eigen::Isometry3d T_CW = T_WC.inverse();
  for (int b = 0; b < nb; ++b) {
    const Eigen::Vector3d c_C = T_CW * (0.5 * (boxes[b].min_W + boxes[b].max_W));
    const double r = 0.5 * (boxes[b].max_W - boxes[b].min_W).norm() * 1.001 + 1e-4;
    const double dist = c_C.norm();
    p.b_always[b] = dist <= r;
    p.b_dir[b] = p.b_always[b] ? Eigen::Vector3f::Zero().eval() : Eigen::Vector3f((c_C / dist).cast<float>());
    p.b_ang[b] = p.b_always[b] ? 0.0f : static_cast<float>(std::asin(r / dist));
  }
  return p;
}

void Renderer::render_radiance(const Eigen::Isometry3d& T_WC, float* out) const {
  std::fill(out, out + static_cast<std::size_t>(width_) * height_, 0.0f);
  const PoseSetup p = setup_pose(T_WC);
  for (const Tile& tile : tiles_) trace(p, tile, tile.chunk_begin, tile.chunk_end, out);
}

void Renderer::render_radiance_rows(const PoseAtTime& T_WC_at, double t0_s, double line_delay_s,
                                    float* out) const {
  std::fill(out, out + static_cast<std::size_t>(width_) * height_, 0.0f);
  const int tiles_x = (width_ + kTileSize - 1) / kTileSize;
  for (int y = 0; y < height_; ++y) {
    const PoseSetup p = setup_pose(T_WC_at(t0_s + y * line_delay_s));
    const int ty = y / kTileSize, r = y - ty * kTileSize;
    for (int tx = 0; tx < tiles_x; ++tx) {
      const Tile& tile = tiles_[static_cast<std::size_t>(ty) * tiles_x + tx];
      trace(p, tile, tile.row_begin[r], tile.row_begin[r + 1], out);
    }
  }
}

void Renderer::trace(const PoseSetup& p, const Tile& tile, std::size_t chunk_begin,
                     std::size_t chunk_end, float* out) const {
  if (!p.free) {
    trace_generic(p.T_WC, chunk_begin, chunk_end, out);  // camera outside the room or in a box
    return;
  }
  const float inv_S = 1.0f / static_cast<float>(ss_ * ss_);
  const Eigen::Matrix3f& R = p.R;
  const Eigen::Vector3f& o = p.o;
  const Eigen::Vector3f room_lo = scene_.room_min().cast<float>();
  const Eigen::Vector3f room_hi = scene_.room_max().cast<float>();
  const double tpm = scene_.config().texels_per_m;
  const auto& surfaces = scene_.surfaces();
  const std::vector<FastSurface>& fs = fs_;
  // Texels (level 0) per sample per metre of distance: one sample spans 1/(f ss) rad.
  const float fp_per_m = static_cast<float>(
      tpm / (0.5 * (camera_->calib().intrinsics[0] + camera_->calib().intrinsics[1]) * ss_));
  const float fp2_per_m2 = fp_per_m * fp_per_m;
  const float angle_per_sample = static_cast<float>(fp_per_m / tpm);
  const auto& b_lo = box_lo_;
  const auto& b_hi = box_hi_;
  const int nb = static_cast<int>(b_lo.size());

  const v4f zero = splat(0.0f);
  int cand[kMaxCandidates];
  int n_cand = 0;
  std::vector<int> cand_more;  // only for scenes with more boxes in one tile than kMaxCandidates
  for (int b = 0; b < nb; ++b) {
    const float c = std::clamp(tile.axis_C.dot(p.b_dir[b]), -1.0f, 1.0f);
    if (p.b_always[b] || std::acos(c) <= tile.half_angle + p.b_ang[b]) {
      if (n_cand < kMaxCandidates) {
        cand[n_cand++] = b;
      } else {
        if (cand_more.empty()) cand_more.assign(cand, cand + n_cand);
        cand_more.push_back(b);
      }
    }
  }
  const int* cand_begin = cand_more.empty() ? cand : cand_more.data();
  const int* cand_end = cand_more.empty() ? cand + n_cand : cand_more.data() + cand_more.size();
  // Slab planes relative to the camera centre, once per tile instead of per chunk (the same
  // float subtractions, so the same results).
  struct Slabs {
    float lo[3], hi[3];
  };
  Slabs cand_slabs[kMaxCandidates];
  std::vector<Slabs> cand_slabs_more;
  Slabs* slabs = cand_slabs;
  if (cand_end - cand_begin > kMaxCandidates) {
    cand_slabs_more.resize(static_cast<std::size_t>(cand_end - cand_begin));
    slabs = cand_slabs_more.data();
  }
  for (const int* bp = cand_begin; bp != cand_end; ++bp) {
    for (int a = 0; a < 3; ++a) {
      slabs[bp - cand_begin].lo[a] = b_lo[*bp][a] - o[a];
      slabs[bp - cand_begin].hi[a] = b_hi[*bp][a] - o[a];
    }
  }
  const Slabs* slabs_end = slabs + (cand_end - cand_begin);
  float room_lo_o[3], room_hi_o[3];
  for (int a = 0; a < 3; ++a) {
    room_lo_o[a] = room_lo[a] - o[a];
    room_hi_o[a] = room_hi[a] - o[a];
  }
  {
    for (std::size_t ci = chunk_begin; ci < chunk_end; ++ci) {
      const Chunk& ch = chunks_[ci];
      v4f cx, cy, cz;
      std::memcpy(&cx, ch.x, sizeof(cx));
      std::memcpy(&cy, ch.y, sizeof(cy));
      std::memcpy(&cz, ch.z, sizeof(cz));
      const v4f d[3] = {R(0, 0) * cx + R(0, 1) * cy + R(0, 2) * cz,
                        R(1, 0) * cx + R(1, 1) * cy + R(1, 2) * cz,
                        R(2, 0) * cx + R(2, 1) * cy + R(2, 2) * cz};
      const v4f inv[3] = {1.0f / d[0], 1.0f / d[1], 1.0f / d[2]};
      // Leaving the room: on each axis the exit wall follows the sign of the direction.
      v4f t = splat(std::numeric_limits<float>::infinity());
      v4i surface = splat_i(0);
      for (int a = 0; a < 3; ++a) {
        const v4i pos = inv[a] >= zero;
        const v4f ta = (pos ? splat(room_hi_o[a]) : splat(room_lo_o[a])) * inv[a];
        const v4i closer = ta < t;
        t = closer ? ta : t;
        surface = closer ? (pos ? splat_i(2 * a + 1) : splat_i(2 * a)) : surface;
      }
      for (const Slabs* sb = slabs; sb != slabs_end; ++sb) {
        const int b = cand_begin[sb - slabs];
        v4f tn = splat(-std::numeric_limits<float>::infinity());
        v4f tf = splat(std::numeric_limits<float>::infinity());
        v4i face = splat_i(0);
        for (int a = 0; a < 3; ++a) {
          const v4f t1 = splat(sb->lo[a]) * inv[a];
          const v4f t2 = splat(sb->hi[a]) * inv[a];
          const v4f lo = vmin(t1, t2);
          const v4i later = lo > tn;
          tn = later ? lo : tn;
          // Entering through the min face when moving in +axis.
          face = later ? (inv[a] >= zero ? splat_i(2 * a) : splat_i(2 * a + 1)) : face;
          tf = vmin(tf, vmax(t1, t2));
        }
        const v4i hit = (tn <= tf) & (tn > zero) & (tn < t);
        t = hit ? tn : t;
        surface = hit ? face + splat_i(6 + 6 * b) : surface;
      }
      // Common case: all four rays on one textured surface: vector math, one mip level for the
      // chunk (its rays are within a pixel or two of each other).
      const int s0 = surface[0];
      const FastSurface& f0 = fs[s0];
      bool fast = s0 == surface[1] && s0 == surface[2] && s0 == surface[3] && ch.pix[0] >= 0 &&
                  ch.pix[3] >= 0;
      v4f pu, pv;
      int level = 0;
      if (fast) {
        pu = splat(o[f0.u_axis]) + t * d[f0.u_axis];
        pv = splat(o[f0.v_axis]) + t * d[f0.v_axis];
        const float fp2 = t[0] * t[0] * fp2_per_m2 * std::abs(inv[f0.normal_axis][0]);
        level = std::min(half_log2_floor(fp2), f0.n_levels - 1);
        if (f0.board) {
          // The board's wall: here only when no lane is on the board (+ margin) and every lane
          // would pick lane 0's mip level, i.e. when the per-lane code below would do exactly
          // these float operations; the lanes are then added to the pixel one by one as there.
          const v4i on = (pu >= splat(f0.board_lo_u)) & (pu <= splat(f0.board_hi_u)) &
                         (pv >= splat(f0.board_lo_v)) & (pv <= splat(f0.board_hi_v));
          fast = ch.pix[1] >= 0 && ch.pix[2] >= 0 && (on[0] | on[1] | on[2] | on[3]) == 0;
          if (fast) {
            v4f abs_inv_n;
            v4i bits;
            std::memcpy(&bits, &inv[f0.normal_axis], sizeof(bits));
            bits &= 0x7FFFFFFF;  // fabs
            std::memcpy(&abs_inv_n, &bits, sizeof(abs_inv_n));
            const v4f fp2_l = t * t * fp2_per_m2 * abs_inv_n;
            for (int l = 1; l < 4; ++l) {
              fast = fast && std::min(half_log2_floor(fp2_l[l]), f0.n_levels - 1) == level;
            }
          }
        }
      }
      if (fast) {
        const FastLevel& lv = f0.level[level];
        const v4f tx = vmin(vmax(pu * lv.scale - lv.off_u, zero), splat(lv.max_x));
        const v4f ty = vmin(vmax(pv * lv.scale - lv.off_v, zero), splat(lv.max_y));
        const v4i x0 = __builtin_convertvector(tx, v4i), y0 = __builtin_convertvector(ty, v4i);
        const v4f fx = tx - __builtin_convertvector(x0, v4f);
        const v4f fy = ty - __builtin_convertvector(y0, v4f);
        // Per lane the two texels of the top and of the bottom row as one 16-bit word each
        // (a single load), then byte unpacking and int->float conversion four lanes at a
        // time: much cheaper than 16 scalar conversions inserted into vectors one by one.
        // Texel offsets y0 * step + x0 of the four lanes with two vector instructions (they fit
        // in 32 bits: Renderer::build_surface_table checks the level sizes).
        const v4i off = y0 * splat_i(static_cast<std::int32_t>(lv.step)) + x0;
        std::uint16_t tw[4], bw[4];
        for (int l = 0; l < 4; ++l) {
          const std::uint8_t* r0 = lv.data + static_cast<std::uint32_t>(off[l]);
          const std::uint8_t* r1 = r0 + lv.step;
          tw[l] = static_cast<std::uint16_t>(r0[0] | (r0[1] << 8));
          bw[l] = static_cast<std::uint16_t>(r1[0] | (r1[1] << 8));
        }
        const v4i tv{tw[0], tw[1], tw[2], tw[3]};
        const v4i bv{bw[0], bw[1], bw[2], bw[3]};
        const v4f a = __builtin_convertvector(tv & 0xFF, v4f);
        const v4f b = __builtin_convertvector(tv >> 8, v4f);
        const v4f c = __builtin_convertvector(bv & 0xFF, v4f);
        const v4f e = __builtin_convertvector(bv >> 8, v4f);
        const v4f top = a + fx * (b - a), bot = c + fx * (e - c);
        const v4f value = (top + fy * (bot - top)) * inv_S;
        if (!f0.board && ch.pix[0] == ch.pix[3]) {  // one pixel (2x2 supersampling): one store
          out[ch.pix[0]] += (value[0] + value[1]) + (value[2] + value[3]);
        } else {
          for (int l = 0; l < 4; ++l) out[ch.pix[l]] += value[l];
        }
        continue;
      }
      // Shade each lane: bilinear lookup in the mip level matching the sample footprint.
      for (int l = 0; l < 4; ++l) {
        const int pix = ch.pix[l];
        if (pix < 0) continue;
        const FastSurface& f = fs[surface[l]];
        const float tl = t[l];
        const float pu = o[f.u_axis] + tl * d[f.u_axis][l];
        const float pv = o[f.v_axis] + tl * d[f.v_axis][l];
        float value;
        if (f.board && pu >= f.board_lo_u && pu <= f.board_hi_u && pv >= f.board_lo_v &&
            pv <= f.board_hi_v) {
          const Surface& sf = surfaces[surface[l]];
          // Board pattern box-filtered over the sample spacing (obliquity as sqrt(1/cos)).
          const float footprint =
              tl * angle_per_sample * std::sqrt(std::abs(inv[f.normal_axis][l]));
          value = scene_.shade(surface[l], pu - sf.u0, pv - sf.v0, footprint);
        } else {
          // Footprint^2 in level-0 texels: distance^2 and obliquity 1/cos (= |1/d_n|).
          const float fp2 = tl * tl * fp2_per_m2 * std::abs(inv[f.normal_axis][l]);
          const FastLevel& lv = f.level[std::min(half_log2_floor(fp2), f.n_levels - 1)];
          const float tx = std::clamp(pu * lv.scale - lv.off_u, 0.0f, lv.max_x);
          const float ty = std::clamp(pv * lv.scale - lv.off_v, 0.0f, lv.max_y);
          const int x0 = static_cast<int>(tx), y0 = static_cast<int>(ty);
          const float fx = tx - x0, fy = ty - y0;
          const std::uint8_t* r0 = lv.data + y0 * lv.step + x0;
          const std::uint8_t* r1 = r0 + lv.step;
          const float top = r0[0] + fx * (static_cast<float>(r0[1]) - r0[0]);
          const float bot = r1[0] + fx * (static_cast<float>(r1[1]) - r1[0]);
          value = top + fy * (bot - top);
        }
        out[pix] += value * inv_S;
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
  expose(app, out);
}

void Renderer::expose(const FrameAppearance& app, cv::Mat* out) const {
  if (app.sensor_effects()) {
    expose_with_effects(app, out);
    return;
  }
  out->create(height_, width_, CV_8UC1);
  const float gain = static_cast<float>(app.gain), offset = static_cast<float>(app.offset);
  const float sigma = static_cast<float>(app.noise_sigma);
  const auto& table = detail::normal_table();
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
      row[x] = static_cast<std::uint8_t>(std::clamp(v, 0.0f, 255.0f) + 0.5f);
    }
  }
}

}  // namespace vid::sim
