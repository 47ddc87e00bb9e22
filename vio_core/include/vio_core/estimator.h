#pragma once
/// @file estimator.h
/// @brief The estimator: consumes time-ordered measurements (IMU, rotor speeds or
/// thrust, feature frames; ground truth only with InitMode::kGroundTruth), runs
/// initialization, propagation, accelerometer updates, MSCKF visual updates and clone
/// marginalization, and emits IMU-rate estimates plus per-frame stage timings.
/// Single-threaded and deterministic (timings aside).
///
/// Stream handling (documented behaviour):
/// * dynamics mode: an IMU sample is processed once thrust is known at its time (a rotor or
///   thrust sample at or after it), or once the stream has moved rotor_gap_s past it; then
///   the last thrust is held and the thrust noise is inflated by rotor_gap_noise_scale
///   (counted in EstimatorCounters::rotor_gap_samples).
/// * IMU gap (step > imu_gap_s): the interval is integrated in sub-steps of at most 10 ms
///   with inputs interpolated linearly between the samples around the gap and all IMU/thrust
///   noises inflated by imu_gap_noise_scale (counted in imu_gaps).
/// * camera dropout: nothing special; propagation and accelerometer updates continue.
/// * frames are processed when the IMU has reached their time (inputs interpolated).

#include <Eigen/Core>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "types/calibration.h"
#include "types/measurements.h"
#include "vio_core/accel_noise.h"
#include "vio_core/dynamic_initializer.h"
#include "vio_core/estimator_counters.h"
#include "vio_core/estimator_outputs.h"
#include "vio_core/estimator_params.h"
#include "vio_core/flight_phase.h"
#include "vio_core/force_jump.h"
#include "vio_core/health_monitor.h"
#include "vio_core/initializer.h"
#include "vio_core/rate_fit.h"
#include "vio_core/state.h"
#include "vio_core/thrust_buffer.h"
#include "vio_core/zero_velocity.h"

namespace vid {
class FixedLagOutput;
class VisualUpdater;
namespace msckf {
class FeatureDatabase;
struct ClonePose;
}

/// @brief Everything the estimator needs besides the measurements.
struct EstimatorConfig {
  EstimatorParams params;
  VehicleParams vehicle;              ///< mass and rotor thrust coefficients (dynamics mode)
  std::vector<CameraCalib> cameras;   ///< by cam_id (T_IC, intrinsics for the pixel noise)
};

/// @brief The estimator.
class Estimator {
 public:
  explicit Estimator(EstimatorConfig config);
  ~Estimator();
  Estimator(const Estimator&) = delete;
  Estimator& operator=(const Estimator&) = delete;

  void set_estimate_callback(std::function<void(const EstimateOutput&)> cb) { on_estimate_ = std::move(cb); }
  void set_frame_callback(std::function<void(const FrameTimings&)> cb) { on_frame_ = std::move(cb); }
  /// @brief With smoother_lag_s > 0 (dynamics mode): every IMU-rate estimate again, smoothed
  /// (docs/notes/smoothing.md), about smoother_lag_s + smoother_clone_period_s
  /// after its time (the rest at finish()). Fields as the causal estimate's; x.F_ext, T_WI,
  /// F_ext_I/W and cov_F_I/W carry the smoothed values.
  void set_smoothed_callback(std::function<void(const EstimateOutput&)> cb) { on_smoothed_ = std::move(cb); }
  /// @brief At an in-flight initialization, before its first estimate: the window's earlier
  /// frame poses in the new world frame (InitResult::window_poses).
  void set_init_window_callback(std::function<void(const std::vector<TimedPose>&)> cb) {
    on_init_window_ = std::move(cb);
  }

  /// @brief Feed the next measurement (non-decreasing time). Ground truth, force, mass and
  /// image measurements are ignored (ground truth is used only by InitMode::kGroundTruth).
  void push(const Measurement& m);
  /// @brief Process everything still queued (end of stream).
  void finish();

  /// @brief Initialize explicitly (e.g. from ground truth); replaces any running state.
  void initialize(TimeNs t_ns, const ImuState& x, const Eigen::MatrixXd& P_imu);

  FilterStatus status() const { return status_; }
  /// @brief Landed / airborne now (unknown before initialization and in imu mode).
  FlightPhase flight_phase() const { return phase_.phase(); }
  /// @brief No feature track reached an update for health_starvation_s (health_monitor.h).
  bool starving() const { return health_.starving(); }
  const std::string& status_message() const { return status_message_; }
  const FilterState& state() const { return state_; }
  const EstimatorCounters& counters() const { return counters_; }
  const EstimatorConfig& config() const { return config_; }

