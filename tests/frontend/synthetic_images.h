#pragma once
// Synthetic textured images and known warps for frontend unit tests (no simulator needed).
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "types/calibration.h"

namespace vid::test {

/// Textured 8-bit image: blurred noise at two scales plus random rectangles and circles.
inline cv::Mat textured_image(int width, int height, std::uint64_t seed) {
  cv::RNG rng(seed);
  cv::Mat coarse(height / 8 + 1, width / 8 + 1, CV_32F), fine(height, width, CV_32F);
  rng.fill(coarse, cv::RNG::UNIFORM, 0.0, 1.0);
  rng.fill(fine, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::Mat c_up;
  cv::resize(coarse, c_up, cv::Size(width, height), 0, 0, cv::INTER_CUBIC);
  cv::GaussianBlur(fine, fine, cv::Size(0, 0), 2.0);
  cv::Mat img = 140.0 * c_up + 500.0 * (fine - 0.5) + 40.0;
  for (int i = 0; i < 120; ++i) {
    const cv::Point a(rng.uniform(0, width), rng.uniform(0, height));
    const double v = rng.uniform(0.0, 255.0);
    if (i % 2) {
      cv::rectangle(img, a, a + cv::Point(rng.uniform(8, 50), rng.uniform(8, 50)), v, -1,
                    cv::LINE_AA);
    } else {
      cv::circle(img, a, rng.uniform(4, 25), v, -1, cv::LINE_AA);
    }
  }
  cv::Mat out;
  img.convertTo(out, CV_8U);
  cv::GaussianBlur(out, out, cv::Size(0, 0), 1.2);
  return out;
}

/// Warp src by homography H (dst(H x) = src(x)), bilinear, replicated border.
inline cv::Mat warp(const cv::Mat& src, const cv::Matx33d& H) {
  cv::Mat dst;
  cv::warpPerspective(src, dst, H, src.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT101);
  return dst;
}

inline cv::Point2d apply(const cv::Matx33d& H, const cv::Point2d& p) {
  const cv::Vec3d q = H * cv::Vec3d(p.x, p.y, 1.0);
  return {q[0] / q[2], q[1] / q[2]};
}

/// Undistorted pinhole 640x480 calibration.
inline CameraCalib pinhole(int cam_id, double baseline_x = 0.0) {
  CameraCalib c;
  c.cam_id = cam_id;
  c.width = 640;
  c.height = 480;
  c.intrinsics << 400.0, 400.0, 319.5, 239.5;
  c.distortion = DistortionModel::kRadTan;
  c.distortion_coeffs.setZero();
  c.T_IC = Eigen::Isometry3d::Identity();
  c.T_IC.translation() = Eigen::Vector3d(baseline_x, 0.0, 0.0);
  return c;
}

inline cv::Matx33d k_of(const CameraCalib& c) {
  return {c.intrinsics[0], 0, c.intrinsics[2], 0, c.intrinsics[1], c.intrinsics[3], 0, 0, 1};
}

}  // namespace vid::test
