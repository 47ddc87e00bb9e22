#pragma once
/// @file system.h
/// @brief The estimator system: (KLT frontend on images | feat0 undistortion) -> the
/// estimator -> docs/formats.md §2 outputs, timings, counters and metrics, fed push-style one
/// measurement at a time. vid_run drives it from a dataset reader, vid_live from LCM, the
/// accuracy tests from simulator folders. The data flow reads top to bottom in system.cpp.

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "vid_system/config.h"
#include "vid_system/force_check.h"
#include "vid_system/frame_faults.h"
#include "vid_system/metrics.h"
#include "vid_system/outputs.h"
#include "vid_system/summary.h"
#include "vio_core/estimator.h"

namespace vid {
class CameraModel;
}  // namespace vid

namespace vid::system {

class FrontendStage;

/// @brief One camera frame as decoded 8-bit mono images (right empty for mono).
struct StereoFrame {
  TimeNs t_ns = 0;
  cv::Mat left;
  cv::Mat right;
};

/// @brief One estimator run, fed push-style. Not thread-safe: one thread pushes. Observers are
/// called on the pushing thread, inside push() / finish().
class System {
 public:
  /// @throws std::runtime_error when the parameters cannot run (no camera)
  explicit System(SystemParams params);
  ~System();
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  // --- Input, in time order -------------------------------------------------------------------
  void push(const ImuSample& s);
  void push(const RotorSample& s);
  void push(const ThrustSample& s);
  /// @brief A camera frame by image paths, decoded here: an unreadable or wrongly sized image
  /// skips its frame (counted in summary.json). 16-bit images use the frontend's
  /// image_bit_depth, or with 0 (auto) the depth found from each camera's first image, kept
  /// for the run (programs that know the whole stream find it from samples and push decoded
  /// frames: system::camera_bit_depths).
  void push(const ImageFrame& frame);
  /// @brief A camera frame as decoded images; checked and counted as push(ImageFrame).
  void push(const StereoFrame& frame);
  /// @brief Feature observations (feat0); undistorted here when they lack normalized coordinates.
  void push(const FeatureFrame& frame);
  /// @brief Ground truth: kept for the metrics and passed on (ground-truth initialization).
  void push(const GroundTruthSample& s);
  void push(const ForceSample& s);
  void push(const MassSample& s);
  /// @brief Any measurement (dispatches to the typed push).
  void push(const Measurement& m);
  /// @brief A camera frame whose images were decoded elsewhere (a decode-ahead thread):
  /// @p images are (cam_id, decode_gray8 image) of the frame's cam 0 / cam 1 images in the
  /// frame's order; checked, counted and tracked exactly as push(ImageFrame) does.
  /// @param decode_ms, decode_cpu_ms  wall / CPU time the decoding took (for summary.json)
  void push_decoded(const ImageFrame& frame, const std::vector<std::pair<int, cv::Mat>>& images, double decode_ms,
                    double decode_cpu_ms);
  /// @brief Account decoding CPU time of frames that were decoded ahead but never pushed (the
  /// run stopped first), so that the CPU time "excluding decoding" stays free of it.
  void add_unused_decode_cpu_ms(double ms);
  /// @brief Start the filter at @p x with covariance @p P_imu instead of its own initializer.
  void initialize(TimeNs t_ns, const ImuState& x, const Eigen::MatrixXd& P_imu);
  /// @brief End of stream: process everything still queued.
  void finish();
  /// @brief Replace the estimator (and tracker) by fresh ones after divergence; outputs,
  /// counters and metrics continue. The new one initializes from the data, as init_mode `auto`
  /// where the config says `static` (docs/notes/recovery.md).
  void restart();

  // --- Observers ------------------------------------------------------------------------------
  /// @brief Every estimate (state, covariance blocks, force), after it was written to the outputs.
  void on_estimate(std::function<void(const EstimateOutput&)> cb) { on_estimate_ = std::move(cb); }
  /// @brief Every smoothed estimate (estimator smoother_lag_s > 0; Estimator::set_smoothed_callback),
  /// after force_smoothed.csv / trajectory_smoothed_tum.txt got its row.
  void on_smoothed(std::function<void(const EstimateOutput&)> cb) { on_smoothed_ = std::move(cb); }
  /// @brief Every camera frame the estimator processed, after timing.csv got its row.
  void on_frame(std::function<void(const FrameTimings&)> cb) { on_frame_ = std::move(cb); }
  /// @brief Every change of the filter status (initialized, diverged, ...), with its message.
  void on_status(std::function<void(FilterStatus, const std::string&)> cb) { on_status_ = std::move(cb); }

