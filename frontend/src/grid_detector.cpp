#include "frontend/grid_detector.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/features2d.hpp>

#include "frontend/image_noise.h"

namespace vid {
namespace {

/// Occupancy raster with cells of min_distance / sqrt(2): one feature per raster cell and
/// its 5x5 neighbourhood checked exactly keeps every pair >= min_distance apart.
class DistanceMask {
 public:
  DistanceMask(int width, int height, double min_distance)
      : min_d2_(min_distance * min_distance),
        cell_(std::max(1.0, min_distance / std::sqrt(2.0))),
        cols_(static_cast<int>(std::ceil(width / cell_)) + 1),
        rows_(static_cast<int>(std::ceil(height / cell_)) + 1),
        slots_(static_cast<std::size_t>(cols_ * rows_), -1) {}

  bool free(const cv::Point2f& p) const {
    const int cx = cell_x(p), cy = cell_y(p);
    const int r = static_cast<int>(std::ceil(std::sqrt(min_d2_) / cell_));
    for (int y = std::max(0, cy - r); y <= std::min(rows_ - 1, cy + r); ++y) {
      for (int x = std::max(0, cx - r); x <= std::min(cols_ - 1, cx + r); ++x) {
        const int idx = slots_[static_cast<std::size_t>(y * cols_ + x)];
        if (idx < 0) continue;
        const cv::Point2f d = points_[static_cast<std::size_t>(idx)] - p;
        if (d.x * d.x + d.y * d.y < min_d2_) return false;
      }
    }
    return true;
  }

  void add(const cv::Point2f& p) {
    const std::size_t s = static_cast<std::size_t>(cell_y(p) * cols_ + cell_x(p));
    slots_[s] = static_cast<int>(points_.size());
    points_.push_back(p);
  }

