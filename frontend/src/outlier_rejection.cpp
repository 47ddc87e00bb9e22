#include "frontend/outlier_rejection.h"

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>
#include <random>

namespace vid {

std::vector<std::uint8_t> ransac_fundamental(const std::vector<Eigen::Vector2d>& x0,
                                             const std::vector<Eigen::Vector2d>& x1,
                                             double threshold, double confidence) {
  const std::size_t n = x0.size();
  std::vector<std::uint8_t> inl(n, 1);
  if (n < 8 || x1.size() != n) return inl;
  std::vector<cv::Point2d> a(n), b(n);
  for (std::size_t i = 0; i < n; ++i) {
    a[i] = {x0[i].x(), x0[i].y()};
    b[i] = {x1[i].x(), x1[i].y()};
  }
  // OpenCV samples with its global RNG: reseed so every call is reproducible.
  cv::theRNG().state = 0x2545F4914F6CDD1DULL;
  cv::Mat mask;
  const cv::Mat F = cv::findFundamentalMat(a, b, cv::FM_RANSAC, threshold, confidence, 500, mask);
  if (F.empty() || mask.empty()) return inl;  // degenerate configuration: keep everything
  for (std::size_t i = 0; i < n; ++i) inl[i] = mask.at<std::uint8_t>(static_cast<int>(i)) ? 1 : 0;
  return inl;
}

std::vector<std::uint8_t> ransac_two_point(const std::vector<Eigen::Vector3d>& b0,
                                           const std::vector<Eigen::Vector3d>& b1,
                                           const Eigen::Matrix3d& R_01, double threshold,
                                           int max_iterations, std::uint64_t seed) {
  const std::size_t n = b0.size();
  std::vector<std::uint8_t> best(n, 1);
  if (n < 3 || b1.size() != n) return best;
  // Coplanarity of t, b0 and R_01 b1: t . a_i = 0.
  std::vector<Eigen::Vector3d> a(n);
  for (std::size_t i = 0; i < n; ++i) a[i] = b0[i].cross(R_01 * b1[i]);

  auto count_inliers = [&](const Eigen::Vector3d& t_dir, std::vector<std::uint8_t>* flags) {
    std::size_t c = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const bool in = std::abs(t_dir.dot(a[i])) < threshold;
      if (flags) (*flags)[i] = in ? 1 : 0;
      c += in ? 1 : 0;
    }
    return c;
  };
  // Pure rotation (no measurable translation): everything that fits the rotation is inlier.
  std::size_t rot_only = 0;
  for (const auto& ai : a) rot_only += ai.norm() < threshold ? 1 : 0;
  std::size_t best_count = 0;
  if (rot_only * 10 >= n * 9) {
    for (std::size_t i = 0; i < n; ++i) best[i] = a[i].norm() < threshold ? 1 : 0;
    return best;
  }

  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, n - 1);
  std::vector<std::uint8_t> flags(n);
  int iterations = max_iterations;
  for (int it = 0; it < iterations; ++it) {
    const std::size_t i = pick(rng), j = pick(rng);
    if (i == j) continue;
    Eigen::Vector3d t = a[i].cross(a[j]);
    if (t.norm() < 1e-12) continue;
    t.normalize();
    const std::size_t c = count_inliers(t, &flags);
    if (c > best_count) {
      best_count = c;
      best = flags;
      // Adaptive stop: 99% confidence of one all-inlier 2-sample.
      const double w = static_cast<double>(c) / static_cast<double>(n);
      const double denom = std::log(std::max(1e-12, 1.0 - w * w));
      if (denom < 0.0) {
        iterations = std::min(max_iterations, static_cast<int>(std::ceil(std::log(0.01) / denom)));
      }
    }
  }
  if (best_count == 0) std::fill(best.begin(), best.end(), 1);
  return best;
}

}  // namespace vid
