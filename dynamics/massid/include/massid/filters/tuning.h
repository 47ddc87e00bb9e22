#pragma once
/// @file tuning.h
/// @brief Noise model and window settings shared by the model-based mass estimators
/// (EKF, UKF, MSCKF, SWLS). Process noise is docs/model.md eq. (49)'s additive n_x as random walks on the
/// error state; measurement noise (eq. (49)'s n_y) comes from the run's RunInfo sigmas.

#include <Eigen/Core>
#include <string>

#include "massid/filters/quadrotor_mass_model.h"
#include "massid/run_data.h"

namespace vid::massid {

/// @brief Tuning of the model-based methods (documented in dynamics/massid/README.md "Methods"); defaults chosen on
/// generated loop runs (massid_diag sweeps) as the best compromise between noise and step lag.
struct ModelBasedTuning {
  double sigma_theta_rw = 0.005;   ///< attitude random walk [rad/sqrt(s)] (body-rate tracking error)
  double sigma_p_rw = 0.003;      ///< position random walk [m/sqrt(s)]
  double sigma_v_rw = 0.1;        ///< velocity random walk [m/s/sqrt(s)] (thrust error, drag)
  double sigma_m_rw_rel = 0.025;   ///< mass random walk [fraction of the initial guess / sqrt(s)]
  double sigma_m0_rel = 0.3;      ///< initial mass sigma [fraction of the initial guess]
  double min_sigma_q = 1e-3;      ///< floors when a run declares zero measurement noise
  double min_sigma_p = 1e-3;
  double min_sigma_v = 1e-3;
  bool mass_change_detection = true;  ///< inflate the mass variance on a detected step
  double change_tau_s = 0.05;     ///< detector EWMA time constant [s]
  double change_threshold = 2.5;  ///< detector threshold [EWMA standard deviations]
  double change_holdoff_s = 0.3;  ///< minimum time between detections [s]
  /// EKF/UKF: on a detection, restart from the filter this many samples back with the inflated
  /// mass variance and re-apply those samples (0: inflate at the current sample only).
  int change_rewind_samples = 5;
  /// MSCKF detector (its innovations come from a state left uncorrected for up to a window, so
  /// the faster EKF/UKF/SWLS setting raises its false alarms: 3.7 % constant-mass error).
  double msckf_change_tau_s = 0.1;
  double msckf_change_threshold = 3.0;
  double change_sigma_rel = 0.3;  ///< added mass sigma on a detection [fraction of the estimate]
  int msckf_window = 5;           ///< MSCKF: samples per window (one stacked update per window)
  int swls_window = 6;            ///< SWLS: states in the sliding window
  int swls_max_iterations = 2;    ///< SWLS: Gauss-Newton/LM iterations per new sample
  double swls_function_tolerance = 1e-6;  ///< SWLS: Ceres function (and parameter) tolerance
  /// SWLS: Ceres linear solver: dense_normal_cholesky | dense_qr | sparse_normal_cholesky
  std::string swls_linear_solver = "dense_normal_cholesky";
};

/// @brief Discrete process covariance Q (10 x 10, diagonal) for an interval dt.
QuadrotorMassModel::StateMat process_covariance(const ModelBasedTuning& t, double mass_guess,
                                                double dt);
/// @brief Measurement covariance R (9 x 9, diagonal) of a run.
Eigen::Matrix<double, 9, 9> measurement_covariance(const ModelBasedTuning& t, const RunInfo& info);
/// @brief Initial covariance P0: measurement sigmas on [theta, p, v], sigma_m0 on m.
QuadrotorMassModel::StateMat initial_covariance(const ModelBasedTuning& t, const RunInfo& info);
/// @brief Initial state: first sample's measurement and the run's initial mass guess.
QuadMassState initial_state(const RunInfo& info, const MassIdSample& first);

}  // namespace vid::massid
