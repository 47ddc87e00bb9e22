#pragma once
/// @file estimator_params.h
/// @brief Every estimator setting with its default. Plain data (loaded by io's strict YAML
/// loader; field names are the YAML keys).

#include <string>

#include "types/calibration.h"

namespace vid {

/// @brief What drives the propagation (docs/design.md §1).
enum class PropagationMode {
  kImu,       ///< accelerometer + gyro drive propagation (classic VIO)
  kDynamics,  ///< gyro + thrust drive propagation; accelerometer is a measurement
};

/// @brief How the filter state is initialised.
enum class InitMode {
  kStatic,       ///< gravity-aligned from averaged accelerometer over a still/hover window
  kGroundTruth,  ///< from the first ground-truth sample (evaluation only)
  kAuto,         ///< the still/hover window when there is one, in flight from stereo frames otherwise
};

/// @brief Frame in which the external-force state F_ext lives and follows its random walk.
/// Outputs always give the force in both frames.
enum class ForceFrame {
  kBody,   ///< F_ext in I (docs/model.md eq. (14)): turns with the vehicle, a yaw turn moves all of it
  kWorld,  ///< F_ext in W: ropes, wind and payload weight stay put while the vehicle yaws
};

/// @brief "imu" / "dynamics".
std::string to_string(PropagationMode mode);
/// @brief Parse "imu" / "dynamics"; throws std::invalid_argument naming the value.
PropagationMode mode_from_string(const std::string& s);
/// @brief "body" / "world".
std::string to_string(ForceFrame frame);
/// @brief Parse "body" / "world"; throws std::invalid_argument naming the value.
ForceFrame force_frame_from_string(const std::string& s);
/// @brief "static" / "groundtruth" / "auto".
std::string to_string(InitMode mode);
/// @brief Parse "static" / "groundtruth" / "auto"; throws std::invalid_argument naming the value.
InitMode init_mode_from_string(const std::string& s);

/// @brief All estimator settings. Units SI; noise densities are continuous-time.
struct EstimatorParams {
  // --- mode and window ---
  PropagationMode mode = PropagationMode::kDynamics;  ///< what drives the propagation (without the key: dynamics when rotor speeds or thrust exist)
  int window_size = 11;         ///< number of stochastic clones kept (max clones)
  bool use_fej = true;          ///< first-estimates Jacobians for observability consistency
  /// magnitude [m/s^2], g_W = [0, 0, -gravity]; a preset's vehicle.yaml gives it (system/config.cpp)
  double gravity = kDefaultGravity;

  // --- IMU noise (Kalibr/EuRoC continuous-time) ---
  // A preset's or dataset's IMU calibration gives them (system/config.cpp); the defaults are the
  // calibration's (types/calibration.h), one default per quantity.
  double gyro_noise_density = ImuNoise{}.gyro_noise_density;    ///< rad/s/sqrt(Hz)
  double gyro_random_walk = ImuNoise{}.gyro_random_walk;        ///< rad/s^2/sqrt(Hz)
  double accel_noise_density = ImuNoise{}.accel_noise_density;  ///< m/s^2/sqrt(Hz)
  double accel_random_walk = ImuNoise{}.accel_random_walk;      ///< m/s^3/sqrt(Hz)
  double imu_rate_hz = ImuNoise{}.rate_hz;  ///< nominal rate, used to discretize the accel measurement noise

