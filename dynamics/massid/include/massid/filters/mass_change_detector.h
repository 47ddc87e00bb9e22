#pragma once
/// @file mass_change_detector.h
/// @brief Detects an abrupt mass change (payload drop / pick-up) from the velocity innovation
/// along the thrust axis: a mass error biases the predicted acceleration along z_I, so the
/// normalized innovation nu = z_W^T (v_meas - v_pred) / sigma stops being zero-mean. An
/// exponentially weighted mean of nu (time constant tau) beyond `threshold` times its
/// white-noise standard deviation triggers; the caller then inflates the mass variance so the
/// filter re-converges fast (a small mass random walk keeps the estimate quiet in between).

#include <Eigen/Core>

#include "massid/filters/quadrotor_mass_model.h"

namespace vid::massid {

/// @brief EWMA change detector on a normalized innovation.
class MassChangeDetector {
 public:
  MassChangeDetector(double tau_s = 0.15, double threshold = 4.0, double holdoff_s = 0.5)
      : tau_s_(tau_s), threshold_(threshold), holdoff_s_(holdoff_s) {}
  /// @brief Feed the normalized innovation nu at time t over step dt; true on a detection.
  bool update(double t, double dt, double nu);
  void reset() { mean_ = 0.0; last_fire_t_ = -1e300; }

 private:
  double tau_s_, threshold_, holdoff_s_;
  double mean_ = 0.0;
  double last_fire_t_ = -1e300;
};

/// @brief nu = z_W^T (v_meas - v_pred) / sqrt(z_W^T P_vv z_W + sigma_v^2), z_W = R_WI e3.
double thrust_axis_innovation(const QuadMassState& x_pred, const Eigen::Matrix3d& P_vv,
                              const Eigen::Vector3d& v_meas_W, double sigma_v);

}  // namespace vid::massid
