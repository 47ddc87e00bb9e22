/// @file accel_noise.cpp
/// @brief Covariance matching of the accelerometer noise (accel_noise.h).
#include "vio_core/accel_noise.h"

#include <algorithm>

namespace vid {

AccelNoiseAdapter::AccelNoiseAdapter(double nominal_var, double window_samples)
    : R_nom_(nominal_var), alpha_(window_samples > 0.0 ? 1.0 / window_samples : 0.0) {
  reset();
}

void AccelNoiseAdapter::reset() {
  n_ = 0;
  mean_.setZero();
  sq_.setZero();
  R_.setConstant(R_nom_);
  e_.setConstant(R_nom_);
}

void AccelNoiseAdapter::add(const Eigen::Vector3d& r_I, const Eigen::Vector3d& S_I_diag) {
  e_ = S_I_diag - R_ + Eigen::Vector3d::Constant(R_nom_);  // H P H^T + R_nom
  if (alpha_ <= 0.0) return;
  ++n_;
  // Plain averages until the window has filled, then exponential weights.
  const double a = std::max(alpha_, 1.0 / static_cast<double>(n_));
  mean_ = (1.0 - a) * mean_ + a * r_I;
  sq_ = (1.0 - a) * sq_ + a * r_I.cwiseAbs2();
  if (static_cast<double>(n_) * alpha_ < 1.0) return;  // less than one window seen
  bool inflated = false;
  for (int i = 0; i < 3; ++i) {
    const double var = std::max(0.0, sq_(i) - mean_(i) * mean_(i));
    const bool noisy = var > 2.0 * e_(i);
    R_(i) = noisy ? R_nom_ + (var - e_(i)) : R_nom_;
    inflated = inflated || noisy;
  }
  if (inflated) ++inflated_;
}

}  // namespace vid
