/// @file accel_noise.cpp
/// @brief Covariance matching of the accelerometer noise (accel_noise.h).
#include "vio_core/accel_noise.h"

#include <algorithm>
#include <cmath>

namespace vid {

AccelNoiseAdapter::AccelNoiseAdapter(double nominal_var, double window_s, double rate_hz)
    : R_nom_(nominal_var),
      alpha_(window_s > 0.0 && rate_hz > 0.0 ? 1.0 / (window_s * rate_hz) : 0.0),
      beta_(rate_hz > 0.0 ? 1.0 / (1.0 + 2.0 * M_PI * kHighpassHz / rate_hz) : 0.0),
      white_gain_(2.0 * beta_ * beta_ / (1.0 + beta_)) {
  reset();
}

void AccelNoiseAdapter::reset() {
  n_ = 0;
  last_r_.setZero();
  hp_.setZero();
  hp_sq_.setZero();
  R_.setConstant(R_nom_);
  e_.setConstant(R_nom_);
}

void AccelNoiseAdapter::add(const Eigen::Vector3d& r_I, const Eigen::Vector3d& S_I_diag) {
  e_ = S_I_diag - R_ + Eigen::Vector3d::Constant(R_nom_);  // H P H^T + R_nom
  if (alpha_ <= 0.0) return;
  ++n_;
  if (n_ == 1) {  // the filter starts at rest: no step from zero into the first innovation
    last_r_ = r_I;
    return;
  }
  hp_ = beta_ * (hp_ + r_I - last_r_);
  last_r_ = r_I;
  // Plain averages until the window has filled, then exponential weights. Each sample counts
  // at most kClipSigma standard deviations of what the noise in use predicts (Huber): a spike
  // (an impact, one bad sample) is the force-jump detector's, and would otherwise inflate the
  // noise for a whole window and hide the step that follows it; vibration, many samples of a
  // similar size, still raises the estimate by up to kClipSigma^2 per window.
  const double a = std::max(alpha_, 1.0 / static_cast<double>(n_ - 1));
  const Eigen::Vector3d clip2 = (kClipSigma * kClipSigma * white_gain_) * S_I_diag;
  hp_sq_ = (1.0 - a) * hp_sq_ + a * hp_.cwiseAbs2().cwiseMin(clip2);
  if (static_cast<double>(n_ - 1) * alpha_ < 1.0) return;  // less than one window seen
  bool inflated = false;
  for (int i = 0; i < 3; ++i) {
    const double var = hp_sq_(i) / white_gain_;  // white-noise equivalent variance
    const bool noisy = var > 2.0 * e_(i);
    R_(i) = noisy ? R_nom_ + (var - e_(i)) : R_nom_;
    inflated = inflated || noisy;
  }
  if (inflated) ++inflated_;
}

}  // namespace vid
