#pragma once
/// @file radtan_camera.h
/// @brief Pinhole + radial-tangential distortion (k1, k2, p1, p2), as OpenCV with 4 coeffs.

#include "frontend/camera_model.h"

namespace vid {

/// @brief Pinhole + radtan camera.
class RadTanCamera final : public CameraModel {
 public:
  /// @brief Build from calib (its distortion_coeffs are k1, k2, p1, p2).
  explicit RadTanCamera(const CameraCalib& calib) : CameraModel(calib) {}
  Eigen::Vector2d distort(const Eigen::Vector2d& xy) const override;
  Eigen::Matrix2d distort_jacobian(const Eigen::Vector2d& xy) const override;
  bool undistort(const Eigen::Vector2d& uv, Eigen::Vector2d* xy) const override;

 protected:
  Eigen::Vector2d distort_normalized(const Eigen::Vector2d& xy,
                                     Eigen::Matrix2d* J) const override;
};

}  // namespace vid
