/// @file mass_change_detector.cpp
/// @brief EWMA detector of abrupt mass changes (see header).
#include "massid/filters/mass_change_detector.h"

#include <algorithm>
#include <cmath>

namespace vid::massid {

bool MassChangeDetector::update(double t, double dt, double nu) {
  const double a = std::clamp(dt / tau_s_, 1e-6, 1.0);
  mean_ = (1.0 - a) * mean_ + a * nu;
  // Stationary std of the EWMA of white unit-variance input: sqrt(a / (2 - a)).
  const double sigma = std::sqrt(a / (2.0 - a));
  if (t - last_fire_t_ < holdoff_s_ || std::abs(mean_) <= threshold_ * sigma) return false;
  last_fire_t_ = t;
  mean_ = 0.0;
  return true;
}

double thrust_axis_innovation(const QuadMassState& x_pred, const Eigen::Matrix3d& P_vv,
                              const Eigen::Vector3d& v_meas_W, double sigma_v) {
  const Eigen::Vector3d z_W = x_pred.q_WI * Eigen::Vector3d::UnitZ();
  const double var = z_W.dot(P_vv * z_W) + sigma_v * sigma_v;
  return z_W.dot(v_meas_W - x_pred.v_WI) / std::sqrt(var);
}

}  // namespace vid::massid
