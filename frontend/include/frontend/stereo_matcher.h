#pragma once
/// @file stereo_matcher.h
/// @brief Left -> right matching of features by pyramidal KLT (sparse_lk), with an epipolar check from the
/// calibrated relative pose (essential matrix) and a disparity / depth check.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "frontend/camera_model.h"
#include "frontend/frontend_params.h"

namespace vid {

/// @brief Stereo matcher for one calibrated camera pair (C0 left, C1 right).
class StereoMatcher {
 public:
  StereoMatcher(const FrontendParams& params, const CameraModel& cam0, const CameraModel& cam1);

  /// @brief Track left points into the right image.
  /// @param pyr0, pyr1  pyramids from build_lk_pyramid
  /// @param uv0         left pixels; xy0 their undistorted normalized coordinates
  /// @param guess1      initial right pixels (empty: projection of the left ray at infinity)
  /// @param close_guess optional, 1 where guess1 is known to be within ~2 px (e.g. last
  ///                    frame's disparity): those points are tracked on one pyramid level only
  /// @param uv1         right pixels (output); ok (output) 1 where the match passed all checks
  void match(const std::vector<cv::Mat>& pyr0, const std::vector<cv::Mat>& pyr1,
             const std::vector<cv::Point2f>& uv0, const std::vector<Eigen::Vector2d>& xy0,
             const std::vector<cv::Point2f>& guess1, const std::vector<std::uint8_t>* close_guess,
             std::vector<cv::Point2f>* uv1,
             std::vector<Eigen::Vector2d>* xy1, std::vector<std::uint8_t>* ok) const;

  /// @brief The geometric checks of a match uv0 (left, normalized xy0) -> uv1 (right): inside
  /// the right image's border, on the epipolar line, disparity and depth in range. Sets xy1
  /// (normalized right) when it passes.
  bool accept(cv::Point2f uv0, const Eigen::Vector2d& xy0, cv::Point2f uv1,
              Eigen::Vector2d* xy1) const;

  /// @brief Right pixel of the left ray through xy0 at infinite depth.
  cv::Point2f infinity_guess(const Eigen::Vector2d& xy0) const;
  /// @brief Distance [px, right image] of xy1 from the epipolar line of xy0.
  double epipolar_distance_px(const Eigen::Vector2d& xy0, const Eigen::Vector2d& xy1) const;
  /// @brief Depths (along z) of the point seen at xy0 / xy1 in C0 and C1; false if the rays are
  /// parallel.
  bool triangulate_depths(const Eigen::Vector2d& xy0, const Eigen::Vector2d& xy1, double* z0,
                          double* z1) const;

 private:
  FrontendParams p_;
  const CameraModel& cam0_;
  const CameraModel& cam1_;
  Eigen::Matrix3d R_10_;  ///< rotation taking C0 vectors into C1
  Eigen::Vector3d p_10_;  ///< position of C0 in C1
  Eigen::Matrix3d E_;     ///< x1^T E x0 = 0
};

}  // namespace vid
