#include "frontend/camera_model.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "frontend/equidistant_camera.h"
#include "frontend/radtan_camera.h"

namespace vid {

std::unique_ptr<CameraModel> CameraModel::create(const CameraCalib& calib) {
  const std::string who = "camera " + std::to_string(calib.cam_id) + ": ";
  if (!(calib.intrinsics[0] > 0.0) || !(calib.intrinsics[1] > 0.0)) {
    throw std::invalid_argument(who + "intrinsics fu, fv must be positive");
  }
  if (calib.width <= 0 || calib.height <= 0) {
    throw std::invalid_argument(who + "resolution must be positive");
  }
  if (!calib.distortion_coeffs.allFinite() || !calib.intrinsics.allFinite()) {
    throw std::invalid_argument(who + "intrinsics/distortion_coefficients must be finite");
  }
  switch (calib.distortion) {
    case DistortionModel::kEquidistant:
      return std::make_unique<EquidistantCamera>(calib);
    case DistortionModel::kNone: {
      CameraCalib c = calib;
      c.distortion_coeffs.setZero();
      return std::make_unique<RadTanCamera>(c);
    }
    case DistortionModel::kRadTan:
    default:
      return std::make_unique<RadTanCamera>(calib);
  }
}

bool CameraModel::project(const Eigen::Vector3d& p_C, Eigen::Vector2d* uv) const {
  if (!(p_C.z() > 1e-6)) return false;
  *uv = distort(p_C.head<2>() / p_C.z());
  return uv->allFinite();
}

Eigen::Matrix<double, 2, 3> CameraModel::project_jacobian(const Eigen::Vector3d& p_C) const {
  const double iz = 1.0 / p_C.z();
  const Eigen::Vector2d xy = p_C.head<2>() * iz;
  Eigen::Matrix<double, 2, 3> dxy_dp;
  dxy_dp << iz, 0.0, -xy.x() * iz, 0.0, iz, -xy.y() * iz;
  return distort_jacobian(xy) * dxy_dp;
}

bool CameraModel::unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* bearing_C) const {
  Eigen::Vector2d xy;
  if (!undistort(uv, &xy)) return false;
  *bearing_C = Eigen::Vector3d(xy.x(), xy.y(), 1.0).normalized();
  return true;
}

bool CameraModel::in_image(const Eigen::Vector2d& uv, double border) const {
  // Pixel centres are at integer coordinates; the image spans [-0.5, size - 0.5].
  return uv.x() >= border - 0.5 && uv.y() >= border - 0.5 &&
         uv.x() <= calib_.width - 0.5 - border && uv.y() <= calib_.height - 0.5 - border;
}

bool CameraModel::undistort_gauss_newton(const Eigen::Vector2d& uv, Eigen::Vector2d* xy) const {
  if (!uv.allFinite()) return false;
  // Target in distorted normalized coordinates; the K part is inverted exactly.
  const Eigen::Vector2d target((uv.x() - cu()) / fu(), (uv.y() - cv()) / fv());
  Eigen::Vector2d x = target;
  constexpr int kMaxIterations = 100;
  for (int it = 0; it < kMaxIterations; ++it) {
    Eigen::Matrix2d J;
    const Eigen::Vector2d r = distort_normalized(x, &J) - target;
    // Residual measured in pixels; the contract is 1e-10 px, aim a decade lower (Gauss-Newton
    // converges quadratically, so this costs at most one more iteration).
    if (std::abs(r.x() * fu()) < 1e-11 && std::abs(r.y() * fv()) < 1e-11) {
      *xy = x;
      return x.allFinite();
    }
    const double det = J.determinant();
    if (!std::isfinite(det) || std::abs(det) < 1e-12) return false;
    Eigen::Vector2d step = J.inverse() * r;
    // Damp huge steps so the iteration stays in the region where the model is monotonic.
    const double max_step = 0.5 * (1.0 + x.norm());
    if (step.norm() > max_step) step *= max_step / step.norm();
    x -= step;
    if (!x.allFinite()) return false;
  }
  // Accept if the last residual is at the floating-point floor (tiny relative error).
  Eigen::Matrix2d J;
  const Eigen::Vector2d r = distort_normalized(x, &J) - target;
  if ((r.array().abs() * Eigen::Array2d(fu(), fv())).maxCoeff() < 1e-10) {
    *xy = x;
    return true;
  }
  return false;
}

}  // namespace vid