 private:
  int cell_x(const cv::Point2f& p) const {
    return std::clamp(static_cast<int>(p.x / cell_), 0, cols_ - 1);
  }
  int cell_y(const cv::Point2f& p) const {
    return std::clamp(static_cast<int>(p.y / cell_), 0, rows_ - 1);
  }
  double min_d2_;
  double cell_;
  int cols_, rows_;
  std::vector<int> slots_;
  std::vector<cv::Point2f> points_;
};

}  // namespace

int GridDetector::cell_of(const cv::Point2f& p) const {
  const int gc = std::max(1, p_.grid_cols), gr = std::max(1, p_.grid_rows);
  const double cw = static_cast<double>(size_.width) / gc, ch = static_cast<double>(size_.height) / gr;
  const int x = std::clamp(static_cast<int>(p.x / cw), 0, gc - 1);
  const int y = std::clamp(static_cast<int>(p.y / ch), 0, gr - 1);
  return y * gc + x;
}

std::vector<cv::Point2f> GridDetector::detect(const cv::Mat& image,
                                              const std::vector<cv::Point2f>& existing,
                                              int wanted) {
  std::fill(born_.begin(), born_.end(), 0);
  if (wanted <= 0 || image.empty()) return {};
  size_ = image.size();
  std::vector<cv::Point2f> out = detect_in_cells(image, existing, wanted);
  born_.assign(static_cast<std::size_t>(std::max(1, p_.grid_cols) * std::max(1, p_.grid_rows)), 0);
  for (const auto& p : out) ++born_[static_cast<std::size_t>(cell_of(p))];
  return out;
}

void GridDetector::first_frame_losses(const std::vector<cv::Point2f>& lost) {
  if (born_.empty() || idle_.size() != born_.size()) return;
  std::vector<int> died(born_.size(), 0);
  for (const auto& p : lost) ++died[static_cast<std::size_t>(cell_of(p))];
  for (std::size_t c = 0; c < born_.size(); ++c) {
    if (born_[c] > 0 && died[c] >= born_[c]) idle_[c] = p_.detect_cell_retry_frames;
  }
  std::fill(born_.begin(), born_.end(), 0);
}

std::vector<cv::Point2f> GridDetector::detect_in_cells(const cv::Mat& image,
                                                       const std::vector<cv::Point2f>& existing,
                                                       int wanted) {
  std::vector<cv::Point2f> out;
  const int W = image.cols, H = image.rows;
  const int gc = std::max(1, p_.grid_cols), gr = std::max(1, p_.grid_rows);
  const int n_cells = gc * gr;
  const int quota = static_cast<int>(
      std::ceil(static_cast<double>(existing.size() + static_cast<std::size_t>(wanted)) / n_cells));
  const double cw = static_cast<double>(W) / gc, ch = static_cast<double>(H) / gr;

  DistanceMask mask(W, H, p_.min_distance_px);
  std::vector<int> count(static_cast<std::size_t>(n_cells), 0);
  for (const auto& e : existing) {
    mask.add(e);
    ++count[static_cast<std::size_t>(cell_of(e))];
  }

  // FAST only in cells below their quota (in steady state most cells are full, so this is
  // much cheaper than a full-image pass). Each cell is searched with a 3 px apron so corners on
  // cell borders are not lost to FAST's own border.
  const int b = std::max(p_.border_px, 3);
  if (W <= 2 * b || H <= 2 * b) return out;
  auto fast_in = [&](const cv::Rect& r, int threshold, int cell, std::vector<cv::KeyPoint>* dst) {
    std::vector<cv::KeyPoint> kps;
    cv::FAST(image(r), kps, threshold, true);
    for (auto& k : kps) {
      k.pt += cv::Point2f(static_cast<float>(r.x), static_cast<float>(r.y));
      if (cell_of(k.pt) == cell && k.pt.x >= b && k.pt.y >= b && k.pt.x < W - b && k.pt.y < H - b) {
        dst->push_back(k);
      }
    }
  };
  // A threshold inside the image noise finds noise corners that die in their first frame and
  // crowd out the real ones (pure noise gives FAST ~2.5 corners per 80x80 cell at 3 sigma,
  // ~50 at 2 sigma, hundreds below), so both thresholds are raised to fast_noise_factor sigma.
  int threshold = p_.fast_threshold, threshold_min = p_.fast_threshold_min;
  if (p_.fast_noise_factor > 0.0) {
    const int floor = static_cast<int>(std::ceil(p_.fast_noise_factor * estimate_noise_sigma(image)));
    threshold = std::max(threshold, floor);
    threshold_min = std::max(threshold_min, floor);
  }
  std::vector<std::vector<cv::KeyPoint>> buckets(static_cast<std::size_t>(n_cells));
  if (idle_.size() != static_cast<std::size_t>(n_cells)) idle_.assign(static_cast<std::size_t>(n_cells), 0);
  std::vector<std::uint8_t> searched(static_cast<std::size_t>(n_cells), 0);
  std::vector<int> candidates;  // below quota and not resting
  for (int c = 0; c < n_cells; ++c) {
    if (count[static_cast<std::size_t>(c)] >= quota) continue;
    if (idle_[static_cast<std::size_t>(c)] > 0) {
      --idle_[static_cast<std::size_t>(c)];
      continue;
    }
    candidates.push_back(c);
  }
  // Search only the cells an even fill needs (water-filling): raising every candidate cell to
  // a common level L costs fill(L) features; `wanted` reaches level L* < quota and leaves
  // `rest` = wanted - fill(L*) features, one each for cells at level L*. So every cell below L*
  // is searched (it can also take one of the rest), plus as many cells at exactly L* as the
  // rest still needs, taken in turn from call to call. FAST costs per pixel searched: searching
  // every cell below its quota spent a whole cell's search on one corner the spread did not
  // need (fast_yaw: 29 of 48 cells per call for 18 new features).
  const auto fill = [&](int level) {
    int n = 0;
    for (const int c : candidates) n += std::max(0, level - count[static_cast<std::size_t>(c)]);
    return n;
  };
  int level = 0;
  while (level < quota - 1 && fill(level + 1) <= wanted) ++level;
  std::vector<int> to_search, at_level;
  for (const int c : candidates) {
    (count[static_cast<std::size_t>(c)] < level ? to_search : at_level).push_back(c);
  }
  int rest = wanted - fill(level) - static_cast<int>(to_search.size());
  if (!at_level.empty()) {
    const std::size_t start = next_cell_ % at_level.size();
    std::size_t taken = 0;
    for (; taken < at_level.size() && rest > 0; ++taken, --rest) {
      to_search.push_back(at_level[(start + taken) % at_level.size()]);
    }
    next_cell_ = start + taken;
  }
  for (const int c : to_search) {
    searched[static_cast<std::size_t>(c)] = 1;
    const int x0 = static_cast<int>(std::floor((c % gc) * cw)) - 3;
    const int y0 = static_cast<int>(std::floor((c / gc) * ch)) - 3;
    const cv::Rect cell(x0, y0, static_cast<int>(std::ceil(cw)) + 7, static_cast<int>(std::ceil(ch)) + 7);
    const cv::Rect r = cell & cv::Rect(b - 3, b - 3, W - 2 * b + 6, H - 2 * b + 6);
    if (r.width < 7 || r.height < 7) continue;
    auto& bucket = buckets[static_cast<std::size_t>(c)];
    fast_in(r, threshold, c, &bucket);
    // Weakly textured cell: retry with a lower threshold so that every region gets features.
    if (bucket.empty() && threshold_min > 0 && threshold_min < threshold) fast_in(r, threshold_min, c, &bucket);
  }

  // Per cell, strongest first, up to the quota; leftovers may fill the global budget later.
  std::vector<cv::KeyPoint> leftovers;
  for (int c = 0; c < n_cells; ++c) {
    auto& bucket = buckets[static_cast<std::size_t>(c)];
    std::sort(bucket.begin(), bucket.end(),
              [](const cv::KeyPoint& a, const cv::KeyPoint& b2) { return a.response > b2.response; });
    for (const auto& k : bucket) {
      if (count[static_cast<std::size_t>(c)] >= quota) {
        leftovers.push_back(k);
        continue;
      }
      if (!mask.free(k.pt)) continue;
      mask.add(k.pt);
      out.push_back(k.pt);
      ++count[static_cast<std::size_t>(c)];
    }
  }
  // Searched cells that gained nothing rest for a few calls.
  {
    std::vector<int> gained(static_cast<std::size_t>(n_cells), 0);
    for (const auto& p : out) ++gained[static_cast<std::size_t>(cell_of(p))];
    for (int c = 0; c < n_cells; ++c) {
      const auto k = static_cast<std::size_t>(c);
      if (searched[k] && gained[k] == 0) idle_[k] = p_.detect_cell_retry_frames;
    }
  }
  if (static_cast<int>(out.size()) > wanted) {
    // Too many (quotas round up): keep an even spread by dropping from the fullest cells last
    // added; simplest fair rule is truncation of a cell-interleaved order.
    std::vector<std::vector<cv::Point2f>> per(static_cast<std::size_t>(n_cells));
    for (const auto& p : out) per[static_cast<std::size_t>(cell_of(p))].push_back(p);
    out.clear();
    for (std::size_t rank = 0; static_cast<int>(out.size()) < wanted; ++rank) {
      bool any = false;
      for (auto& v : per) {
        if (rank < v.size()) {
          any = true;
          if (static_cast<int>(out.size()) < wanted) out.push_back(v[rank]);
        }
      }
      if (!any) break;
    }
    return out;
  }
  std::sort(leftovers.begin(), leftovers.end(),
            [](const cv::KeyPoint& a, const cv::KeyPoint& b2) { return a.response > b2.response; });
  for (const auto& k : leftovers) {
    if (static_cast<int>(out.size()) >= wanted) break;
    if (!mask.free(k.pt)) continue;
    mask.add(k.pt);
    out.push_back(k.pt);
  }
  return out;
}

}  // namespace vid
