/// @file initializer.cpp
/// @brief Static / hover initialization.
#include "vio_core/initializer.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "geometry/so3.h"

namespace vid {

Eigen::Quaterniond gravity_aligned_orientation(const Eigen::Vector3d& f_I) {
  // Body z expressed in W must map f_I to +z_W; build R_WI rows: the world z axis in body
  // coordinates is f_I normalized; pick world x as body x projected orthogonally (yaw 0).
  const Eigen::Vector3d z_in_I = f_I.normalized();
  Eigen::Vector3d x_in_I = Eigen::Vector3d::UnitX() - z_in_I.x() * z_in_I;
  if (x_in_I.norm() < 1e-6) x_in_I = Eigen::Vector3d::UnitY() - z_in_I.y() * z_in_I;
  x_in_I.normalize();
  const Eigen::Vector3d y_in_I = z_in_I.cross(x_in_I);
  Eigen::Matrix3d R_IW;
  R_IW.col(0) = x_in_I;
  R_IW.col(1) = y_in_I;
  R_IW.col(2) = z_in_I;
  return so3::normalized(Eigen::Quaterniond(R_IW.transpose()));
}

ImuState state_from_groundtruth(const GroundTruthSample& gt) {
  ImuState x;
  x.T_WI = gt.T_WI;
  x.v_WI = gt.v_WI;
  x.b_g = gt.b_g;
  x.b_a = gt.b_a;
  return x;
}

Eigen::MatrixXd initial_covariance(const EstimatorParams& p, const Eigen::Quaterniond& q_WI) {
  const ImuLayout layout = ImuLayout::from(p);
  const bool dyn = layout.force;
  const bool rate = layout.force_rate;
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(layout.dim(), layout.dim());
  // World-frame orientation covariance diag(rp, rp, yaw) -> body right perturbation R^T C R.
  const Eigen::Matrix3d R = q_WI.toRotationMatrix();
  const Eigen::Vector3d s(p.init_sigma_roll_pitch, p.init_sigma_roll_pitch, p.init_sigma_yaw);
  P.block<3, 3>(imu_idx::kTheta, imu_idx::kTheta) =
      R.transpose() * s.cwiseAbs2().asDiagonal() * R;
  P.block<3, 3>(imu_idx::kP, imu_idx::kP).diagonal().setConstant(std::pow(p.init_sigma_position, 2));
  P.block<3, 3>(imu_idx::kV, imu_idx::kV).diagonal().setConstant(std::pow(p.init_sigma_velocity, 2));
  P.block<3, 3>(imu_idx::kBg, imu_idx::kBg).diagonal().setConstant(std::pow(p.init_sigma_gyro_bias, 2));
  P.block<3, 3>(imu_idx::kBa, imu_idx::kBa).diagonal().setConstant(std::pow(p.init_sigma_accel_bias, 2));
  if (dyn) {
    P.block<3, 3>(imu_idx::kF, imu_idx::kF).diagonal().setConstant(std::pow(p.init_sigma_force, 2));
  }
  if (rate) {
    // The force rate lives in the force's frame; a world-frame rate is isotropic anyway.
    P.block<3, 3>(imu_idx::kFdot, imu_idx::kFdot).diagonal().setConstant(std::pow(p.init_sigma_force_rate, 2));
  }
  if (layout.thrust_scale) {
    // The calibration's mass and thrust coefficients are the prior: s = 1.
    const int is = layout.thrust_scale_index();
    P(is, is) = p.init_sigma_thrust_scale * p.init_sigma_thrust_scale;
  }
  return P;
}

namespace {
// Sum over the three axes of the variance of the nb-sample moving average of `field`.
template <class S>
double lowpassed_variance(const std::deque<S>& w, Eigen::Vector3d S::*field, int nb) {
  std::vector<Eigen::Vector3d> avg;
  avg.reserve(w.size() - nb + 1);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < w.size(); ++i) {
    sum += w[i].*field;
    if (i + 1 >= static_cast<std::size_t>(nb)) {
      avg.push_back(sum / nb);
      sum -= w[i + 1 - nb].*field;
    }
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& v : avg) mean += v / static_cast<double>(avg.size());
  double var = 0.0;
  for (const auto& v : avg) var += (v - mean).squaredNorm() / static_cast<double>(avg.size());
  return var;
}
}  // namespace

