#pragma once
/// @file camera_model.h
/// @brief Pinhole camera models with radial-tangential (Kalibr "radtan", OpenCV's
/// k1,k2,p1,p2) or equidistant (Kalibr "equidistant", OpenCV fisheye k1..k4) distortion.
/// Eigen only; conventions match OpenCV's projectPoints / fisheye::projectPoints.

#include <Eigen/Core>
#include <memory>

#include "types/calibration.h"

namespace vid {

/// @brief Pinhole + distortion camera, built from a CameraCalib.
class CameraModel {
 public:
  /// @brief Make the model named by calib.distortion (kNone -> radtan with zero coeffs).
  /// Throws std::invalid_argument on non-positive focal length or resolution.
  static std::unique_ptr<CameraModel> create(const CameraCalib& calib);
  virtual ~CameraModel() = default;

  /// @brief The calibration the model was built from.
  const CameraCalib& calib() const { return calib_; }
  /// @brief Image width [px].
  int width() const { return calib_.width; }
  /// @brief Image height [px].
  int height() const { return calib_.height; }

  /// @brief Normalized undistorted (x/z, y/z) -> distorted pixel.
  virtual Eigen::Vector2d distort(const Eigen::Vector2d& xy) const = 0;
  /// @brief d(pixel)/d(xy) of distort().
  virtual Eigen::Matrix2d distort_jacobian(const Eigen::Vector2d& xy) const = 0;
  /// @brief Distorted pixel -> normalized undistorted, Gauss-Newton to 1e-10; false if it
  /// fails to converge.
  virtual bool undistort(const Eigen::Vector2d& uv, Eigen::Vector2d* xy) const = 0;

  /// @brief Point in camera frame -> pixel; false if behind camera (z <= 1e-6).
  bool project(const Eigen::Vector3d& p_C, Eigen::Vector2d* uv) const;
  /// @brief d(pixel)/d(p_C) of project() (z must be > 0).
  Eigen::Matrix<double, 2, 3> project_jacobian(const Eigen::Vector3d& p_C) const;
  /// @brief Pixel -> unit bearing in the camera frame; false if undistortion fails.
  bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* bearing_C) const;
  /// @brief True if uv lies inside the image, at least `border` px from its edges.
  bool in_image(const Eigen::Vector2d& uv, double border = 0.0) const;

 protected:
  explicit CameraModel(const CameraCalib& calib) : calib_(calib) {}

  /// @brief Normalized xy -> distorted normalized (before applying K) and its Jacobian.
  virtual Eigen::Vector2d distort_normalized(const Eigen::Vector2d& xy,
                                             Eigen::Matrix2d* J) const = 0;
  /// @brief Shared Gauss-Newton inversion of distort_normalized().
  bool undistort_gauss_newton(const Eigen::Vector2d& uv, Eigen::Vector2d* xy) const;

  double fu() const { return calib_.intrinsics[0]; }
  double fv() const { return calib_.intrinsics[1]; }
  double cu() const { return calib_.intrinsics[2]; }
  double cv() const { return calib_.intrinsics[3]; }

 private:
  CameraCalib calib_;
};

}  // namespace vid
