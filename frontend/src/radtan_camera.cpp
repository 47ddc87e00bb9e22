#include "frontend/radtan_camera.h"

namespace vid {

Eigen::Vector2d RadTanCamera::distort_normalized(const Eigen::Vector2d& xy,
                                                 Eigen::Matrix2d* J) const {
  const auto& d = calib().distortion_coeffs;
  const double k1 = d[0], k2 = d[1], p1 = d[2], p2 = d[3];
  const double x = xy.x(), y = xy.y();
  const double x2 = x * x, y2 = y * y, xy2 = 2.0 * x * y;
  const double r2 = x2 + y2;
  const double radial = 1.0 + r2 * (k1 + k2 * r2);
  const Eigen::Vector2d out(x * radial + p1 * xy2 + p2 * (r2 + 2.0 * x2),
                            y * radial + p1 * (r2 + 2.0 * y2) + p2 * xy2);
  if (J != nullptr) {
    const double dradial_dr2 = k1 + 2.0 * k2 * r2;
    // d(radial)/dx = dradial_dr2 * 2x
    (*J)(0, 0) = radial + x * dradial_dr2 * 2.0 * x + 2.0 * p1 * y + 6.0 * p2 * x;
    (*J)(0, 1) = x * dradial_dr2 * 2.0 * y + 2.0 * p1 * x + 2.0 * p2 * y;
    (*J)(1, 0) = y * dradial_dr2 * 2.0 * x + 2.0 * p1 * x + 2.0 * p2 * y;
    (*J)(1, 1) = radial + y * dradial_dr2 * 2.0 * y + 6.0 * p1 * y + 2.0 * p2 * x;
  }
  return out;
}

Eigen::Vector2d RadTanCamera::distort(const Eigen::Vector2d& xy) const {
  const Eigen::Vector2d d = distort_normalized(xy, nullptr);
  return {fu() * d.x() + cu(), fv() * d.y() + cv()};
}

Eigen::Matrix2d RadTanCamera::distort_jacobian(const Eigen::Vector2d& xy) const {
  Eigen::Matrix2d J;
  distort_normalized(xy, &J);
  J.row(0) *= fu();
  J.row(1) *= fv();
  return J;
}

bool RadTanCamera::undistort(const Eigen::Vector2d& uv, Eigen::Vector2d* xy) const {
  return undistort_gauss_newton(uv, xy);
}

}  // namespace vid