std::optional<InitResult> StaticInitializer::add(TimeNs t_ns, const Eigen::Vector3d& gyro,
                                                 const Eigen::Vector3d& accel,
                                                 const Eigen::Vector3d& T_m) {
  window_.push_back({t_ns, gyro, accel, T_m});
  const auto span = static_cast<TimeNs>(params_.init_window_s * 1e9);
  while (window_.size() > 1 && window_.back().t - window_[1].t >= span) window_.pop_front();
  if (window_.back().t - window_.front().t < span) return std::nullopt;

  const double n = static_cast<double>(window_.size());
  Eigen::Vector3d w_mean = Eigen::Vector3d::Zero(), a_mean = Eigen::Vector3d::Zero(),
                  T_mean = Eigen::Vector3d::Zero();
  for (const Sample& s : window_) {
    w_mean += s.w / n;
    a_mean += s.a / n;
    T_mean += s.T / n;
  }
  // Band-limited spread: rotor vibration (88 / 175 Hz lines, broadband 0.08 rad/s per gyro axis
  // on a real 400 Hz IMU in hover) is far above any motion threshold sample by sample, while
  // motion lives below a few Hz. A moving average over init_lowpass_s (first null at
  // 1/init_lowpass_s) removes the vibration and keeps the motion; 0: raw samples.
  const double rate_hz = (n - 1.0) / ns_to_s(window_.back().t - window_.front().t);
  const int nb = std::clamp(static_cast<int>(std::lround(params_.init_lowpass_s * rate_hz)), 1,
                            static_cast<int>(window_.size()));
  const double a_var = lowpassed_variance(window_, &Sample::a, nb);
  const double w_var = lowpassed_variance(window_, &Sample::w, nb);
  const double g = params_.gravity;
  // Stillness is judged on the variance in excess of the sensors' own white noise (after the
  // average: density^2 * rate / nb per axis; with noisy IMUs, e.g. 0.1 m/s^2/sqrt(Hz) at 400 Hz,
  // it is 2 m/s^2 per raw sample). The allowance is the expected noise variance (3 axes) plus
  // three standard deviations of its estimate from n / nb independent averages.
  const double m = std::max(1.0, n / nb);
  const auto allowed_var = [&](double density, double motion_std) {
    const double noise_var = 3.0 * density * density * rate_hz / nb;
    return noise_var * (1.0 + 3.0 * std::sqrt(2.0 / (3.0 * m))) + motion_std * motion_std;
  };
  if (a_var > allowed_var(params_.accel_noise_density, params_.init_accel_std_max)) {
    reason_ = "accelerometer not still (low-passed std " + std::to_string(std::sqrt(a_var)) + " m/s^2)";
    return std::nullopt;
  }
  if (w_var > allowed_var(params_.gyro_noise_density, params_.init_gyro_std_max)) {
    reason_ = "gyro not still (low-passed std " + std::to_string(std::sqrt(w_var)) + " rad/s)";
    return std::nullopt;
  }
  // A constant turn has no spread at all (fast_yaw's 3 rad/s yaw passed the spread tests and
  // became a 3 rad/s "gyro bias"): the window's mean rate is the bias estimate, so it must be a
  // gyro bias a MEMS IMU can have. The gyro alone cannot tell a slow turn from a bias, so the
  // bound is the larger of a plausible bias (0.2 rad/s, ~11 deg/s; euroc_like's IMU has 0.077)
  // and 3 init_sigma_gyro_bias plus the noise of a mean over n samples.
  constexpr double kPlausibleGyroBias = 0.2;  // rad/s
  const double w_mean_max = std::max(kPlausibleGyroBias,
                                     3.0 * (params_.init_sigma_gyro_bias +
                                            params_.gyro_noise_density * std::sqrt(params_.imu_rate_hz / n)));
  if (w_mean.cwiseAbs().maxCoeff() > w_mean_max) {
    reason_ = "turning (mean gyro " + std::to_string(w_mean.norm()) + " rad/s, more than a gyro bias can be)";
    return std::nullopt;
  }
  if (params_.mode == PropagationMode::kDynamics && a_mean.norm() < params_.init_freefall_thrust_ratio * g &&
      T_mean.norm() < params_.init_freefall_thrust_ratio * g) {
    reason_ = "free fall (no thrust, no specific force)";
    return std::nullopt;
  }
  if (std::abs(a_mean.norm() - g) > params_.init_gravity_tolerance) {
    reason_ = "vehicle accelerating (|a| differs from g)";
    return std::nullopt;
  }
  InitResult r;
  r.t_ns = window_.back().t;
  r.x.T_WI.q = gravity_aligned_orientation(a_mean);
  r.x.b_g = w_mean;
  if (params_.mode == PropagationMode::kDynamics) {
    // Hover: a ≈ T_m (F_ext ≈ 0); resting on ground: the support is an external force.
    set_force_from_body(r.x, params_.force_frame, a_mean - T_mean);
  }
  r.P = initial_covariance(params_, r.x.T_WI.q);
  return r;
}

}  // namespace vid
