#include "frontend/sparse_lk.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <opencv2/video/tracking.hpp>

#include "bilinear.h"

namespace vid {
namespace {

/// Bilinear samples of the n x n pixel grid whose first sample is at (x, y) (one set of
/// weights for all); false if the grid, plus the interpolation's extra pixel, leaves the Mat's
/// allocation (the pyramid's padding counts).
bool sample_square(const cv::Mat& img, float x, float y, int n, float* out) {
  cv::Size whole;
  cv::Point ofs;
  img.locateROI(whole, ofs);
  const float fx0 = std::floor(x), fy0 = std::floor(y);
  if (!(std::isfinite(fx0) && std::isfinite(fy0))) return false;
  const int x0 = static_cast<int>(fx0), y0 = static_cast<int>(fy0);
  if (x0 < -ofs.x || y0 < -ofs.y || x0 + n >= whole.width - ofs.x ||
      y0 + n >= whole.height - ofs.y) {
    return false;
  }
  const auto step = static_cast<std::ptrdiff_t>(img.step[0]);
  // Rows above 0 and columns left of it: the padding.
  sample_translated(img.data + y0 * step + x0, step, n, x - fx0, y - fy0, out);
  return true;
}

/// One point through all levels; false on failure.
bool track_point(const std::vector<cv::Mat>& pyr_from, const std::vector<cv::Mat>& pyr_to,
                 cv::Point2f from, cv::Point2f* to, const LkParams& p) {
  const int h = p.window / 2, n = 2 * h + 1, m = n + 2, N = n * n;
  // 15x15 windows (31 at most here) fit on the stack.
  float big[35 * 35], tmpl[33 * 33], gx[33 * 33], gy[33 * 33], cur[33 * 33];
  if (n > 33) return false;
  const int top = std::min<int>(p.levels, static_cast<int>(pyr_from.size()) - 1);
  const float top_scale = 1.f / static_cast<float>(1 << top);
  cv::Point2f q = *to * top_scale;
  using Arr = Eigen::Map<Eigen::ArrayXf>;
  const Arr T(tmpl, N), GX(gx, N), GY(gy, N), J(cur, N);
  for (int level = top; level >= 0; --level) {
    const float s = 1.f / static_cast<float>(1 << level);
    const cv::Point2f c = from * s;
    if (!sample_square(pyr_from[static_cast<std::size_t>(level)], c.x - static_cast<float>(h + 1),
                       c.y - static_cast<float>(h + 1), m, big)) {
      return false;
    }
    for (int r = 0; r < n; ++r) {
      for (int k = 0; k < n; ++k) {
        const float* row = big + (r + 1) * m + (k + 1);
        tmpl[r * n + k] = row[0];
        gx[r * n + k] = 0.5f * (row[1] - row[-1]);
        gy[r * n + k] = 0.5f * (row[m] - row[-m]);
      }
    }
    const float a11 = (GX * GX).sum(), a12 = (GX * GY).sum(), a22 = (GY * GY).sum();
    const float det = a11 * a22 - a12 * a12;
    // cv::calcOpticalFlowPyrLK's scale: Scharr gradient = 32 x central difference, / 2^20.
    const float min_eig = (a11 + a22 - std::sqrt((a11 - a22) * (a11 - a22) + 4.f * a12 * a12)) /
                          (2.f * static_cast<float>(N) * 1024.f);
    if (min_eig < static_cast<float>(p.min_eigen) || det < 1e-6f) {
      if (level == 0) return false;
      q *= 2.f;  // too weak at this level: keep the guess
      continue;
    }
    cv::Point2f last_step(0.f, 0.f);
    for (int it = 0; it < p.max_iterations; ++it) {
      if (!sample_square(pyr_to[static_cast<std::size_t>(level)], q.x - static_cast<float>(h),
                         q.y - static_cast<float>(h), n, cur)) {
        return false;
      }
      const auto e = T - J;
      const float b1 = (e * GX).sum(), b2 = (e * GY).sum();
      const cv::Point2f step((a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det);
      // Oscillating between two points: settle half-way (as OpenCV does).
      if (it > 0 && std::abs(step.x + last_step.x) < 0.01f &&
          std::abs(step.y + last_step.y) < 0.01f) {
        q -= step * 0.5f;
        break;
      }
      q += step;
      last_step = step;
      if (step.dot(step) < static_cast<float>(p.epsilon * p.epsilon)) break;
    }
    if (level > 0) q *= 2.f;
  }
  if (!std::isfinite(q.x) || !std::isfinite(q.y)) return false;
  *to = q;
  return true;
}

}  // namespace

void build_lk_pyramid(const cv::Mat& img, int window, int levels, std::vector<cv::Mat>* pyr) {
  cv::buildOpticalFlowPyramid(img, *pyr, cv::Size(window, window), levels, false);
}

void sparse_lk(const std::vector<cv::Mat>& pyr_from, const std::vector<cv::Mat>& pyr_to,
               const std::vector<cv::Point2f>& from, std::vector<cv::Point2f>* to,
               std::vector<std::uint8_t>* ok, const LkParams& p) {
  ok->assign(from.size(), 0);
  for (std::size_t i = 0; i < from.size(); ++i) {
    (*ok)[i] = track_point(pyr_from, pyr_to, from[i], &(*to)[i], p) ? 1 : 0;
  }
}

}  // namespace vid
