#include "sim/render/texture.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "sim/render/random.h"

namespace vid::sim {

namespace {

/// Smooth value noise: a coarse random grid upsampled with bicubic interpolation, with a
/// random sub-cell offset so octaves do not share grid lines.
void add_value_noise(cv::Mat* acc, double cell_texels, double amplitude, Rng* rng) {
  const int gw = static_cast<int>(std::ceil(acc->cols / cell_texels)) + 4;
  const int gh = static_cast<int>(std::ceil(acc->rows / cell_texels)) + 4;
  cv::Mat grid(gh, gw, CV_32F);
  for (int r = 0; r < gh; ++r) {
    for (int c = 0; c < gw; ++c) grid.at<float>(r, c) = static_cast<float>(rng->uniform(-1, 1));
  }
  const int up_w = static_cast<int>(std::lround(gw * cell_texels));
  const int up_h = static_cast<int>(std::lround(gh * cell_texels));
  cv::Mat up;
  cv::resize(grid, up, cv::Size(up_w, up_h), 0, 0, cv::INTER_CUBIC);
  const int off_x = rng->uniform_int(std::max(1, up_w - acc->cols - 1));
  const int off_y = rng->uniform_int(std::max(1, up_h - acc->rows - 1));
  cv::Mat roi = up(cv::Rect(off_x, off_y, acc->cols, acc->rows));
  cv::scaleAdd(roi, amplitude, *acc, *acc);
}

/// One hard-edged shape of size ~`s` texels at a random place with gray level `level`.
void draw_shape(cv::Mat* img, double s, double level, Rng* rng) {
  constexpr int kShift = 4;  // sub-texel precision for anti-aliased polygon edges
  constexpr double kScale = 1 << kShift;
  const double cx = rng->uniform(-s, img->cols + s);
  const double cy = rng->uniform(-s, img->rows + s);
  const cv::Scalar color(level);
  const int kind = rng->uniform_int(10);
  auto pt = [&](double x, double y) {
    return cv::Point(static_cast<int>(std::lround(x * kScale)),
                     static_cast<int>(std::lround(y * kScale)));
  };
  if (kind < 4) {  // axis-aligned rectangle: the most corner-rich shape
    const double w = s * rng->uniform(0.4, 1.0), h = s * rng->uniform(0.4, 1.0);
    const cv::Point p[4] = {pt(cx - w / 2, cy - h / 2), pt(cx + w / 2, cy - h / 2),
                            pt(cx + w / 2, cy + h / 2), pt(cx - w / 2, cy + h / 2)};
    cv::fillConvexPoly(*img, p, 4, color, cv::LINE_AA, kShift);
  } else if (kind < 7) {  // rotated rectangle
    const double w = s * rng->uniform(0.3, 1.0), h = s * rng->uniform(0.3, 1.0);
    const double a = rng->uniform(0, std::numbers::pi);
    const double ca = std::cos(a), sa = std::sin(a);
    cv::Point p[4];
    const double sx[4] = {-0.5, 0.5, 0.5, -0.5}, sy[4] = {-0.5, -0.5, 0.5, 0.5};
    for (int i = 0; i < 4; ++i) {
      const double x = sx[i] * w, y = sy[i] * h;
      p[i] = pt(cx + ca * x - sa * y, cy + sa * x + ca * y);
    }
    cv::fillConvexPoly(*img, p, 4, color, cv::LINE_AA, kShift);
  } else if (kind < 9) {  // triangle
    cv::Point p[3];
    const double a0 = rng->uniform(0, 2 * std::numbers::pi);
    for (int i = 0; i < 3; ++i) {
      const double a = a0 + i * 2.0 * std::numbers::pi / 3.0 + rng->uniform(-0.5, 0.5);
      const double r = 0.5 * s * rng->uniform(0.6, 1.0);
      p[i] = pt(cx + r * std::cos(a), cy + r * std::sin(a));
    }
    cv::fillConvexPoly(*img, p, 3, color, cv::LINE_AA, kShift);
  } else {  // ellipse: gives curved edges, no corners
    const cv::Size axes(static_cast<int>(std::lround(0.5 * s * rng->uniform(0.4, 1.0) * kScale)),
                        static_cast<int>(std::lround(0.5 * s * rng->uniform(0.4, 1.0) * kScale)));
    cv::ellipse(*img, pt(cx, cy), axes, rng->uniform(0, 180), 0, 360, color, cv::FILLED,
                cv::LINE_AA, kShift);
  }
}

}  // namespace

cv::Mat make_surface_texture(double size_m_u, double size_m_v, double texels_per_m,
                             std::uint64_t seed, const TextureStyle& style) {
  const int w = std::max(2, static_cast<int>(std::ceil(size_m_u * texels_per_m)) + 1);
  const int h = std::max(2, static_cast<int>(std::ceil(size_m_v * texels_per_m)) + 1);
  Rng rng(seed);
  cv::Mat img(h, w, CV_8U, cv::Scalar(std::clamp(style.mean_level, 0.0, 255.0)));
  // Dead-leaves layers from large to small shapes; each scale covers part of the area, so
  // corners exist at every viewing distance and large shapes stay visible from far away.
  const double scales_m[] = {0.80, 0.42, 0.22, 0.11, 0.055, 0.03};
  const double coverage[] = {3.0, 0.6, 0.3, 0.14, 0.07, 0.03};
  // Small surfaces (box faces) start at a scale that fits them, fully covered, so every
  // face shows several shapes instead of one large one.
  int k0 = 0;
  while (k0 < 5 && scales_m[k0] > 0.5 * std::min(size_m_u, size_m_v)) ++k0;
  const double area_texels = static_cast<double>(w) * h;
  for (int k = k0; k < 6; ++k) {
    const double s = scales_m[k] * texels_per_m;
    if (s < 3.0) continue;  // smaller than the texel grid can hold
    const double cover = k == k0 ? std::max(coverage[k], 3.0) : coverage[k];
    const long n = std::lround(style.shape_density * cover * area_texels / (0.6 * s * s));
    for (long i = 0; i < n; ++i) {
      const double size = s * rng.uniform(0.7, 1.4);
      const double level = std::clamp(
          style.mean_level + rng.uniform(-style.level_spread, style.level_spread), 8.0, 247.0);
      draw_shape(&img, size, level, &rng);
    }
  }
  // Smooth gradients on top: value-noise octaves (1.5 m, 0.5 m, 0.15 m cells).
  cv::Mat acc;
  img.convertTo(acc, CV_32F);
  const double cells_m[] = {1.5, 0.5, 0.15};
  const double weights[] = {0.5, 0.3, 0.2};
  for (int k = 0; k < 3; ++k) {
    const double cell = std::max(2.0, cells_m[k] * texels_per_m);
    add_value_noise(&acc, cell, style.noise_amplitude * weights[k] * 2.0, &rng);
  }
  acc.convertTo(img, CV_8U);  // saturating
  return img;
}

}  // namespace vid::sim
