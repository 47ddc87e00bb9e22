/// @file accel_noise.cpp
/// @brief Covariance matching of the accelerometer noise (accel_noise.h).
#include "vio_core/accel_noise.h"

#include <algorithm>
#include <cmath>

#include "types/median.h"

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
  excess_.setZero();
  hp_sq_window_.clear();
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
  const auto window = static_cast<std::size_t>(std::lround(1.0 / alpha_));
  if (hp_sq_window_.size() < window) {
    hp_sq_window_.push_back(hp_.cwiseAbs2());
  } else {
    hp_sq_window_[static_cast<std::size_t>(n_ - 2) % window] = hp_.cwiseAbs2();
  }
  if (static_cast<double>(n_ - 1) * alpha_ < 1.0) return;  // less than one window seen
  bool inflated = false;
  for (int i = 0; i < 3; ++i) {
    const double var = hp_sq_(i) / white_gain_;  // white-noise equivalent variance
    const bool noisy = var > kExcessRatio * e_(i);
    R_(i) = noisy ? R_nom_ + (var - e_(i)) : R_nom_;
    scratch_.clear();
    for (const Eigen::Vector3d& h : hp_sq_window_) scratch_.push_back(h(i));
    constexpr double kChi2MedianOne = 0.4549;  // median of chi2(1)
    const double var_med = upper_median(scratch_) / (kChi2MedianOne * white_gain_);
    excess_(i) = var_med > kExcessRatio * e_(i) ? var_med - e_(i) : 0.0;
    inflated = inflated || noisy;
  }
  if (inflated) ++inflated_;
}

}  // namespace vid
