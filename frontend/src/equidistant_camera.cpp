#include "frontend/equidistant_camera.h"

#include <cmath>

namespace vid {

Eigen::Vector2d EquidistantCamera::distort_normalized(const Eigen::Vector2d& xy,
                                                      Eigen::Matrix2d* J) const {
  const auto& k = calib().distortion_coeffs;
  const double r = xy.norm();
  // Near the axis the model is the identity to second order; avoid 0/0.
  if (r < 1e-10) {
    if (J != nullptr) J->setIdentity();
    return xy;
  }
  const double th = std::atan(r);
  const double t2 = th * th;
  const double poly = 1.0 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3])));
  const double th_d = th * poly;
  const double scale = th_d / r;
  if (J != nullptr) {
    // d(th_d)/d(th) = 1 + 3k1 t^2 + 5k2 t^4 + 7k3 t^6 + 9k4 t^8; d(th)/dr = 1/(1+r^2)
    const double dthd_dth =
        1.0 + t2 * (3.0 * k[0] + t2 * (5.0 * k[1] + t2 * (7.0 * k[2] + t2 * 9.0 * k[3])));
    const double dthd_dr = dthd_dth / (1.0 + r * r);
    const double dscale_dr = (dthd_dr * r - th_d) / (r * r);
    const Eigen::Vector2d dr_dxy = xy / r;
    *J = scale * Eigen::Matrix2d::Identity() + xy * (dscale_dr * dr_dxy.transpose());
  }
  return xy * scale;
}

Eigen::Vector2d EquidistantCamera::distort(const Eigen::Vector2d& xy) const {
  const Eigen::Vector2d d = distort_normalized(xy, nullptr);
  return {fu() * d.x() + cu(), fv() * d.y() + cv()};
}

Eigen::Matrix2d EquidistantCamera::distort_jacobian(const Eigen::Vector2d& xy) const {
  Eigen::Matrix2d J;
  distort_normalized(xy, &J);
  J.row(0) *= fu();
  J.row(1) *= fv();
  return J;
}

bool EquidistantCamera::undistort(const Eigen::Vector2d& uv, Eigen::Vector2d* xy) const {
  return undistort_gauss_newton(uv, xy);
}

}  // namespace vid