  // --- State and results ----------------------------------------------------------------------
  FilterStatus status() const;
  /// @brief No feature track reached an update for health_starvation_s (vio_core/health_monitor.h).
  bool starving() const;
  const std::string& status_message() const;
  /// @brief Landed / airborne now (vio_core/flight_phase.h; unknown in imu mode).
  FlightPhase flight_phase() const;
  /// @brief Counters of every estimator of the run (also those replaced by restart()).
  EstimatorCounters counters() const;
  /// @brief The parameters (mode and init decided).
  const SystemParams& params() const { return p_; }
  const SystemConfig& config() const { return p_.config; }
  /// @brief True in dynamics mode (force estimated).
  bool dynamics() const { return p_.config.estimator.mode == PropagationMode::kDynamics; }
  /// @brief True with fixed-lag smoothing on (dynamics mode, estimator smoother_lag_s > 0).
  bool smoothing() const { return dynamics() && p_.config.estimator.smoother_lag_s > 0.0; }
  int restarts() const { return restarts_; }
  /// @brief Camera frames pushed (also those skipped for a bad image).
  long camera_frames() const { return frames_; }
  long feature_frames() const { return feature_frames_; }
  long estimates() const { return estimates_; }
  /// @brief Camera ids the frontend tracks (0 with feat0 input; images of other cameras are ignored).
  int tracked_cameras() const;

  /// @brief summary.json fields of the run so far: mode, init, features, status, counts,
  /// timing, cpu, config, and ATE / force RMSE when ground truth was pushed. The caller adds
  /// its own fields (input, data duration, wall time) and writes it (write_summary).
  nlohmann::json summary() const;
  /// @brief Close the output files (also done by the destructor); sums up the skipped frames
  /// not warned one by one.
  void close_outputs();
  /// @brief Camera frames skipped for bad images; set_strict(true) makes them errors.
  FrameFaults& frame_faults() { return faults_; }

 private:
  void build_estimator();
  void to_estimator(Measurement m);
  void report_status();
  void track(TimeNs t_ns, const cv::Mat& left, const cv::Mat& right);
  void estimate_out(const EstimateOutput& e);
  void init_window_out(const std::vector<TimedPose>& poses);
  void start_piece(TimeNs t_ns);
  void smoothed_out(const EstimateOutput& e);
  /// ATE and force RMSE of one estimate series into summary @p s, keys suffixed @p sfx.
  void score(nlohmann::json& s, const Vec3Series& est_p, const Vec3Series& est_f_W, const Vec3Series& est_f_I,
             const std::string& sfx) const;
  void frame_out(const FrameTimings& ft);

  SystemParams p_;
  std::unique_ptr<Estimator> estimator_;
  std::unique_ptr<FrontendStage> frontend_;
  std::array<int, 2> image_bits_{0, 0};  ///< per camera, for push(ImageFrame); 0 until known
  std::vector<std::unique_ptr<CameraModel>> models_;  ///< feat0 undistortion
  std::optional<RunOutputs> outputs_;
  std::optional<FlushedFile> tracks_;  ///< tracks.csv (SystemParams::write_tracks)
  std::optional<SmoothedOutputs> smoothed_outputs_;  ///< with smoother_lag_s > 0
  FilterStatus last_status_ = FilterStatus::kWaitingForInit;
  StageTimes stage_times_;
  std::map<TimeNs, double> tracking_ms_;
  Vec3Series est_p_, est_f_W_, est_f_I_, gt_p_, gt_f_W_;
  Vec3Series est_p_smoothed_, est_f_W_smoothed_, est_f_I_smoothed_;
  ForceMagnitude force_mag_;  ///< mean |F_ext| of the run (summary force_check, the 2 g warning)
  std::vector<Eigen::Matrix3d> gt_R_WI_;  ///< at gt_p_.t_ns, for the body-frame force figure
  std::vector<TimeNs> mass_t_;
  std::vector<double> mass_kg_;
  EstimatorCounters past_counters_;  ///< counters of estimators replaced by restart()
  long estimates_ = 0, frames_ = 0, feature_frames_ = 0;
  FrameFaults faults_;
  int restarts_ = 0;
  bool mark_next_estimate_ = false, mark_next_smoothed_ = false;  ///< after a restart (outputs' marker)
  TimeNs last_estimate_t_ = INT64_MIN;
  std::vector<TimeNs> piece_starts_;  ///< first time of each piece after a re-initialization
  bool was_starving_ = false;    ///< the estimator's starvation flag at the previous frame
  int starvation_warnings_ = 0;  ///< episodes warned about (the first 10)
  StageStats decode_ms_, tracking_cpu_ms_;
  double decode_cpu_ms_ = 0.0;
  double cpu_start_s_ = 0.0;
  std::function<void(const EstimateOutput&)> on_estimate_;
  std::function<void(const FrameTimings&)> on_frame_;
  std::function<void(const EstimateOutput&)> on_smoothed_;
  std::function<void(FilterStatus, const std::string&)> on_status_;
};

}  // namespace vid::system
