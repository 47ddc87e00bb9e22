#include "dynamics/rotation_helpers.h"

#include <cmath>

namespace vid::dynamics {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return S;
}

Eigen::Quaterniond quat_exp(const Eigen::Vector3d& theta) {
  const double angle = theta.norm();
  if (angle < 1e-12) {
    // First-order expansion; exact to machine precision at this size.
    Eigen::Quaterniond q(1.0, 0.5 * theta.x(), 0.5 * theta.y(), 0.5 * theta.z());
    return q.normalized();
  }
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, theta / angle));
}

Eigen::Vector3d rot_log(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

Eigen::Vector3d vee(const Eigen::Matrix3d& S) { return Eigen::Vector3d(S(2, 1), S(0, 2), S(1, 0)); }

}  // namespace vid::dynamics
