/// @file so3.cpp
/// @brief SO(3) / quaternion maps with series expansions near 0 and a quaternion-based
/// logarithm that stays accurate near pi.
#include "geometry/so3.h"

#include <cmath>

namespace vid::so3 {
namespace {
// Below this angle the closed forms lose digits to cancellation; the series terms
// kept are exact to well below double precision there.
constexpr double kSmallAngle = 1e-4;
}  // namespace

Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d W;
  W << 0.0, -w.z(), w.y(),  //
      w.z(), 0.0, -w.x(),   //
      -w.y(), w.x(), 0.0;
  return W;
}

Eigen::Vector3d vee(const Eigen::Matrix3d& W) {
  return 0.5 * Eigen::Vector3d(W(2, 1) - W(1, 2), W(0, 2) - W(2, 0), W(1, 0) - W(0, 1));
}

Eigen::Matrix3d exp(const Eigen::Vector3d& phi) {
  const double theta2 = phi.squaredNorm();
  const double theta = std::sqrt(theta2);
  const Eigen::Matrix3d W = skew(phi);
  double a;  // sin(t)/t
  double b;  // (1-cos(t))/t^2
  if (theta < kSmallAngle) {
    a = 1.0 - theta2 / 6.0 + theta2 * theta2 / 120.0;
    b = 0.5 - theta2 / 24.0 + theta2 * theta2 / 720.0;
  } else {
    a = std::sin(theta) / theta;
    // 2 sin^2(t/2) avoids the cancellation of 1 - cos(t).
    const double s = std::sin(0.5 * theta);
    b = 2.0 * s * s / theta2;
  }
  return Eigen::Matrix3d::Identity() + a * W + b * W * W;
}

Eigen::Quaterniond quat_exp(const Eigen::Vector3d& phi) {
  const double theta2 = phi.squaredNorm();
  const double theta = std::sqrt(theta2);
  double k;  // sin(t/2)/t
  double c;
  if (theta < kSmallAngle) {
    k = 0.5 - theta2 / 48.0 + theta2 * theta2 / 3840.0;
    c = 1.0 - theta2 / 8.0 + theta2 * theta2 / 384.0;
  } else {
    k = std::sin(0.5 * theta) / theta;
    c = std::cos(0.5 * theta);
  }
  Eigen::Quaterniond q(c, k * phi.x(), k * phi.y(), k * phi.z());
  q.normalize();
  return q;
}

Eigen::Vector3d quat_log(const Eigen::Quaterniond& q_in) {
  Eigen::Quaterniond q = q_in.normalized();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const Eigen::Vector3d v = q.vec();
  const double s = v.norm();  // sin(t/2)
  const double w = q.w();     // cos(t/2) >= 0
  if (s < kSmallAngle) {
    // t = 2 atan(s/w), t/s = 2/w (1 - s^2/(3 w^2) + ...); w ~ 1 here.
    const double r2 = (s * s) / (w * w);
    return (2.0 / w) * (1.0 - r2 / 3.0 + r2 * r2 / 5.0) * v;
  }
  // atan2 is well conditioned also at w -> 0 (angle -> pi).
  const double theta = 2.0 * std::atan2(s, w);
  return (theta / s) * v;
}

Eigen::Vector3d log(const Eigen::Matrix3d& R) {
  // Eigen's matrix->quaternion uses the largest-diagonal branch near pi (Shepperd).
  return quat_log(Eigen::Quaterniond(R));
}

Eigen::Matrix3d right_jacobian(const Eigen::Vector3d& phi) {
  const double theta2 = phi.squaredNorm();
  const double theta = std::sqrt(theta2);
  const Eigen::Matrix3d W = skew(phi);
  double a;  // (1-cos t)/t^2
  double b;  // (t - sin t)/t^3
  if (theta < kSmallAngle) {
    a = 0.5 - theta2 / 24.0 + theta2 * theta2 / 720.0;
    b = 1.0 / 6.0 - theta2 / 120.0 + theta2 * theta2 / 5040.0;
  } else {
    const double s = std::sin(0.5 * theta);
    a = 2.0 * s * s / theta2;
    b = (theta - std::sin(theta)) / (theta2 * theta);
  }
  return Eigen::Matrix3d::Identity() - a * W + b * W * W;
}

Eigen::Matrix3d left_jacobian(const Eigen::Vector3d& phi) { return right_jacobian(-phi); }

Eigen::Matrix3d right_jacobian_inv(const Eigen::Vector3d& phi) {
  const double theta2 = phi.squaredNorm();
  const double theta = std::sqrt(theta2);
  const Eigen::Matrix3d W = skew(phi);
  double c;  // 1/t^2 - cot(t/2)/(2t)
  if (theta < kSmallAngle) {
    c = 1.0 / 12.0 + theta2 / 720.0 + theta2 * theta2 / 30240.0;
  } else {
    const double half = 0.5 * theta;
    c = 1.0 / theta2 - std::cos(half) / (2.0 * theta * std::sin(half));
  }
  return Eigen::Matrix3d::Identity() + 0.5 * W + c * W * W;
}

Eigen::Matrix3d left_jacobian_inv(const Eigen::Vector3d& phi) { return right_jacobian_inv(-phi); }

Eigen::Quaterniond boxplus(const Eigen::Quaterniond& q, const Eigen::Vector3d& delta) {
  return (q * quat_exp(delta)).normalized();
}

Eigen::Vector3d boxminus(const Eigen::Quaterniond& q1, const Eigen::Quaterniond& q0) {
  return quat_log(q0.conjugate() * q1);
}

Eigen::Quaterniond normalized(const Eigen::Quaterniond& q) {
  Eigen::Quaterniond n = q.normalized();
  if (n.w() < 0.0) n.coeffs() = -n.coeffs();
  return n;
}

Eigen::Matrix3d orthonormalized(const Eigen::Matrix3d& R) {
  return Eigen::Quaterniond(R).normalized().toRotationMatrix();
}

}  // namespace vid::so3
