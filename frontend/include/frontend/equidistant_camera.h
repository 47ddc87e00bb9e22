#pragma once
/// @file equidistant_camera.h
/// @brief Pinhole + equidistant (fisheye) distortion (k1..k4), as cv::fisheye.

#include "frontend/camera_model.h"

namespace vid {

/// @brief Pinhole + equidistant camera: theta_d = theta (1 + k1 t^2 + k2 t^4 + k3 t^6 + k4 t^8).
class EquidistantCamera final : public CameraModel {
 public:
  /// @brief Build from calib (its distortion_coeffs are k1..k4).
  explicit EquidistantCamera(const CameraCalib& calib) : CameraModel(calib) {}
  Eigen::Vector2d distort(const Eigen::Vector2d& xy) const override;
  Eigen::Matrix2d distort_jacobian(const Eigen::Vector2d& xy) const override;
  bool undistort(const Eigen::Vector2d& uv, Eigen::Vector2d* xy) const override;

 protected:
  Eigen::Vector2d distort_normalized(const Eigen::Vector2d& xy,
                                     Eigen::Matrix2d* J) const override;
};

}  // namespace vid