  // --- dynamics model ---
  double thrust_noise_density = 0.05;    ///< mass-normalized thrust noise [m/s^2/sqrt(Hz)]
  // Force process model of a real vehicle: everything the thrust model misses (rotor drag, blade
  // flapping, motor transients) is "external force" and varies fast. On the Blackbird real
  // flight (0.3, 1.0) keeps the force NEES in the 95 % band 91 % of the time (the simulator's
  // (0.02, 0.3): 44 %, body force 0.186 -> 0.139 m/s^2). The simulator's vehicle has exact
  // thrust and smooth rope forces: config/sim sets (0.02, 0.5) (world force RMSE 0.130 / 0.206
  // on full-length vid17/vid18_like with (0.02, 0.3); docs/notes/force-accuracy.md,
  // docs/notes/real-sensors.md).
  double force_random_walk = 0.3;        ///< F_ext random walk [m/s^3/sqrt(Hz)]
  ForceFrame force_frame = ForceFrame::kWorld;  ///< frame of the F_ext state
  /// > 0 adds the force rate dF_ext/dt to the state, driven by this random walk
  /// [m/s^4/sqrt(Hz)] (integrated random walk: ramps are followed without lag); 0 = off.
  double force_rate_random_walk = 1.0;
  /// > 0 adds the thrust scale s to the state (a = s T_m + F_ext + b_a: s = m0 k / (m k0), a
  /// payload picked up or dropped, or a thrust coefficient off; mass and coefficient scale are
  /// one observable), driven by this random walk [1/sqrt(s)]; 0 = off. docs/notes/mass-state.md.
  double thrust_scale_random_walk = 0.0;
  /// Rotor telemetry latency [s]: a rotor / thrust sample stamped t is the thrust at t - delay
  /// (it reaches the estimator that much later; the IMU waits for it up to rotor_gap_s).
  double thrust_delay_s = 0.0;
  double rotor_gap_s = 0.05;             ///< no rotor sample for longer -> hold last thrust
  double rotor_gap_noise_scale = 10.0;   ///< thrust noise multiplier while holding

  // --- IMU gaps ---
  double imu_gap_s = 0.05;               ///< larger step -> hold last sample, inflate noise
  double imu_gap_noise_scale = 10.0;     ///< gyro/accel/thrust noise multiplier over a gap

  // --- accelerometer update (dynamics mode) ---
  bool accel_update = true;              ///< update with every accelerometer sample
  /// Window [s] of the vibration-aware accelerometer noise (vio_core/accel_noise.h; 100 samples at
  /// 400 Hz: a consistent filter never reaches the 2x threshold, a 1-3 s burst does in ~0.1 s): where the
  /// innovations' power above 10 Hz over it (each sample clipped at 3 sigma) exceeds twice what
  /// accel_noise_density predicts (rotor vibration, bursts), the excess is added to the
  /// measurement noise; slower innovations are a force being followed, not noise. 0 = off.
  double accel_noise_window_s = 0.25;
  bool accel_chi2_gating = true;         ///< gate each accelerometer sample at the 99% chi2(3) quantile
  double accel_chi2_multiplier = 1.0;    ///< multiplies the 99% chi2(3) threshold
  /// A sample past the gate is applied down-weighted (its innovation covariance scaled so its
  /// chi2 sits at the gate: influence bounded, nothing dropped) instead of rejected. With a
  /// Gaussian accelerometer the 99% gate otherwise throws away 1% of good samples, on the
  /// ground and in flight alike; a true spike still moves the state no more than a sample at
  /// the gate. docs/notes/accel-gate.md.
  bool accel_gate_downweight = true;
  // Abrupt forces (vio_core/force_jump.h): GLR step test on the accelerometer innovations over
  // the last 2 .. force_jump_window samples; a detection re-estimates F from them.
  bool force_jump_detection = true;      ///< detect abrupt force changes and re-estimate F from the window
  double force_jump_threshold = 30.0;    ///< GLR statistic (chi2(3); P(> 30) ~ 1.4e-6 per test)
  double force_jump_split_sigma = 2.0;   ///< each half of the window carries the step at >= this [sigma]
  int force_jump_window = 64;            ///< longest window [samples] (160 ms at 400 Hz)
  /// Smallest step [m/s^2] treated as a jump; smaller ones are followed by the force(-rate)
  /// random walk. 0 = any size. On the Blackbird real flight every one of its 361 "jumps"
  /// (0.13-0.56 m/s^2) was rotor vibration or thrust-model error; the presets' steps are >= 2
  /// m/s^2 and no ideal preset changes with 1.0 (docs/notes/real-sensors.md).
  double force_jump_min_step = 1.0;
  // Flight phase (vio_core/flight_phase.h): landed while the estimated upward external force
  // (the ground reaction) carries at least this fraction of the weight, airborne below the
  // second one; a change must hold flight_phase_hold_s.
  double landed_weight_fraction = 0.5;   ///< landed once the upward external force carries this fraction of the weight
  double airborne_weight_fraction = 0.25;  ///< airborne once it falls below this fraction (< landed_weight_fraction)
  double flight_phase_hold_s = 0.1;      ///< [s]

