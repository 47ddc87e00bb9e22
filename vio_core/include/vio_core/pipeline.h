#pragma once
/// @file pipeline.h
/// @brief The estimator pipeline: consumes time-ordered measurements (IMU, rotor speeds or
/// thrust, feature frames; ground truth only with InitMode::kGroundTruth), runs
/// initialization, propagation, accelerometer updates, MSCKF visual updates and clone
/// marginalization, and emits IMU-rate estimates plus per-frame stage timings.
/// Single-threaded and deterministic (timings aside).
///
/// Stream handling (documented behaviour):
/// * dynamics mode: an IMU sample is processed once thrust is known at its time (a rotor or
///   thrust sample at or after it), or once the stream has moved rotor_gap_s past it; then
///   the last thrust is held and the thrust noise is inflated by rotor_gap_noise_scale
///   (counted in PipelineCounters::rotor_gap_samples).
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
#include "vio_core/dynamic_initializer.h"
#include "vio_core/estimator_params.h"
#include "vio_core/flight_phase.h"
#include "vio_core/accel_noise.h"
#include "vio_core/health_monitor.h"
#include "vio_core/force_jump.h"
#include "vio_core/initializer.h"
#include "vio_core/rate_fit.h"
#include "vio_core/state.h"
#include "vio_core/thrust_buffer.h"
#include "vio_core/zero_velocity.h"

