#include "frontend/stereo_matcher.h"

#include <algorithm>
#include <cmath>

#include "frontend/sparse_lk.h"

namespace vid {

StereoMatcher::StereoMatcher(const FrontendParams& params, const CameraModel& cam0,
                             const CameraModel& cam1)
    : p_(params), cam0_(cam0), cam1_(cam1) {
  // T_C1C0 = T_IC1^-1 T_IC0
  const Eigen::Isometry3d T_10 = cam1.calib().T_IC.inverse() * cam0.calib().T_IC;
  R_10_ = T_10.linear();
  p_10_ = T_10.translation();
  Eigen::Matrix3d tx;
  tx << 0, -p_10_.z(), p_10_.y(), p_10_.z(), 0, -p_10_.x(), -p_10_.y(), p_10_.x(), 0;
  E_ = tx * R_10_;
}

cv::Point2f StereoMatcher::infinity_guess(const Eigen::Vector2d& xy0) const {
  const Eigen::Vector3d b1 = R_10_ * Eigen::Vector3d(xy0.x(), xy0.y(), 1.0);
  Eigen::Vector2d uv;
  if (!cam1_.project(b1, &uv)) return {-1.f, -1.f};
  return {static_cast<float>(uv.x()), static_cast<float>(uv.y())};
}

double StereoMatcher::epipolar_distance_px(const Eigen::Vector2d& xy0,
                                           const Eigen::Vector2d& xy1) const {
  const Eigen::Vector3d l = E_ * Eigen::Vector3d(xy0.x(), xy0.y(), 1.0);
  const double n = l.head<2>().norm();
  if (n < 1e-15) return 0.0;
  const double d = std::abs(l.dot(Eigen::Vector3d(xy1.x(), xy1.y(), 1.0))) / n;
  return d * 0.5 * (cam1_.calib().intrinsics[0] + cam1_.calib().intrinsics[1]);
}

bool StereoMatcher::triangulate_depths(const Eigen::Vector2d& xy0, const Eigen::Vector2d& xy1,
                                       double* z0, double* z1) const {
  // z1 f1 = z0 R_10 f0 + p_10, least squares in (z0, z1).
  const Eigen::Vector3d f0(xy0.x(), xy0.y(), 1.0), f1(xy1.x(), xy1.y(), 1.0);
  Eigen::Matrix<double, 3, 2> A;
  A.col(0) = R_10_ * f0;
  A.col(1) = -f1;
  const Eigen::Matrix2d AtA = A.transpose() * A;
  if (std::abs(AtA.determinant()) < 1e-12) return false;
  const Eigen::Vector2d z = AtA.ldlt().solve(-A.transpose() * p_10_);
  *z0 = z[0];
  *z1 = z[1];
  return true;
}

void StereoMatcher::match(const std::vector<cv::Mat>& pyr0, const std::vector<cv::Mat>& pyr1,
                          const std::vector<cv::Point2f>& uv0,
                          const std::vector<Eigen::Vector2d>& xy0,
                          const std::vector<cv::Point2f>& guess1,
                          const std::vector<std::uint8_t>* close_guess,
                          std::vector<cv::Point2f>* uv1,
                          std::vector<Eigen::Vector2d>* xy1, std::vector<std::uint8_t>* ok) const {
  const std::size_t n = uv0.size();
  uv1->assign(n, cv::Point2f());
  xy1->assign(n, Eigen::Vector2d::Zero());
  ok->assign(n, 0);
  if (n == 0) return;
  std::vector<cv::Point2f> pts1(n);
  for (std::size_t i = 0; i < n; ++i) {
    pts1[i] = guess1.size() == n ? guess1[i] : infinity_guess(xy0[i]);
    if (pts1[i].x < 0.f) pts1[i] = uv0[i];
  }
  LkParams far{p_.lk_window, p_.stereo_lk_levels, p_.lk_max_iterations, p_.lk_epsilon,
               p_.lk_min_eigen};
  LkParams near_lk = far;
  near_lk.levels = std::min(p_.stereo_track_lk_levels, p_.stereo_lk_levels);
  near_lk.max_iterations = p_.lk_predicted_max_iterations;
  near_lk.epsilon = p_.lk_predicted_epsilon;
  std::vector<std::uint8_t> st(n, 0);
  // Points whose guess is last frame's disparity are within a pixel or two: stereo_track_lk_levels
  // (the base image alone by default) suffice. The others (new tracks, at the infinity guess) use
  // stereo_lk_levels.
  for (const bool near : {true, false}) {
    std::vector<std::size_t> idx;
    std::vector<cv::Point2f> a, b;
    for (std::size_t i = 0; i < n; ++i) {
      const bool is_near = close_guess != nullptr && (*close_guess)[i] != 0;
      if (is_near != near) continue;
      idx.push_back(i);
      a.push_back(uv0[i]);
      b.push_back(pts1[i]);
    }
    if (idx.empty()) continue;
    std::vector<std::uint8_t> s;
    sparse_lk(pyr0, pyr1, a, &b, &s, near ? near_lk : far);
    for (std::size_t k = 0; k < idx.size(); ++k) {
      pts1[idx[k]] = b[k];
      st[idx[k]] = s[k];
    }
  }
  std::vector<std::uint8_t> st_back(n, 1);
  if (p_.stereo_fb_check_px > 0.0) {
    std::vector<cv::Point2f> back = uv0;
    sparse_lk(pyr1, pyr0, pts1, &back, &st_back, far);
    for (std::size_t i = 0; i < n; ++i) {
      if (st_back[i] && cv::norm(back[i] - uv0[i]) > p_.stereo_fb_check_px) st_back[i] = 0;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!st[i] || !st_back[i]) continue;
    if (!accept(uv0[i], xy0[i], pts1[i], &(*xy1)[i])) continue;
    (*uv1)[i] = pts1[i];
    (*ok)[i] = 1;
  }
}

bool StereoMatcher::accept(cv::Point2f uv0, const Eigen::Vector2d& xy0, cv::Point2f uv1,
                           Eigen::Vector2d* xy1) const {
  const Eigen::Vector2d uv(uv1.x, uv1.y);
  if (!cam1_.in_image(uv, p_.border_px)) return false;
  Eigen::Vector2d x1;
  if (!cam1_.undistort(uv, &x1)) return false;
  if (epipolar_distance_px(xy0, x1) > p_.stereo_epipolar_px) return false;
  if (cv::norm(uv1 - uv0) > p_.stereo_max_disparity_px) return false;
  double z0 = 0.0, z1 = 0.0;
  // Parallel rays (far points) are fine; a finite intersection must lie in front.
  if (triangulate_depths(xy0, x1, &z0, &z1) &&
      (z0 < p_.stereo_min_depth_m || z1 < p_.stereo_min_depth_m)) {
    // Negative depths near infinity come from noise on far points: accept if the left ray at
    // infinity projects within the epipolar tolerance of the match.
    const cv::Point2f inf = infinity_guess(xy0);
    if (z0 > 0.0 || cv::norm(inf - uv1) > p_.stereo_epipolar_px) return false;
  }
  *xy1 = x1;
  return true;
}

}  // namespace vid