  // --- fixed-lag smoothing (dynamics mode; docs/notes/smoothing.md) ---
  /// > 0: stochastic clones of F_ext are kept in the state for this lag [s] and corrected by
  /// every later accelerometer and visual update through their cross-covariances (a Kalman
  /// filter on the augmented state is the fixed-lag smoother of those times); the smoothed
  /// estimate of a clone's time is output when it leaves the window. The causal estimate is
  /// unchanged. 0 = off (the default).
  double smoother_lag_s = 0.0;
  /// A force clone is taken at the first camera frame at least this long [s] after the
  /// previous one (memory and time grow with lag / period clones of 3 states); smoothed
  /// outputs between clone times interpolate the clones' corrections.
  double smoother_clone_period_s = 0.1;

  // --- visual update ---
  bool visual_update = true;             ///< MSCKF updates from the camera features (false: inertial/dynamics only)
  double pixel_noise_px = 1.0;           ///< observation noise [px] (divided by focal length)
  double chi2_multiplier = 1.0;          ///< multiplies the 95% chi2 threshold per feature
  int min_track_length = 3;              ///< observations needed to use a feature
  int max_features_per_update = 60;      ///< cap per camera frame (0 = no cap)
  bool use_stereo = true;                ///< use cam1 (stereo features) when the calibration has it
  /// Compress the stacked visual system through H^T H (block-structured, ~2.4x faster than
  /// the Householder QR of the stacked rows; both give the same EKF update).
  bool msckf_normal_equations = true;
  /// Triangulation gate on cond(midpoint normal matrix) ~ (depth / baseline)^2; 1e6 keeps
  /// stereo-only (hover) features up to ~1000 baselines deep, chi2 gating catches the rest.
  double triangulation_max_condition = 1e6;

  // --- zero-velocity update (one camera, or landed; vio_core/zero_velocity.h) ---
  /// With use_stereo false: when the median rotation-compensated parallax of cam0's features
  /// between the oldest clone and now (>= 0.25 s apart, >= 20 features) is below this [px],
  /// apply v_WI = 0; 0 = off. 1.5 px is above the parallax of pixel noise on still features
  /// (median 1.66 sigma: 0.8 px at 0.5 px) and is what 2 cm/s shows over 0.5 s at 3 m depth
  /// (f = 450 px); deeper scenes hide faster motion. Stereo sees depth in every frame and
  /// uses it only while landed (below).
  double zero_velocity_max_parallax_px = 1.5;
  double zero_velocity_sigma = 0.02;     ///< [m/s] per axis
  /// While the flight phase is landed (flight_phase.h: the ground carries at least half the
  /// weight), the same parallax test applies v_WI = 0 with this sigma [m/s], with one camera or
  /// two: through the dynamics the zero velocity pins the ground reaction to F = -T - R^T g
  /// while the rotors spin up or down. 0 = off. A tighter 0.005 m/s (what a vehicle on its legs
  /// really moves) gains 30 % on the landed force but makes the tilt / accelerometer-bias pair
  /// overconfident on the ground and costs up to 2x airborne force error after lift-off
  /// (docs/notes/flight-phase.md).
  double landed_zero_velocity_sigma = 0.02;