 private:
  struct ImuInput {
    TimeNs t;
    Eigen::Vector3d gyro, accel, T_m;
    bool thrust_held;
  };
  void drain(bool force);
  void process_imu(const ImuInput& in);
  void integrate_to(const ImuInput& a, const ImuInput& b, TimeNs t_end, double noise_scale,
                    double thrust_scale);
  /// @brief One camera frame at f.t_ns (IMU clock); @p stamp is its camera stamp (timings),
  /// @p w_I the body rate at f.t_ns for the clone's time-offset Jacobian (rate_for_clone).
  void process_frame(const FeatureFrame& f, TimeNs stamp, const Eigen::Vector3d& w_I);
  /// @brief IMU-clock time of a camera stamp: t_cam + t_d (the estimate with the time-offset
  /// state, else cam0's calibrated timeshift_cam_imu).
  TimeNs imu_clock(TimeNs t_cam) const;
  /// @brief t_d in use [s]: the estimate with the time-offset state, else cam0's calibrated one.
  double time_offset_s() const;
  /// @brief How far behind the newest stamp IMU samples wait for frames (negative t_d) and,
  /// while t_d is estimated, for the gyro samples after a frame (rate_for_clone).
  TimeNs frame_hold_ns() const;
  /// @brief The body rate for the time-offset clone Jacobian at @p t (IMU clock): the gyro fitted
  /// over the longest window up to +-kTdRateHalfWindowNs whose residual is noise
  /// (fit_rate_adaptive, rate_fit.h: shorter near impacts), its bias left in (a constant is the
  /// same for every clone and tells t_d nothing, while the bias estimate, corrected by the same
  /// updates in the first seconds, put update-correlated steps into the rate: -10 ms runs lagged
  /// 18 ms at 10 s);
  /// @p fallback (the interpolated sample) without enough samples or without the t_d state.
  Eigen::Vector3d rate_for_clone(TimeNs t, const Eigen::Vector3d& fallback) const;
  void zero_velocity_if_still(const msckf::ClonePose& oldest, const msckf::ClonePose& newest, double sigma_mps,
                              bool landed);
  void check_divergence(bool full);
  void check_health(TimeNs t, int used, int rejected_chi2, int untriangulated);  ///< health_monitor.h, per frame
  void emit(TimeNs t);
  bool smoother_frame_start();  ///< take a force clone at this frame if one is due
  /// Record the new clone's causal value (@p cloned), release the clones past the lag (all with
  /// @p all) and emit the smoothed estimates they anchor.
  void smoother_frame_end(bool cloned, bool all = false);
  void accel_step(const ImuInput& in);
  void record_rejected(TimeNs t);
  void record_downweighted(TimeNs t);
  void record_past_gate(TimeNs t);  ///< rejected or down-weighted, by accel_gate_downweight
  void update_flight_phase(TimeNs t);
  ImuInput interpolate(const ImuInput& a, const ImuInput& b, TimeNs t) const;

  EstimatorConfig config_;
  FilterState state_;
  StaticInitializer initializer_;
  std::unique_ptr<DynamicInitializer> dynamic_init_;  ///< init_mode auto (stereo or mono)
  /// @brief While waiting (auto / static): offer the sample and the frames up to it to the
  /// initializers; on success initialize and process the rest as usual (estimator_init.cpp).
  void init_from_sensors(const ImuInput& in);
  void record_init(TimeNs t, const char* how);
  ThrustBuffer thrust_;
  void add_noise_fit(const AccelInnovation& info);
  double nominal_accel_var() const;
  /// @brief process_imu once initialized: frames up to the sample, propagation, updates.
  void process_imu_initialized(const ImuInput& in);
  TimeNs thrust_delay_ns_ = 0;  ///< EstimatorParams::thrust_delay_s
  bool tilted_thrust_ = false;  ///< VehicleParams::thrust_axis_I is not z
  std::unique_ptr<msckf::FeatureDatabase> features_;
  std::unique_ptr<VisualUpdater> visual_;  ///< the MSCKF update with its options (built once)
  std::deque<ImuSample> imu_queue_;
  std::deque<GyroSample> gyro_history_;  ///< processed samples, the last kTdRateHalfWindowNs (with t_d)
  std::deque<FeatureFrame> frame_queue_;
  std::optional<ImuInput> last_input_;
  /// Recent ground truth while waiting for init_mode groundtruth (the last second), so the
  /// initial state is interpolated to the first IMU sample's own time.
  std::deque<GroundTruthSample> init_gt_;
  /// @brief Ground truth interpolated to t (nearest row within 20 ms without a bracket).
  std::optional<GroundTruthSample> groundtruth_at(TimeNs t) const;
  std::optional<Eigen::Vector3d> last_force_W_;
  TimeNs stream_time_ = INT64_MIN;
  FilterStatus status_ = FilterStatus::kWaitingForInit;
  std::string status_message_ = "waiting for initialization";
  EstimatorCounters counters_;
  FrameTimings pending_timings_;
  ForceJumpDetector jumps_;
  FlightPhaseClassifier phase_;
  TimeNs phase_time_ = 0;  ///< time of the last flight-phase update
  ParallaxWindow parallax_;  ///< cam0 frames of the clone window (zero-velocity test)
  HealthMonitor health_;
  AccelNoiseAdapter accel_noise_;  ///< vibration-aware accelerometer noise (accel_noise.h)
  std::function<void(const EstimateOutput&)> on_estimate_;
  std::function<void(const FrameTimings&)> on_frame_;
  std::unique_ptr<FixedLagOutput> lagged_;  ///< smoothed outputs (smoother_lag_s > 0)
  std::function<void(const EstimateOutput&)> on_smoothed_;
  std::function<void(const std::vector<TimedPose>&)> on_init_window_;
};

}  // namespace vid