namespace vid {
class FixedLagOutput;
namespace msckf {
class FeatureDatabase;
struct ClonePose;
}

/// @brief Filter health.
enum class FilterStatus { kWaitingForInit, kOk, kDiverged };
/// @brief "waiting_for_init" / "ok" / "diverged".
std::string to_string(FilterStatus s);

/// @brief Everything the pipeline needs besides the measurements.
struct PipelineConfig {
  EstimatorParams params;
  VehicleParams vehicle;              ///< mass and rotor thrust coefficients (dynamics mode)
  std::vector<CameraCalib> cameras;   ///< by cam_id (T_IC, intrinsics for the pixel noise)
};

/// @brief One IMU-rate estimate.
struct EstimateOutput {
  TimeNs t_ns = 0;
  ImuState x;
  Eigen::VectorXd sigma;  ///< 1-sigma of the IMU error block (15 or 18)
  Eigen::Matrix3d cov_theta, cov_p;  ///< for consistency checks
  /// External force in I and in W [m/s^2] and their covariances (zero in imu mode); the one
  /// in the state's force frame is the state's block, the other is mapped through R_WI with
  /// the orientation uncertainty included.
  Eigen::Vector3d F_ext_I, F_ext_W;
  Eigen::Matrix3d cov_F_I, cov_F_W;
  double sigma_thrust_scale = 0.0;  ///< 1-sigma of x.thrust_scale (0 when it is not estimated)
  double time_offset_s = 0.0;        ///< camera-IMU time offset t_d in use (t_imu = t_cam + t_d)
  double sigma_time_offset_s = 0.0;  ///< its 1-sigma (0 when it is not estimated)
  FilterStatus status = FilterStatus::kOk;
  FlightPhase phase = FlightPhase::kUnknown;  ///< landed / airborne (dynamics mode; flight_phase.h)
};

/// @brief Stage times of one camera frame [ms] (propagation and accelerometer updates are
/// accumulated since the previous frame).
struct FrameTimings {
  TimeNs t_ns = 0;  ///< the frame's camera stamp
  double propagation_ms = 0.0;
  double accel_update_ms = 0.0;
  double msckf_update_ms = 0.0;
  double marginalization_ms = 0.0;
  int features_used = 0;
  int features_rejected = 0;
  int features_rejected_chi2 = 0;  ///< of features_rejected, by the chi2 gate (health_monitor.h)
  int clones = 0;
};

/// @brief A time span [first, last] of consecutive events.
struct TimeSpan {
  TimeNs first_ns = 0;
  TimeNs last_ns = 0;
};

/// @brief A force step found by the detector (force_jump.h).
struct ForceJumpRecord {
  TimeNs t_ns = 0;        ///< newest sample of the window
  int window = 0;         ///< samples it was estimated from
  double size_mps2 = 0.0; ///< |mean innovation| of the window
};

/// @brief A change of flight phase (flight_phase.h): lift-off or touchdown.
struct FlightPhaseRecord {
  TimeNs t_ns = 0;
  FlightPhase to = FlightPhase::kUnknown;  ///< kAirborne: lift-off, kLanded: touchdown
};

/// @brief An initialization (docs/notes/initialization.md): how and when.
struct InitRecord {
  TimeNs t_ns = 0;
  std::string how;  ///< "still" (still/hover window), "in_flight" (stereo window), "groundtruth"
};

/// @brief Event counters.
struct PipelineCounters {
  std::vector<InitRecord> inits;  ///< every (re-)initialization
  long imu_samples = 0;
  long accel_updates = 0;     ///< accelerometer samples applied one by one at full weight
  /// Samples the chi2 gate held back and no force jump used: final once a sample has left
  /// the detector's window (force_jump_window samples later) or at finish().
  long accel_rejected = 0;
  long accel_used_in_jumps = 0;  ///< past the gate, then used at full weight in a jump's estimate
  /// Past the gate, applied down-weighted (accel_gate_downweight) and used by no force jump;
  /// final like accel_rejected.
  long accel_downweighted = 0;
  std::vector<TimeSpan> accel_downweighted_spans;  ///< down-weighted samples less than 50 ms apart joined
  long force_jumps = 0;
  std::vector<TimeSpan> accel_rejected_spans;  ///< rejected samples less than 50 ms apart joined
  std::vector<ForceJumpRecord> force_jump_events;
  long rotor_gap_samples = 0;  ///< IMU samples propagated with held thrust
  long imu_gaps = 0;
  long frames = 0;
  long frames_skipped = 0;      ///< frames before init or behind the filter time
  long visual_updates = 0;
  long features_used = 0;
  long features_rejected = 0;   ///< chi2 + triangulation
  long features_rejected_chi2 = 0;
  long features_too_short = 0;
  long zero_velocity_updates = 0;  ///< frames whose window showed no parallax (one camera, or landed)
  long zero_velocity_updates_landed = 0;  ///< of those, while landed (any camera count)
  long observations_without_norm = 0;
  double landed_s = 0.0;    ///< time classified landed (flight_phase.h) [s]
  double airborne_s = 0.0;  ///< time classified airborne [s]
  std::vector<FlightPhaseRecord> flight_phase_events;  ///< lift-offs and touchdowns
  long starvation_episodes = 0;  ///< health_monitor.h: no feature used for health_starvation_s
  double starved_s = 0.0;        ///< total time starving [s]
  /// Largest fraction of tested features that failed the chi2 gate over one health window
  /// (windows with at least health_min_tested_features); the out-of-band test's margin.
  double max_chi2_rejected_fraction = 0.0;
  /// Noise fit (docs/notes/real-sensors.md, "Noise that does not fit the data"): per body axis, the sum of the
  /// accelerometer innovations' r_i^2 / S_ii (mean 1 when the noise model fits) ...
  Eigen::Vector3d accel_nis_sum = Eigen::Vector3d::Zero();
  long accel_nis_count = 0;
  /// ... and the visual features' chi2 over their degrees of freedom (features used).
  double visual_chi2_sum = 0.0;
  long visual_dof_sum = 0;
  long accel_noise_inflated = 0;  ///< accelerometer samples with the vibration-aware noise above nominal
};

/// @brief The estimator.
class Pipeline {
 public:
  explicit Pipeline(PipelineConfig config);
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

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
  const PipelineCounters& counters() const { return counters_; }
  const PipelineConfig& config() const { return config_; }

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

  PipelineConfig config_;
  FilterState state_;
  StaticInitializer initializer_;
  std::unique_ptr<DynamicInitializer> dynamic_init_;  ///< init_mode auto with a stereo pair
  /// @brief While waiting (auto / static): offer the sample and the frames up to it to the
  /// initializers; on success initialize and process the rest as usual (pipeline_init.cpp).
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
  PipelineCounters counters_;
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
