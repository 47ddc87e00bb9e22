#pragma once
/// @file vio_filter.h
/// @brief The study method "vio": the VIO's own estimator core (vio_core) run on the study's
/// data, as a MassEstimator. No second model: the state is vio_core's `FilterState` in dynamics
/// mode with the thrust scale s (docs/model.md eq. (1), docs/notes/mass-state.md), propagated
/// by vio_core's `propagate` (eqs. (7)-(13)) and corrected by `ekf_update_columns` (eq. (17)).
///
/// Mapping of a study sample onto the estimator's inputs (docs/model.md eqs. (5), (8), (48)):
/// * gyro = the commanded body rate w_I, held over [t_k, t_{k+1}] (gyro0 = gyro1);
/// * thrust drive T_m = (thrust_cmd / m0) e3 in I, m0 = RunInfo::initial_mass_guess, held;
///   then s T_m = thrust_cmd / m, so m = m0 / s (eq. (48));
/// * measurement [q_WI, p_WI, v_WI] with residual [Log(q_hat^-1 q_m), p_m - p_hat, v_m - v_hat]
///   (right perturbation, docs/model.md eq. (3)) and H = I on the (theta, p, v) columns; noise
///   from RunInfo (the study filters' `measurement_covariance`).
///
/// What the study data does not have: no accelerometer (so no accelerometer update, eq. (14), no
/// force-jump test, docs/model.md §6), no camera (no clones, no visual update), no IMU biases. What is
/// left is the VIO's dynamics propagation with its force and thrust-scale states, corrected by
/// the measured pose and velocity. vio_params_for_study() says which settings differ from
/// EstimatorParams' defaults and why.

#include <memory>

#include "massid/estimator.h"
#include "massid/filters/quadrotor_mass_model.h"
#include "massid/filters/tuning.h"
#include "vio_core/estimator_params.h"
#include "vio_core/propagation.h"
#include "vio_core/state.h"

namespace vid::massid {

/// @brief EstimatorParams of the "vio" method: the defaults except
/// * force_frame = body and force_rate_random_walk = 0: the seed's body-frame random-walk force
///   (eq. (9) without the rate state); a fast force model takes every mass change as a force,
///   docs/notes/mass-state.md, and vid_run warns on that combination;
/// * thrust_scale_random_walk = 0.02 /sqrt(s) (off by default): the setting of
///   docs/notes/mass-state.md;
/// * gyro_random_walk = accel_random_walk = 0 and zero bias priors: the study has no biases, so
///   b_g and b_a stay exactly zero (their rows of P are zero).
/// Kept at their defaults: gyro_noise_density (the study's rate is exact: a small process
/// noise on the attitude), thrust_noise_density, force_random_walk (0.3 m/s^2/sqrt(s), as much as
/// the scale's 0.02 T_m: the force takes a share of every mass change, dynamics/massid/README.md), init_sigma_force,
/// init_sigma_thrust_scale (0.3, the study filters' sigma_m0_rel), use_fej (no effect here).
EstimatorParams vio_params_for_study();

/// @brief The interval input of vio_core's propagate for a study input held over dt:
/// gyro0 = gyro1 = w_I, drive0 = drive1 = (thrust_N / mass_guess) e3.
ImuInterval vio_interval(const QuadMassInput& u, double mass_guess, double dt);

/// @brief The VIO's IMU state for a study state, with s = mass_guess / m (biases, force zero).
ImuState vio_state(const QuadMassState& x, double mass_guess);

/// @brief The "vio" method. @p tuning is used only for the measurement-noise floors
/// (measurement_covariance), as by the other methods.
std::unique_ptr<MassEstimator> make_vio_estimator(const EstimatorParams& params = vio_params_for_study(),
                                                  const ModelBasedTuning& tuning = {});

}  // namespace vid::massid