  // --- health (vio_core/health_monitor.h) ---
  /// Window [s] over which the visual chi2 gate's rejections are counted.
  double health_window_s = 1.0;
  /// Diverged when at least this fraction of the features tested in the window fail the 95 %
  /// gate (a consistent filter: ~5 %; a stereo calibration 1 deg off: 0.86); 0 = off, the
  /// default: on rendered images a rope snap or a force step makes a healthy filter reject
  /// 0.75-0.77 for a moment (it recovers), so no fixed fraction separates the two yet.
  double health_max_chi2_rejected_fraction = 0.0;
  /// ... and at least this many features were tested in the window (a fraction of few says little).
  int health_min_tested_features = 30;
  /// Starving after this long [s] without a feature track reaching an update while frames
  /// arrive; 0 = off.
  double health_starvation_s = 1.0;

  // --- initialization ---
  /// auto: the still/hover window when there is one, in flight from init_dynamic_window_s of
  /// stereo frames otherwise; static: only the window; groundtruth: evaluation only.
  /// docs/notes/initialization.md.
  InitMode init_mode = InitMode::kAuto;
  double init_window_s = 0.5;            ///< averaging window for static/hover init
  /// The still/hover test judges the spread of init_lowpass_s moving averages of the samples
  /// (removes rotor vibration, keeps motion below ~1 / (2 init_lowpass_s) Hz); 0: raw samples [s].
  double init_lowpass_s = 0.1;
  double init_accel_std_max = 0.3;       ///< low-passed accel std beyond the white noise above this -> moving [m/s^2]
  double init_gyro_std_max = 0.05;       ///< low-passed gyro std beyond the white noise [rad/s]
  double init_dynamic_window_s = 1.0;    ///< in-flight initialization: window of stereo frames [s]
  /// ... of mono frames [s]: one camera's scale comes from the accelerometer, which needs the
  /// motion's acceleration to stand out of its noise over the window.
  double init_dynamic_window_mono_s = 2.0;
  int init_dynamic_min_features = 15;    ///< ... and the tracks it needs through the window
  double init_gravity_tolerance = 0.5;   ///< | |a_mean| - g | must stay below [m/s^2]
  double init_freefall_thrust_ratio = 0.3;  ///< T/m below ratio*g with |a| small -> free fall
  double init_sigma_roll_pitch = 0.02;   ///< [rad]
  double init_sigma_yaw = 1e-4;          ///< [rad] (yaw is unobservable: fixed gauge)
  double init_sigma_position = 1e-4;     ///< [m]  (position is unobservable: fixed gauge)
  double init_sigma_velocity = 0.05;     ///< [m/s]
  double init_sigma_gyro_bias = 0.01;    ///< [rad/s]
  double init_sigma_accel_bias = 0.1;    ///< [m/s^2]
  double init_sigma_force = 0.5;         ///< [m/s^2]
  double init_sigma_force_rate = 0.5;    ///< [m/s^3] (with force_rate_random_walk > 0)
  double init_sigma_thrust_scale = 0.3;  ///< [-] (with thrust_scale_random_walk > 0)
  /// > 0 estimates the camera-IMU time offset t_d (t_imu = t_cam + t_d) online, starting from
  /// cam0's calibrated timeshift_cam_imu with this sigma [s]; 0: t_d fixed at the calibration's
  /// value. While estimated, every frame waits 0.4 s for the gyro samples after it (outputs come
  /// that much later). docs/notes/time-offset.md.
  double init_sigma_time_offset = 0.0;
  /// 1-sigma noise of each frame's timestamp against the IMU clock [s] (trigger / exposure
  /// jitter, independent per frame): the pose change over it is added to every clone as noise.
  /// docs/notes/time-offset.md.
  double camera_time_jitter = 0.0;

  // --- divergence detection ---
  double max_velocity = 50.0;            ///< |v| above this [m/s] -> diverged
  double max_position_sigma = 100.0;     ///< 1-sigma position above this [m] -> diverged
};

}  // namespace vid
