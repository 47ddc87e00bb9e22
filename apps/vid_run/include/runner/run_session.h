#pragma once
/// @file run_session.h
/// @brief Push-style estimator session: the wiring of vid_run (KLT frontend or feat0
/// undistortion -> estimator pipeline -> docs/formats.md §2 outputs, timings, counters, metrics) fed one
/// measurement at a time. vid_run drives it from a dataset reader; vid_live from LCM.

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "io/dataset_reader.h"
#include "runner/run_config.h"
#include "runner/run_metrics.h"
#include "runner/run_outputs.h"
#include "runner/run_summary.h"
#include "runner/runner.h"
#include "vio_core/pipeline.h"

namespace vid {
class KltTracker;
class CameraModel;
}  // namespace vid

namespace vid::runner {

/// @brief What a session needs to know before the first measurement.
struct SessionOptions {
  std::optional<std::filesystem::path> out_dir;  ///< nullopt: no output files
  std::optional<std::filesystem::path> config;   ///< preset folder or its estimator.yaml
  std::optional<PropagationMode> mode;           ///< nullopt: preset `mode:`, else auto
  std::optional<InitMode> init;
  FeatureSource features = FeatureSource::kImages;  ///< kImages or kFeat0 (not kAuto)
  bool has_rotor = false;   ///< rotor speeds will be pushed
  bool has_thrust = false;  ///< thrust will be pushed
  std::string context;      ///< names the input in error messages (dataset path, LCM URL)
};

/// @brief One estimator run, fed push-style. Not thread-safe: one thread pushes.
class RunSession {
 public:
  /// @throws std::runtime_error / io::ConfigError when the configuration cannot run
  RunSession(const SessionOptions& options, const io::DatasetCalibration& calibration);
  ~RunSession();
  RunSession(const RunSession&) = delete;
  RunSession& operator=(const RunSession&) = delete;

  /// @brief Feed the next measurement in time order. ImageFrame paths are decoded here (an
  /// unreadable or wrongly sized image skips its frame, counted); ground truth is kept for the
  /// metrics and passed to the pipeline (ground-truth initialization).
  void push(const Measurement& m);
  /// @brief Feed a camera frame whose images were decoded elsewhere (a decode-ahead thread):
  /// @p images are (cam_id, decode_gray8 image) of the frame's cam 0 / cam 1 images in the
  /// frame's order; checked, counted and tracked exactly as push() does with the paths.
  /// @param decode_ms, decode_cpu_ms  wall / CPU time the decoding took (for summary.json)
  void push_decoded(const ImageFrame& frame, const std::vector<std::pair<int, cv::Mat>>& images, double decode_ms,
                    double decode_cpu_ms);
  /// @brief Account decoding CPU time of frames that were decoded ahead but never pushed (the
  /// run stopped first), so that the CPU time "excluding decoding" stays free of it.
  void add_unused_decode_cpu_ms(double ms);
  /// @brief Feed one camera frame as decoded 8-bit images (right empty for mono).
  void push_images(TimeNs t_ns, const cv::Mat& left, const cv::Mat& right);
  /// @brief End of stream: process everything still queued.
  void finish();
  /// @brief Replace the estimator (and tracker) by fresh ones after divergence; outputs,
  /// counters and metrics continue.
  void restart();

  /// @brief Called with every estimate, after it was written to the outputs.
  void set_estimate_listener(std::function<void(const EstimateOutput&)> cb) { on_estimate_ = std::move(cb); }
  /// @brief Called when the pipeline has processed a camera frame (after timing.csv got its row).
  void set_frame_listener(std::function<void(const FrameTimings&)> cb) { on_frame_ = std::move(cb); }

  /// @brief Status of the current estimator.
  FilterStatus status() const;
  /// @brief The current estimator's status message.
  const std::string& status_message() const;
  /// @brief The resolved configuration (mode and init decided).
  const RunConfig& config() const { return cfg_; }
  /// @brief True in dynamics mode (force estimated).
  bool dynamics() const { return cfg_.estimator.mode == PropagationMode::kDynamics; }
  /// @brief Where the mode came from ("flag --mode", the preset file, "auto (...)").
  const std::string& mode_source() const { return mode_source_; }
  /// @brief restart() calls so far.
  int restarts() const { return restarts_; }
  /// @brief Camera frames pushed (also those skipped for a bad image).
  long camera_frames() const { return frames_; }
  /// @brief feat0 frames pushed.
  long feature_frames() const { return feature_frames_; }
  /// @brief Estimates emitted so far.
  long estimates() const { return estimates_; }
  /// @brief Camera ids the frontend tracks (images of other cameras are ignored).
  int tracked_cameras() const;

  /// @brief summary.json fields of the run so far: mode, init, features, status, counts,
  /// timing, cpu, config, and ATE / force RMSE when ground truth was pushed. The caller adds
  /// its own fields (dataset, data duration, wall time) and writes it.
  nlohmann::json summary() const;
  /// @brief Close the output files (also done by the destructor).
  void close_outputs();

 private:
  void build_estimator();
  void on_estimate(const EstimateOutput& e);
  void on_frame(const FrameTimings& ft);
  void track(TimeNs t_ns, const cv::Mat& left, cv::Mat right);
  void warn_image(const std::string& msg);

  SessionOptions opt_;
  io::DatasetCalibration calib_;
  RunConfig cfg_;
  std::string mode_source_;
  std::unique_ptr<Pipeline> pipeline_;
  std::unique_ptr<KltTracker> tracker_;
  std::vector<std::unique_ptr<CameraModel>> models_;
  std::optional<RunOutputs> outputs_;
  StageTimes stage_times_;
  std::map<TimeNs, double> tracking_ms_;
  Vec3Series est_p_, est_f_W_, est_f_I_, gt_p_, gt_f_W_;
  std::vector<Eigen::Matrix3d> gt_R_WI_;  ///< at gt_p_.t_ns, for the body-frame force figure
  std::vector<TimeNs> mass_t_;
  std::vector<double> mass_kg_;
  PipelineCounters past_counters_;  ///< counters of estimators replaced by restart()
  long estimates_ = 0, frames_ = 0, feature_frames_ = 0, images_unreadable_ = 0, images_wrong_size_ = 0;
  int restarts_ = 0;
  int image_warnings_ = 0;
  std::vector<double> decode_ms_, tracking_cpu_ms_;
  double decode_cpu_ms_ = 0.0;
  double cpu_start_s_ = 0.0;
  std::function<void(const EstimateOutput&)> on_estimate_;
  std::function<void(const FrameTimings&)> on_frame_;
};

}  // namespace vid::runner
